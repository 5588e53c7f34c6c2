//! Every model family beside Lafortune (which has tests of its own) against the same checks:
//! the analytic Jacobian against central differences in the optimiser's coordinates, every
//! kernel against the libm reference, reciprocity, and parameters that round-trip through
//! the layout and the JSON form.

use brdf_model::{
    DataSet, Evaluator, ExponentCoord, FamilyRef, Kernel, Layout, LobeKind, Params, family,
    family_names, uniform_hemisphere,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// The registered families other than Lafortune.
fn families() -> Vec<FamilyRef> {
    family_names()
        .into_iter()
        .filter(|&n| n != "lafortune")
        .map(|n| family(n).unwrap())
        .collect()
}

/// Layouts of a family: each kind it has alone, two lobes of mixed kinds, both coordinates.
fn layouts(f: &FamilyRef) -> Vec<Layout> {
    let kinds = f.kinds();
    let mut shapes: Vec<Vec<LobeKind>> = kinds.iter().map(|&k| vec![k]).collect();
    shapes.push(vec![kinds[0], *kinds.last().unwrap()]);
    let mut out = Vec::new();
    for coord in [ExponentCoord::Log1p, ExponentCoord::Raw] {
        for s in &shapes {
            let b = Layout::builder_for(f, s).unwrap().exponent_coord(coord);
            out.push(b.build().unwrap());
        }
    }
    out
}

fn directions(count: usize, seed: u64) -> DataSet {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut d = DataSet::new();
    for _ in 0..count {
        let u = uniform_hemisphere(&mut rng);
        let v = uniform_hemisphere(&mut rng);
        d.push(u, v, rng.random_range(0.0..2.0));
    }
    d
}

/// A point inside the box, away from its edges (central differences need room).
fn inner_point(layout: &Layout, rng: &mut Pcg64Mcg) -> Vec<f64> {
    layout
        .lower()
        .iter()
        .zip(layout.upper())
        .map(|(&lo, &hi)| {
            let w = hi - lo;
            lo + w * rng.random_range(0.1..0.9)
        })
        .collect()
}

#[test]
fn jacobians_match_central_differences() {
    for f in families() {
        for layout in layouts(&f) {
            let data = directions(200, 1);
            let samples = layout.prepare(&data);
            let mut ev = Evaluator::with_kernel(&layout, Kernel::Scalar).unwrap();
            let (m, p) = (data.len(), layout.dim());
            let mut rng = Pcg64Mcg::seed_from_u64(7);
            for trial in 0..20 {
                let x = inner_point(&layout, &mut rng);
                let mut jac = vec![0.0; m * p];
                assert!(ev.jacobian(&x, &samples, &mut jac), "{} {x:?}", f.name());
                let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
                for j in 0..p {
                    let h = 1e-6 * (1.0 + x[j].abs());
                    let mut xp = x.clone();
                    xp[j] += h;
                    let mut xm = x.clone();
                    xm[j] -= h;
                    assert!(ev.residuals(&xp, &samples, &mut rp));
                    assert!(ev.residuals(&xm, &samples, &mut rm));
                    let col = &jac[j * m..(j + 1) * m];
                    let scale = col.iter().fold(1e-12f64, |s, v| s.max(v.abs()));
                    for i in 0..m {
                        let fd = (rp[i] - rm[i]) / (2.0 * h);
                        // The difference's own rounding: each residual (of size 1, the data
                        // value) is off by a few eps, which a sharp lobe's tiny column shows.
                        let noise = 4.0 * f64::EPSILON * (rp[i].abs() + rm[i].abs()) / (2.0 * h);
                        assert!(
                            (fd - col[i]).abs() <= 1e-5 * scale + noise,
                            "{} trial {trial} {}: sample {i} analytic {} numeric {fd}",
                            f.name(),
                            layout.free_names()[j],
                            col[i]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn every_kernel_agrees_with_the_libm_reference() {
    for f in families() {
        for layout in layouts(&f) {
            let data = directions(333, 2);
            let samples = layout.prepare(&data);
            let mut reference = Evaluator::with_kernel(&layout, Kernel::Scalar).unwrap();
            let mut rng = Pcg64Mcg::seed_from_u64(3);
            let (m, p) = (data.len(), layout.dim());
            for _ in 0..20 {
                let x: Vec<f64> = layout
                    .lower()
                    .iter()
                    .zip(layout.upper())
                    .map(|(&lo, &hi)| rng.random_range(lo..=hi))
                    .collect();
                let (mut r0, mut j0) = (vec![0.0; m], vec![0.0; m * p]);
                let ok0 = reference.residuals_and_jacobian(&x, &samples, &mut r0, &mut j0);
                for k in Kernel::available() {
                    let mut ev = Evaluator::with_kernel(&layout, k).unwrap();
                    let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * p]);
                    let ok = ev.residuals_and_jacobian(&x, &samples, &mut r, &mut jac);
                    assert_eq!(ok, ok0, "{} {k}: success differs at {x:?}", f.name());
                    if !ok {
                        continue;
                    }
                    for (a, b) in r.iter().zip(&r0) {
                        assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{} {k}", f.name());
                    }
                    for (ca, cb) in jac.chunks(m).zip(j0.chunks(m)) {
                        let scale = cb.iter().fold(1e-300f64, |s, v| s.max(v.abs()));
                        for (a, b) in ca.iter().zip(cb) {
                            assert!((a - b).abs() <= 1e-11 * scale, "{} {k}", f.name());
                        }
                    }
                    let mut rr = vec![0.0; m];
                    assert!(ev.residuals(&x, &samples, &mut rr));
                    assert_eq!(rr, r, "{} {k}: residuals alone differ", f.name());
                }
            }
        }
    }
}

#[test]
fn models_are_reciprocal_and_round_trip() {
    for f in families() {
        let layout = &layouts(&f)[0];
        let mut rng = Pcg64Mcg::seed_from_u64(11);
        for _ in 0..50 {
            let x = inner_point(layout, &mut rng);
            let p = layout.decode(&x);
            let back = layout.encode(&p);
            for (a, b) in back.iter().zip(&x) {
                assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{}", f.name());
            }
            let json = serde_json::to_string(&p).unwrap();
            let q: Params = serde_json::from_str(&json).unwrap();
            assert_eq!(q, p, "{json}");
            assert!(
                json.contains(&format!("\"family\":\"{}\"", f.name())),
                "{json}"
            );
            for _ in 0..20 {
                let u = uniform_hemisphere(&mut rng);
                let v = uniform_hemisphere(&mut rng);
                let (a, b) = (p.value(u, v), p.value(v, u));
                assert!(a.is_finite() && a >= 0.0, "{} {a}", f.name());
                assert!((a - b).abs() <= 1e-12 * a.abs(), "{}: {a} vs {b}", f.name());
            }
        }
    }
}
