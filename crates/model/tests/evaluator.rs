//! Evaluator tests: analytic Jacobian against central differences, edge cases of the box,
//! agreement with the scalar libm reference, overflow handling.

use brdf_model::{
    BrdfParams, DataSet, Evaluator, ExponentCoord, FamilyRef, Kernel, Layout, Lobe, LobeKind,
    Samples, named_params, synthetic,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// The compiled copies of the fast loops this CPU runs (every kernel but the scalar reference),
/// slowest first.
fn compiled_copies() -> Vec<Kernel> {
    let mut kernels = Kernel::available();
    kernels.retain(|&k| k != Kernel::Scalar);
    kernels.reverse();
    kernels
}

/// The Lafortune family's samples of `data` (what every layout here evaluates).
fn prepare(data: &DataSet) -> Samples {
    FamilyRef::lafortune().prepare(data)
}

fn layouts() -> Vec<Layout> {
    let mut out = Vec::new();
    for coord in [ExponentCoord::Raw, ExponentCoord::Log1p] {
        for kinds in [
            vec![LobeKind::Anisotropic],
            vec![LobeKind::Isotropic],
            vec![LobeKind::Anisotropic, LobeKind::Isotropic],
        ] {
            out.push(
                Layout::builder(&kinds)
                    .exponent_coord(coord)
                    .build()
                    .unwrap(),
            );
        }
        // Fixed parameters: no column for them.
        out.push(
            Layout::builder(&[LobeKind::Anisotropic, LobeKind::Anisotropic])
                .exponent_coord(coord)
                .fix("lobe1.pan", 30.0)
                .unwrap()
                .fix("lobe2.pan", 0.0)
                .unwrap()
                .fix("lobe2.n", 5.0)
                .unwrap()
                .fix("kd", 0.1)
                .unwrap()
                .build()
                .unwrap(),
        );
    }
    out
}

thread_local! {
    static COUNTS: (std::cell::Cell<usize>, std::cell::Cell<usize>) = const {
        (std::cell::Cell::new(0), std::cell::Cell::new(0))
    };
}

/// Central-difference Jacobian check; returns false when the point cannot be evaluated.
fn check_jacobian(layout: &Layout, x: &[f64], data: &Samples, tol: f64) -> bool {
    COUNTS
        .with(|(checked, unsmooth)| check_jacobian_counted(layout, x, data, tol, checked, unsmooth))
}

fn check_jacobian_counted(
    layout: &Layout,
    x: &[f64],
    data: &Samples,
    tol: f64,
    checked: &std::cell::Cell<usize>,
    unsmooth: &std::cell::Cell<usize>,
) -> bool {
    let mut ev = Evaluator::new(layout);
    let (m, p) = (data.len(), layout.dim());
    let mut jac = vec![0.0; m * p];
    let mut r = vec![0.0; m];
    let ok_r = ev.residuals(x, data, &mut r);
    let ok_j = ev.jacobian(x, data, &mut jac);
    assert_eq!(
        ok_r, ok_j,
        "residuals and jacobian disagree on failure at {x:?}"
    );
    assert!(jac.iter().all(|v| !v.is_nan()) || !ok_j);
    // Every compiled copy of the loops gives the same answer (to rounding) and the same
    // success flag.
    let mut other = vec![0.0; m * p];
    for level in compiled_copies() {
        let mut e2 = Evaluator::new(layout);
        e2.set_kernel(level).unwrap();
        assert_eq!(e2.jacobian(x, data, &mut other), ok_j, "{level:?} at {x:?}");
        if ok_j && m > 0 {
            // Relative to the column's scale: FMA and separate rounding differ where a
            // column's terms cancel.
            for (ca, cb) in jac.chunks(m).zip(other.chunks(m)) {
                let scale = ca.iter().fold(1e-300f64, |s, v| s.max(v.abs()));
                for (a, b) in ca.iter().zip(cb) {
                    assert!((a - b).abs() <= 1e-9 * scale, "{level:?}: {a} vs {b}");
                }
            }
        }
    }
    if !ok_r {
        assert_eq!(ev.sum_squares(x, data), f64::INFINITY);
        return false;
    }
    let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
    for j in 0..p {
        let h = 1e-6 * x[j].abs().max(1.0);
        let mut xp = x.to_vec();
        let mut xm = x.to_vec();
        xp[j] += h;
        xm[j] -= h;
        if !(ev.residuals(&xp, data, &mut rp) && ev.residuals(&xm, data, &mut rm)) {
            continue;
        }
        // A second, smaller step: rows where the two estimates disagree are not smooth at
        // this scale (a sample sits on the d = 0 kink with n < 1), so differences say nothing.
        let h2 = h / 4.0;
        let (mut rp2, mut rm2) = (vec![0.0; m], vec![0.0; m]);
        let mut xp2 = x.to_vec();
        let mut xm2 = x.to_vec();
        xp2[j] += h2;
        xm2[j] -= h2;
        if !(ev.residuals(&xp2, data, &mut rp2) && ev.residuals(&xm2, data, &mut rm2)) {
            continue;
        }
        let col = &jac[j * m..(j + 1) * m];
        let scale = col.iter().fold(1e-12f64, |a, v| a.max(v.abs()));
        for i in 0..m {
            let fd = (rp[i] - rm[i]) / (2.0 * h);
            let fd2 = (rp2[i] - rm2[i]) / (2.0 * h2);
            // Rounding of the residuals themselves limits what the difference can resolve.
            let noise = 1e-14 * rp2[i].abs().max(rm2[i].abs()) / h2;
            if (fd - fd2).abs() > tol * scale + noise {
                unsmooth.set(unsmooth.get() + 1);
                continue;
            }
            checked.set(checked.get() + 1);
            assert!(
                (fd2 - col[i]).abs() <= tol * scale + noise,
                "{} row {i}: analytic {} vs central {fd2} (scale {scale}) at {x:?}",
                layout.free_names()[j],
                col[i]
            );
        }
    }
    true
}

#[test]
fn jacobian_matches_central_differences_over_the_box() {
    let mut rng = Pcg64Mcg::seed_from_u64(11);
    let data = prepare(&synthetic(&named_params("cross").unwrap(), 200, 0.05, 5));
    let mut evaluated = 0;
    for layout in layouts() {
        for _ in 0..60 {
            let x: Vec<f64> = (0..layout.dim())
                .map(|j| {
                    let (lo, hi) = (layout.lower()[j], layout.upper()[j]);
                    // Keep exponents moderate half the time so values are not all 0 or inf.
                    let hi = if layout.is_exponent(j) && rng.random_bool(0.5) {
                        lo + (hi - lo) * 0.02
                    } else {
                        hi
                    };
                    rng.random_range(lo..=hi)
                })
                .collect();
            if check_jacobian(&layout, &x, &data, 2e-4) {
                evaluated += 1;
            }
        }
    }
    assert!(evaluated > 200, "only {evaluated} points evaluable");
    let (checked, unsmooth) = COUNTS.with(|(c, u)| (c.get(), u.get()));
    println!("checked {checked} entries, skipped {unsmooth} non-smooth ones");
    assert!(
        unsmooth * 100 < checked,
        "{unsmooth} of {checked} entries not smooth"
    );
}

fn iso_layout(coord: ExponentCoord) -> Layout {
    Layout::builder(&[LobeKind::Isotropic])
        .exponent_coord(coord)
        .build()
        .unwrap()
}

#[test]
fn jacobian_at_edge_cases() {
    let data = prepare(&synthetic(&named_params("tuning").unwrap(), 100, 0.0, 3));
    for coord in [ExponentCoord::Raw, ExponentCoord::Log1p] {
        let l = Layout::builder(&[LobeKind::Anisotropic])
            .exponent_coord(coord)
            .build()
            .unwrap();
        let enc = |kd: f64, lobe: Lobe| {
            l.encode(&BrdfParams {
                kd,
                lobes: vec![lobe],
            })
        };
        let cases = [
            // n = 0 (lobe is 1 where d > 0, 0 elsewhere).
            enc(
                0.2,
                Lobe {
                    cx: -1.0,
                    cy: 0.8,
                    cz: 0.9,
                    n: 0.0,
                    pan_deg: 10.0,
                },
            ),
            // C at its bounds, pan at its bounds.
            enc(
                0.0,
                Lobe {
                    cx: -1.5,
                    cy: -1.5,
                    cz: 1.5,
                    n: 3.0,
                    pan_deg: 90.0,
                },
            ),
            enc(
                1.0,
                Lobe {
                    cx: 1.5,
                    cy: -1.5,
                    cz: -1.5,
                    n: 3.0,
                    pan_deg: -90.0,
                },
            ),
            // d <= 0 everywhere: value 0 and zero lobe derivatives.
            enc(
                0.5,
                Lobe {
                    cx: 0.0,
                    cy: 0.0,
                    cz: -1.0,
                    n: 2.0,
                    pan_deg: 0.0,
                },
            ),
            // Large n with d < 1.
            enc(
                0.1,
                Lobe {
                    cx: -0.9,
                    cy: -0.9,
                    cz: 0.9,
                    n: 10000.0,
                    pan_deg: 0.0,
                },
            ),
            // Small n below 1.
            enc(
                0.1,
                Lobe {
                    cx: -0.5,
                    cy: 0.3,
                    cz: 0.7,
                    n: 0.3,
                    pan_deg: 45.0,
                },
            ),
        ];
        for x in &cases {
            assert!(check_jacobian(&l, x, &data, 2e-4), "not evaluable: {x:?}");
        }
        // d <= 0 everywhere: every lobe column is exactly 0.
        let mut ev = Evaluator::new(&l);
        let mut jac = vec![f64::NAN; data.len() * l.dim()];
        assert!(ev.jacobian(&cases[3], &data, &mut jac));
        assert!(jac[data.len()..].iter().all(|&v| v == 0.0));
        // n = 0: C columns are 0, the n column is ln d where d > 0.
        assert!(ev.jacobian(&cases[0], &data, &mut jac));
        assert!(jac[data.len()..4 * data.len()].iter().all(|&v| v == 0.0));
    }
}

#[test]
fn d_to_zero_from_above_is_finite() {
    // u = v = normal: d = Cz, which we drive to tiny positive values, even subnormal.
    let mut data = DataSet::new();
    data.push([0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 0.0);
    let data = prepare(&data);
    for coord in [ExponentCoord::Raw, ExponentCoord::Log1p] {
        let l = iso_layout(coord);
        let mut ev = Evaluator::new(&l);
        for (level, cz) in compiled_copies()
            .into_iter()
            .flat_map(|lv| [1e-10, 1e-300, 5e-324].map(|c| (lv, c)))
        {
            ev.set_kernel(level).unwrap();
            for n in [0.0, 0.5, 1.0, 2.0, 50.0] {
                let x = l.encode(&BrdfParams {
                    kd: 0.0,
                    lobes: vec![Lobe::isotropic(0.3, cz, n)],
                });
                let mut jac = vec![0.0; 4];
                let mut r = vec![0.0; 1];
                assert!(ev.residuals(&x, &data, &mut r), "cz {cz} n {n}");
                let ok = ev.jacobian(&x, &data, &mut jac);
                assert!(
                    jac.iter().all(|v| !v.is_nan()),
                    "NaN at cz {cz} n {n}: {jac:?}"
                );
                let expect = if n == 0.0 { 1.0 } else { cz.powf(n) };
                assert!(
                    (r[0] - expect).abs() <= 1e-12 * expect.max(1e-300),
                    "{r:?} {expect}"
                );
                // The Cz column is n d^(n-1) (cz enters d with weight uz vz = 1).
                let dcz = if n == 0.0 { 0.0 } else { n * cz.powf(n - 1.0) };
                // The vector kernels flush d^n below 2^-1010 to 0 (no subnormal arithmetic),
                // and with it n d^n / d: where d itself is that small (the lobe's edge), the
                // Cz column may be 0.
                let flushed = n != 0.0 && expect < 1e-303;
                if ok {
                    assert!(
                        (jac[2] - dcz).abs() <= 1e-10 * dcz.abs() + 1e-290
                            || (flushed && jac[2] == 0.0),
                        "{jac:?} {dcz}"
                    );
                } else {
                    assert!(!dcz.is_finite() || dcz > 1e300);
                }
            }
        }
    }
}

#[test]
fn overflow_gives_inf_not_nan() {
    let mut data = DataSet::new();
    data.push([0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 0.3);
    data.push([0.6, 0.0, 0.8], [-0.6, 0.0, 0.8], 0.3);
    let data = prepare(&data);
    for coord in [ExponentCoord::Raw, ExponentCoord::Log1p] {
        let l = Layout::builder(&[LobeKind::Anisotropic])
            .exponent_coord(coord)
            .build()
            .unwrap();
        let x = l.encode(&BrdfParams {
            kd: 0.0,
            lobes: vec![Lobe {
                cx: 1.5,
                cy: 1.5,
                cz: 1.5,
                n: 10000.0,
                pan_deg: 0.0,
            }],
        });
        let mut ev = Evaluator::new(&l);
        let mut r = vec![0.0; 2];
        let mut jac = vec![0.0; 2 * l.dim()];
        assert!(!ev.residuals(&x, &data, &mut r));
        assert!(r.iter().all(|v| !v.is_nan()));
        assert!(!ev.jacobian(&x, &data, &mut jac));
        assert_eq!(ev.sum_squares(&x, &data), f64::INFINITY);
        assert_eq!(ev.rmse(&x, &data), f64::INFINITY);
        for level in compiled_copies() {
            ev.set_kernel(level).unwrap();
            assert!(!ev.residuals(&x, &data, &mut r));
            assert!(r.iter().all(|v| !v.is_nan()));
            assert!(!ev.jacobian(&x, &data, &mut jac));
            assert_eq!(ev.sum_squares(&x, &data), f64::INFINITY);
        }
    }
}

#[test]
fn evaluator_agrees_with_scalar_libm_reference() {
    let mut rng = Pcg64Mcg::seed_from_u64(99);
    let data = synthetic(&named_params("tuning").unwrap(), 2000, 0.0, 17);
    let l = Layout::builder(&[LobeKind::Anisotropic, LobeKind::Isotropic])
        .build()
        .unwrap();
    let samples = l.prepare(&data);
    let mut ev = Evaluator::new(&l);
    let mut r = vec![0.0; data.len()];
    let levels = compiled_copies();
    let mut worst = vec![0.0f64; levels.len()];
    let mut compared = 0usize;
    for _ in 0..300 {
        let x: Vec<f64> = (0..l.dim())
            .map(|j| {
                let hi = l.upper()[j] * if l.is_exponent(j) { 0.6 } else { 1.0 };
                rng.random_range(l.lower()[j]..=hi)
            })
            .collect();
        let p = l.decode(&x);
        for (k, &level) in levels.iter().enumerate() {
            ev.set_kernel(level).unwrap();
            if !ev.residuals(&x, &samples, &mut r) {
                continue;
            }
            for (i, ri) in r.iter().enumerate() {
                let reference = p.value(data.u(i), data.v(i));
                let got = ri + data.value(i);
                if reference > 1e-290 {
                    worst[k] = worst[k].max((got - reference).abs() / reference);
                    compared += 1;
                }
            }
        }
    }
    for (level, w) in levels.iter().zip(&worst) {
        println!("max relative error vs libm powf, {level:?} loops: {w:.3e}");
    }
    println!("({compared} values compared)");
    assert!(compared > 100_000);
    assert!(worst.iter().all(|&w| w < 1e-10), "{worst:?}");
}

#[test]
fn simd_and_portable_jacobians_agree() {
    let data = prepare(&synthetic(&named_params("cross").unwrap(), 1000, 0.1, 1));
    let l = Layout::builder(&[LobeKind::Anisotropic, LobeKind::Anisotropic])
        .build()
        .unwrap();
    let x = l.encode(named_params("cross").unwrap());
    let mut ev = Evaluator::new(&l);
    let mut a = vec![0.0; data.len() * l.dim()];
    let mut b = a.clone();
    ev.set_kernel(Kernel::Portable).unwrap();
    assert!(ev.jacobian(&x, &data, &mut b));
    for level in compiled_copies() {
        ev.set_kernel(level).unwrap();
        assert!(ev.jacobian(&x, &data, &mut a));
        for (p, q) in a.iter().zip(&b) {
            assert!((p - q).abs() <= 1e-12 * (1.0 + q.abs()), "{level:?}");
        }
    }
    // The true parameters of a noiseless instance have zero residuals.
    let clean = l.prepare(&synthetic(&named_params("cross").unwrap(), 500, 0.0, 2));
    assert!(ev.rmse(&x, &clean) < 1e-12);
    let noisy = l.prepare(&synthetic(&named_params("cross").unwrap(), 5000, 0.1, 2));
    let e = ev.rmse(&x, &noisy);
    assert!((e - 0.1).abs() < 0.005, "{e}");
    let rows: Vec<u32> = (0..100).collect();
    let mut sub = Samples::empty(l.family().name(), 0);
    noisy.gather_into(&rows, &mut sub);
    assert_eq!(ev.rmse_rows(&x, &noisy, &rows), ev.rmse(&x, &sub));
}

#[test]
fn reciprocity_and_phong() {
    let mut rng = Pcg64Mcg::seed_from_u64(4);
    let cross = named_params("cross").unwrap();
    let phong_c: f64 = 0.9;
    let phong = BrdfParams {
        kd: 0.05,
        lobes: vec![Lobe::isotropic(-phong_c, phong_c, 12.0)],
    };
    for _ in 0..1000 {
        let u = brdf_model::uniform_hemisphere(&mut rng);
        let v = brdf_model::uniform_hemisphere(&mut rng);
        assert_eq!(cross.value(u, v), cross.value(v, u));
        // Phong: kd + (c cos alpha)^n, alpha between v and the mirror direction of u.
        let mirror = [-u[0], -u[1], u[2]];
        let cos_a = mirror[0] * v[0] + mirror[1] * v[1] + mirror[2] * v[2];
        let expect = 0.05 + (phong_c * cos_a).max(0.0).powf(12.0);
        assert!((phong.value(u, v) - expect).abs() < 1e-14);
    }
    // Through the evaluator too: swap u and v in the data set.
    let d = synthetic(&cross, 300, 0.0, 8);
    let mut swapped = DataSet::new();
    for i in 0..d.len() {
        swapped.push(d.v(i), d.u(i), d.value(i));
    }
    let l = Layout::builder(&[LobeKind::Anisotropic, LobeKind::Anisotropic])
        .build()
        .unwrap();
    let mut ev = Evaluator::new(&l);
    assert!(ev.rmse(&l.encode(&cross), &l.prepare(&swapped)) < 1e-12);
}

#[test]
fn length_mismatch_is_a_failed_evaluation() {
    let l = iso_layout(ExponentCoord::Log1p);
    let mut ev = Evaluator::new(&l);
    let d = l.prepare(&synthetic(&named_params("tuning").unwrap(), 10, 0.0, 1));
    let mut r = vec![0.0; 9];
    assert!(!ev.residuals(&[0.1, 0.2, 0.3, 1.0], &d, &mut r));
    let mut r = vec![0.0; 10];
    assert!(!ev.residuals(&[0.1, 0.2], &d, &mut r));
    assert_eq!(
        ev.rmse(&[0.1, 0.2, 0.3, 1.0], &l.prepare(&DataSet::new())),
        0.0
    );
}
