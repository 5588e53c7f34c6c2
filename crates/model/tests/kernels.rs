//! Every evaluation kernel the machine can run against the scalar libm reference
//! ([`Kernel::Scalar`]) over the whole Table 1 box, edges included, and exponents up to the
//! widest bound a spec or `fit --bounds` may set ([`MAX_EXPONENT`]); plus the kernel choice
//! (names, parsing, resolution) and [`Evaluator::sum_squares_below`].

use brdf_model::{
    BrdfParams, DataSet, Evaluator, ExponentCoord, FamilyRef, Kernel, KernelError, Layout, Lobe,
    LobeKind, MAX_EXPONENT, SUM_BLOCK, Samples, uniform_hemisphere,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// ln(f64::MAX): `d^n` overflows when `n ln d` exceeds it.
const LN_MAX: f64 = 709.782_712_893_384;

/// Directions covering the hemisphere, its rim (grazing: `uz = 0` or `vz = 0`), the normal,
/// mirror and retro configurations; `y` uniform in [0, 1].
fn box_data(n: usize, seed: u64) -> DataSet {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut d = DataSet::new();
    let normal = [0.0, 0.0, 1.0];
    d.push(normal, normal, 0.3);
    for k in 0..n {
        let mut u = uniform_hemisphere(&mut rng);
        let mut v = uniform_hemisphere(&mut rng);
        match k % 8 {
            0 => {
                // Grazing incidence: in the surface plane.
                let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                u = [a.cos(), a.sin(), 0.0];
            }
            1 => {
                let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                v = [a.cos(), a.sin(), 0.0];
            }
            2 => v = [-u[0], -u[1], u[2]], // mirror
            3 => v = u,                    // retro
            4 => u = normal,
            _ => {}
        }
        d.push(u, v, rng.random_range(0.0..1.0));
    }
    d
}

fn with_values(d: &DataSet, y: f64) -> DataSet {
    let mut out = DataSet::new();
    for i in 0..d.len() {
        out.push(d.u(i), d.v(i), y);
    }
    out
}

/// The Lafortune family's samples of `data` (what every layout here evaluates).
fn prepare(data: &DataSet) -> Samples {
    FamilyRef::lafortune().prepare(data)
}

/// A data set with its samples and those of the same directions with every value 0 (the
/// model's values as residuals), prepared once.
struct Prepared {
    data: DataSet,
    samples: Samples,
    zero: Samples,
}

impl Prepared {
    fn new(data: DataSet) -> Self {
        Prepared {
            samples: prepare(&data),
            zero: prepare(&with_values(&data, 0.0)),
            data,
        }
    }
}

/// The Lafortune view of the parameters at `x`.
fn decode(layout: &Layout, x: &[f64]) -> BrdfParams {
    BrdfParams::try_from(&layout.decode(x)).unwrap()
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
    }
    out
}

/// Edge values per parameter: bounds, zero, tiny and near-bound values, and (for n) the
/// neighbourhood of 0 and 1.
fn edge_values(name: &str) -> Vec<f64> {
    if name.ends_with(".n") {
        vec![
            0.0,
            1e-300,
            1e-12,
            1e-6,
            0.5,
            1.0,
            2.0,
            50.0,
            9999.999,
            10000.0,
            16600.0,
            1e5,
            MAX_EXPONENT,
        ]
    } else if name.ends_with(".pan") {
        vec![-90.0, -89.999_999, 0.0, 45.0, 89.999_999, 90.0]
    } else if name == "kd" {
        vec![0.0, 1e-9, 0.5, 1.0]
    } else {
        vec![-1.5, -1.0, -1e-12, 0.0, 1e-12, 0.3, 1.0, 1.5]
    }
}

/// Points of the box for `layout`: corners and edge combinations, random points, and pairs
/// straddling the overflow boundary of `d^n` (a lobe with `Cx = Cy = 0`, so `d = Cz uz vz`
/// peaks at `Cz` at the normal sample) at relative distance 1e-9 and 1e-6 on either side.
fn points(layout: &Layout, rng: &mut Pcg64Mcg) -> Vec<(Vec<f64>, &'static str)> {
    let names = layout.free_names().to_vec();
    let p = layout.dim();
    let (lo, hi) = (layout.lower(), layout.upper());
    let coord = layout.exponent_coord();
    let internal = |name: &str, v: f64| {
        if name.ends_with(".n") {
            coord.to_internal(v)
        } else {
            v
        }
    };
    let mut out = Vec::new();
    // Random edge combinations: each coordinate an edge value.
    for _ in 0..400 {
        let x: Vec<f64> = names
            .iter()
            .map(|nm| {
                let e = edge_values(nm);
                internal(nm, e[rng.random_range(0..e.len())])
            })
            .collect();
        out.push((x, "edges"));
    }
    // Uniform in the internal coordinates (Raw: uniform n, mostly overflowing; Log1p: moderate).
    for _ in 0..200 {
        let x: Vec<f64> = (0..p).map(|j| rng.random_range(lo[j]..=hi[j])).collect();
        out.push((x, "uniform"));
    }
    // Moderate exponents with random Cs.
    for _ in 0..200 {
        let x: Vec<f64> = names
            .iter()
            .enumerate()
            .map(|(j, nm)| {
                if nm.ends_with(".n") {
                    internal(nm, rng.random_range(0.0..200.0))
                } else {
                    rng.random_range(lo[j]..=hi[j])
                }
            })
            .collect();
        out.push((x, "moderate"));
    }
    // The overflow boundary of lobe 1 (all other lobes switched off: Cs = 0).
    for cz in [1.5, 1.2, 1.1] {
        let n_star = LN_MAX / f64::ln(cz);
        for rel in [-1e-6, -1e-9, 1e-9, 1e-6] {
            let n = n_star * (1.0 + rel);
            if n > MAX_EXPONENT {
                continue;
            }
            let x: Vec<f64> = names
                .iter()
                .map(|nm| match nm.as_str() {
                    "lobe1.cz" => cz,
                    "lobe1.n" => internal(nm, n),
                    "kd" => 0.1,
                    _ if nm.ends_with(".n") => internal(nm, 3.0),
                    _ => 0.0,
                })
                .collect();
            out.push((
                x,
                if rel < 0.0 {
                    "below-overflow"
                } else {
                    "above-overflow"
                },
            ));
        }
    }
    out
}

/// The rounding of `d` itself, propagated into the exponent column `n_scale d^n ln d`: with
/// `T = |Cx u'x v'x| + |Cy u'y v'y| + |Cz uz vz|` every kernel computes `d` to within a few
/// `eps T`, which moves `d^n ln d` by `eps (T / d) d^n (1 + n |ln d|)`. It is what makes a
/// column pure rounding noise where `d = 1` within rounding (mirror directions with
/// `Cxy = -Cz`). Zero for other columns.
fn allowance(layout: &Layout, x: &[f64], j: usize, data: &DataSet, i: usize, entry: f64) -> f64 {
    let name = &layout.free_names()[j];
    let Some((k, field)) = name
        .strip_prefix("lobe")
        .and_then(|r| r.split_once('.'))
        .map(|(k, f)| (k.parse::<usize>().unwrap(), f))
    else {
        return 0.0;
    };
    let lobe = decode(layout, x).lobes[k - 1];
    let (d, t) = terms(&lobe, data.u(i), data.v(i));
    if d <= 0.0 {
        return 0.0;
    }
    let n = lobe.n;
    if field != "n" {
        // The other lobe columns hold `n d^(n-1)` times a direction term: rounding `d` moves
        // them by `(n - 1) eps (T / d)` relative, which matters only for the exponents beyond
        // Table 1's 10,000.
        return 16.0 * f64::EPSILON * (t / d) * n * entry.abs();
    }
    let scale = layout.exponent_coord().dn_dx(n);
    16.0 * f64::EPSILON * (t / d) * d.powf(n) * (1.0 + n * d.ln().abs()) * scale
}

/// The same for a value: rounding `d` moves `d^n` by `eps (T / d) n d^n`, summed over lobes.
fn value_allowance(params: &BrdfParams, u: [f64; 3], v: [f64; 3]) -> f64 {
    let mut a = 0.0;
    for lobe in &params.lobes {
        let (d, t) = terms(lobe, u, v);
        if d > 0.0 {
            a += 16.0 * f64::EPSILON * (t / d) * lobe.n * d.powf(lobe.n);
        }
    }
    a
}

/// `d` of a lobe and the sum `T` of its terms' magnitudes.
fn terms(lobe: &Lobe, u: [f64; 3], v: [f64; 3]) -> (f64, f64) {
    let (s, c) = lobe.pan_deg.to_radians().sin_cos();
    let tx = lobe.cx * ((c * u[0] + s * u[1]) * (c * v[0] + s * v[1]));
    let ty = lobe.cy * ((-s * u[0] + c * u[1]) * (-s * v[0] + c * v[1]));
    let tz = lobe.cz * (u[2] * v[2]);
    (tx + ty + tz, tx.abs() + ty.abs() + tz.abs())
}

/// Worst errors of one kernel against scalar.
#[derive(Default, Debug)]
struct Worst {
    value: f64,
    residual: f64,
    column: f64,
}

/// Compares `kernel` with scalar at every point; returns the worst errors seen and counts of
/// points whose values overflowed.
fn compare(kernel: Kernel, layout: &Layout, x: &[f64], what: &str, prep: &Prepared) -> Worst {
    let Prepared {
        data,
        samples,
        zero,
    } = prep;
    let m = data.len();
    let p = layout.dim();
    let mut sc = Evaluator::with_kernel(layout, Kernel::Scalar).unwrap();
    let mut ev = Evaluator::with_kernel(layout, kernel).unwrap();
    let mut w = Worst::default();
    let params = decode(layout, x);
    // Values (residuals against y = 0).
    let (mut a, mut b) = (vec![0.0; m], vec![0.0; m]);
    let ok_a = ev.residuals(x, zero, &mut a);
    let ok_b = sc.residuals(x, zero, &mut b);
    assert_eq!(
        ok_a, ok_b,
        "{kernel}: value overflow differs at {what} {x:?}"
    );
    for (i, (&va, &vb)) in a.iter().zip(&b).enumerate() {
        assert!(
            !va.is_nan() && !vb.is_nan(),
            "{kernel}: NaN value at {what} {x:?} row {i}"
        );
        assert!(va >= 0.0 && vb >= 0.0);
        if vb.is_infinite() || va.is_infinite() {
            assert_eq!(va, vb, "{kernel}: overflow differs at {what} {x:?} row {i}");
            continue;
        }
        // Relative, with an absolute floor for underflowed (subnormal) lobe values, beyond
        // the effect of rounding d.
        let allow = value_allowance(&params, data.u(i), data.v(i));
        w.value = w
            .value
            .max(((va - vb).abs() - allow).max(0.0) / vb.max(1e-290));
    }
    match what {
        "above-overflow" => assert!(!ok_b && b[0] == f64::INFINITY, "{x:?}"),
        "below-overflow" => assert!(ok_b && b[0].is_finite() && b[0] > 1e307, "{x:?}"),
        _ => {}
    }
    // Residuals against the data (relative to the larger of value and y).
    let (mut ra, mut rb) = (vec![0.0; m], vec![0.0; m]);
    assert_eq!(ev.residuals(x, samples, &mut ra), ok_b);
    assert_eq!(sc.residuals(x, samples, &mut rb), ok_b);
    if ok_b {
        for i in 0..m {
            let scale = b[i].max(data.value(i)).max(1e-290);
            let allow = value_allowance(&params, data.u(i), data.v(i));
            w.residual = w
                .residual
                .max(((ra[i] - rb[i]).abs() - allow).max(0.0) / scale);
        }
    }
    // Sum of squares: +inf exactly when the evaluation fails (or the squares overflow).
    let (sa, sb) = (ev.sum_squares(x, samples), sc.sum_squares(x, samples));
    assert!(!sa.is_nan() && !sb.is_nan());
    assert_eq!(
        sa.is_finite(),
        sb.is_finite(),
        "{kernel}: sum of squares at {what} {x:?}"
    );
    // Jacobian (with the residuals computed alongside).
    let (mut ja, mut jb) = (vec![0.0; m * p], vec![0.0; m * p]);
    let (mut r1, mut r2) = (vec![0.0; m], vec![0.0; m]);
    let okj_a = ev.residuals_and_jacobian(x, samples, &mut r1, &mut ja);
    let okj_b = sc.residuals_and_jacobian(x, samples, &mut r2, &mut jb);
    assert_eq!(
        okj_a, okj_b,
        "{kernel}: Jacobian failure differs at {what} {x:?}"
    );
    if okj_b {
        for (j, (ca, cb)) in ja.chunks(m).zip(jb.chunks(m)).enumerate() {
            // Relative to the column's largest entry: the weights of P, Q, R, S cancel in
            // places, where FMA and separate rounding legitimately differ per entry.
            // The floor: kernels flush `d^n` below 2^-1010 (about 1e-304), and a column holds
            // `n d^(n-1)`, up to 1e6 times that for the widest exponents (MAX_EXPONENT).
            let scale = cb.iter().fold(0.0f64, |s, v| s.max(v.abs())).max(1e-280);
            for (i, (&ea, &eb)) in ca.iter().zip(cb).enumerate() {
                assert!(ea.is_finite() && eb.is_finite(), "col {j} row {i}");
                let allow = allowance(layout, x, j, data, i, eb);
                let e = ((ea - eb).abs() - allow).max(0.0) / scale;
                if e > 1e-10 {
                    println!(
                        "{kernel} {what} col {j} row {i}: {ea} vs {eb} (scale {scale}) at {x:?}"
                    );
                }
                w.column = w.column.max(e);
            }
        }
    }
    w
}

/// Every kernel this machine runs (AVX-512, AVX2, portable) agrees with the scalar libm
/// reference over the whole Table 1 box, for both exponent coordinates (raw `n` and
/// `ln(1 + n)`), anisotropic and isotropic lobes:
///
/// - values `f(u, v) = kd + sum max(0, d)^n`: relative error at most **1e-11**
///   (`|f - f_ref| <= 1e-11 max(f_ref, 1e-290)`, the floor only matters for underflowed lobes)
///   beyond the effect of rounding `d` itself (each kernel computes `d` to a few ulp of its
///   terms, which moves `d^n` by up to `16 eps (T / d) n d^n`, see [`value_allowance`]: this is
///   the problem's conditioning, not kernel error);
/// - residuals `f - y`: error at most **1e-11** relative to `max(f_ref, y)`;
/// - Jacobian columns: error at most **1e-10** relative to the column's largest entry
///   (entries are sums of weighted products that cancel in places, so entry-wise relative
///   error is not meaningful there), plus, in exponent columns, the effect of rounding `d`
///   ([`allowance`]: 16 eps of `d`'s terms, propagated), which is all a column holds where
///   `d = 1` within rounding;
/// - overflow is reported identically: the same success flags for residuals, Jacobian and a
///   finite sum of squares, `+inf` values in the same rows, never NaN. Points straddle the
///   overflow boundary `n ln d = ln(f64::MAX)` at relative distances 1e-9 and 1e-6 (closer
///   than the kernels' rounding, about 1e-13, a kernel may land on either side).
///
/// The points: 400 random combinations of edge values per layout (n = 0, 1e-300, 1e-12, 1e-6,
/// 0.5, 1, 2, 50, 9999.999, 10000, and beyond Table 1 16600, 1e5 and 1e6, the widest an
/// exponent's bounds may be, [`MAX_EXPONENT`]; C = ±1.5, ±1, ±1e-12, 0, 0.3; pan = ±90, ±89.999999, 0, 45;
/// kd = 0, 1e-9, 0.5, 1), 200 uniform points of the internal box, 200 with moderate n, and the
/// overflow pairs; the directions include grazing ones (`uz = 0` or `vz = 0`), the normal,
/// mirror and retro pairs, so lobes with `d <= 0` and `d = 0` occur.
#[test]
fn every_kernel_agrees_with_scalar_over_the_box() {
    let prep = Prepared::new(box_data(600, 7));
    let mut rng = Pcg64Mcg::seed_from_u64(3);
    let kernels: Vec<Kernel> = Kernel::available()
        .into_iter()
        .filter(|&k| k != Kernel::Scalar)
        .collect();
    assert!(kernels.contains(&Kernel::Portable));
    let mut worst = Worst::default();
    let (mut overflowed, mut total) = (0, 0);
    for layout in layouts() {
        for (x, what) in points(&layout, &mut rng) {
            total += 1;
            let mut sc = Evaluator::with_kernel(&layout, Kernel::Scalar).unwrap();
            let mut r = vec![0.0; prep.data.len()];
            if !sc.residuals(&x, &prep.samples, &mut r) {
                overflowed += 1;
            }
            for &k in &kernels {
                let w = compare(k, &layout, &x, what, &prep);
                worst.value = worst.value.max(w.value);
                worst.residual = worst.residual.max(w.residual);
                worst.column = worst.column.max(w.column);
            }
        }
    }
    println!("kernels {kernels:?}: {total} points ({overflowed} overflowing), worst {worst:?}");
    assert!(
        overflowed > 50 && overflowed < total / 2,
        "{overflowed} of {total}"
    );
    assert!(worst.value <= 1e-11, "{worst:?}");
    assert!(worst.residual <= 1e-11, "{worst:?}");
    assert!(worst.column <= 1e-10, "{worst:?}");
}

#[test]
fn kernel_names_parse_display_and_serde() {
    for k in Kernel::ALL {
        assert_eq!(k.to_string(), k.name());
        assert_eq!(k.name().parse::<Kernel>(), Ok(k));
        assert_eq!(
            serde_json::to_string(&k).unwrap(),
            format!("\"{}\"", k.name())
        );
        assert_eq!(
            serde_json::from_str::<Kernel>(&format!("\"{k}\"")).unwrap(),
            k
        );
    }
    let names: Vec<&str> = Kernel::ALL.iter().map(|k| k.name()).collect();
    assert_eq!(names, ["auto", "avx512", "avx2", "portable", "scalar"]);
    assert_eq!(" AVX2 ".parse::<Kernel>(), Ok(Kernel::Avx2));
    let err = "sse9".parse::<Kernel>().unwrap_err();
    assert!(matches!(err, KernelError::Unknown(_)));
    assert!(
        err.to_string()
            .contains("auto, avx512, avx2, portable, scalar")
    );
    assert_eq!(Kernel::default(), Kernel::Auto);
}

#[test]
fn kernels_resolve_or_explain() {
    let layout = Layout::builder(&[LobeKind::Isotropic]).build().unwrap();
    let auto = Kernel::Auto.resolve().unwrap();
    assert_ne!(auto, Kernel::Auto);
    assert_ne!(auto, Kernel::Scalar);
    assert_eq!(Evaluator::new(&layout).kernel(), auto);
    assert_eq!(Kernel::available()[0], auto);
    for k in Kernel::ALL {
        match k.resolve() {
            Ok(c) => {
                assert!(k == Kernel::Auto || c == k);
                let ev = Evaluator::with_kernel(&layout, k).unwrap();
                assert_eq!(ev.kernel(), c);
            }
            Err(e) => {
                assert!(!k.is_available());
                let msg = e.to_string();
                assert!(
                    msg.contains(k.name()) && msg.contains("available: "),
                    "{msg}"
                );
                let mut ev = Evaluator::new(&layout);
                assert_eq!(ev.set_kernel(k), Err(e));
                assert_eq!(ev.kernel(), auto, "a failed choice changes nothing");
            }
        }
    }
}

/// `sum_squares_below` with an infinite bound is `sum_squares` bit for bit (every kernel), and
/// with a bound below the sum it stops early and says so.
#[test]
fn sum_squares_below_is_exact_or_exceeds_the_bound() {
    let layout = Layout::builder(&[LobeKind::Anisotropic, LobeKind::Isotropic])
        .build()
        .unwrap();
    let data = layout.prepare(&box_data(5 * SUM_BLOCK + 13, 9));
    let mut rng = Pcg64Mcg::seed_from_u64(5);
    let mut cut = 0;
    for k in Kernel::available() {
        let mut ev = Evaluator::with_kernel(&layout, k).unwrap();
        for trial in 0..40 {
            let x: Vec<f64> = if trial == 0 {
                layout.encode(&BrdfParams {
                    kd: 0.2,
                    lobes: vec![
                        Lobe::isotropic(-1.0, 1.0, 20.0),
                        Lobe::isotropic(0.5, 0.5, 2.0),
                    ],
                })
            } else {
                (0..layout.dim())
                    .map(|j| rng.random_range(layout.lower()[j]..=layout.upper()[j]))
                    .collect()
            };
            let ss = ev.sum_squares(&x, &data);
            let all = ev.sum_squares_below(&x, &data, f64::INFINITY);
            assert_eq!(all.sum_squares.map(f64::to_bits), Some(ss.to_bits()), "{k}");
            if ss.is_finite() {
                assert_eq!(all.samples, data.len());
            }
            if ss.is_finite() {
                let at = ev.sum_squares_below(&x, &data, ss);
                assert_eq!(at.sum_squares, Some(ss));
                let below = ev.sum_squares_below(&x, &data, ss * 0.1);
                assert_eq!(below.sum_squares, None, "{k}");
                assert!(below.samples <= data.len());
                if below.samples < data.len() {
                    cut += 1;
                    assert_eq!(below.samples % SUM_BLOCK, 0);
                }
            } else {
                let b = ev.sum_squares_below(&x, &data, 1e300);
                assert_eq!(b.sum_squares, None);
            }
        }
    }
    assert!(cut > 10, "{cut}");
}

/// Regression (stress suite): `g = n d^n / d` was computed as `(n d^n) / d`, which overflowed
/// while `g` itself is finite, so the Jacobian reported a failed evaluation. At normal
/// incidence with `Cz = 1.5` (`d = 1.5`) and `n = 1732.5466110450388`: `d^n = 1.22e305`,
/// `n d^n = 2.1e308` overflows, but `g = n d^(n-1) = 1.41e308` does not. Every kernel the
/// machine runs must return true and the Cz column must hold `g`; just above the overflow of
/// `g` itself every kernel must report failure.
#[test]
fn jacobian_does_not_overflow_before_its_true_value() {
    let n: f64 = 1_732.546_611_045_038_8;
    let mut data = DataSet::new();
    let normal = [0.0, 0.0, 1.0];
    data.push(normal, normal, 0.0);
    // A second sample with d < 1 so a column is not a single entry.
    data.push([0.6, 0.0, 0.8], [-0.6, 0.0, 0.8], 0.1);
    let data = prepare(&data);
    let want_f = 1.5f64.powf(n);
    let want_g = n * 1.5f64.powf(n - 1.0);
    assert!(want_f.is_finite() && want_g.is_finite() && (n * want_f).is_infinite());
    for coord in [ExponentCoord::Raw, ExponentCoord::Log1p] {
        for kind in [LobeKind::Isotropic, LobeKind::Anisotropic] {
            let layout = Layout::builder(&[kind])
                .exponent_coord(coord)
                .build()
                .unwrap();
            let lobe = match kind {
                LobeKind::Isotropic => Lobe::isotropic(0.0, 1.5, n),
                LobeKind::Anisotropic => Lobe {
                    pan_deg: 10.0,
                    ..Lobe::isotropic(0.0, 1.5, n)
                },
            };
            let x = layout.encode(&BrdfParams {
                kd: 0.0,
                lobes: vec![lobe],
            });
            let cz = layout
                .free_names()
                .iter()
                .position(|s| s == "lobe1.cz")
                .unwrap();
            let m = data.len();
            for kernel in Kernel::available() {
                let mut ev = Evaluator::with_kernel(&layout, kernel).unwrap();
                let mut r = vec![0.0; m];
                let mut jac = vec![0.0; m * layout.dim()];
                assert!(
                    ev.residuals_and_jacobian(&x, &data, &mut r, &mut jac),
                    "{kernel} {coord:?} {kind:?}: spurious Jacobian overflow"
                );
                assert!(ev.jacobian(&x, &data, &mut jac), "{kernel}");
                assert!((r[0] - want_f).abs() <= 1e-9 * want_f, "{kernel}: {}", r[0]);
                let g = jac[cz * m];
                assert!(
                    (g - want_g).abs() <= 1e-9 * want_g,
                    "{kernel} {coord:?} {kind:?}: {g} vs {want_g}"
                );
                // 1.002 n: d^n still finite (about 1.5e305 * 1.5^3.5), g overflows.
                let n_over = n * 1.002;
                assert!(1.5f64.powf(n_over).is_finite());
                assert!((n_over * 1.5f64.powf(n_over - 1.0)).is_infinite());
                let lobe = match kind {
                    LobeKind::Isotropic => Lobe::isotropic(0.0, 1.5, n_over),
                    LobeKind::Anisotropic => Lobe {
                        pan_deg: 10.0,
                        ..Lobe::isotropic(0.0, 1.5, n_over)
                    },
                };
                let xo = layout.encode(&BrdfParams {
                    kd: 0.0,
                    lobes: vec![lobe],
                });
                assert!(
                    !ev.residuals_and_jacobian(&xo, &data, &mut r, &mut jac),
                    "{kernel}: a true overflow of g must fail"
                );
            }
        }
    }
}

/// Each sample's value and Jacobian row do not depend on which other samples share its pass:
/// every kernel gives the same bits over a whole data set as over each sample alone. The
/// AVX-512 kernels run two vectors per iteration where they can and one masked vector for
/// the rest, and the portable and AVX2 kernels choose a shorter logarithm and exponential
/// per chunk, so this compares those paths with one another at sizes around their steps.
#[test]
fn a_sample_gets_the_same_bits_in_any_company() {
    let mut rng = Pcg64Mcg::seed_from_u64(11);
    let all = prepare(&box_data(80, 5));
    let mut compared = 0usize;
    for kernel in Kernel::available() {
        for layout in layouts() {
            let p = layout.dim();
            for (x, what) in points(&layout, &mut rng).into_iter().take(6) {
                let mut ev = Evaluator::with_kernel(&layout, kernel).unwrap();
                for m in [1, 7, 8, 9, 15, 16, 17, 31, 33, 64, 65, 81] {
                    let rows: Vec<u32> = (0..m as u32).collect();
                    let mut data = Samples::empty(layout.family().name(), 0);
                    all.gather_into(&rows, &mut data);
                    let (mut v, mut r, mut jac) = (vec![0.0; m], vec![0.0; m], vec![0.0; m * p]);
                    let ok_v = ev.residuals(&x, &data, &mut v);
                    let ok = ev.residuals_and_jacobian(&x, &data, &mut r, &mut jac);
                    let mut one = Samples::empty(layout.family().name(), 0);
                    let (mut v1, mut r1, mut j1) = (vec![0.0; 1], vec![0.0; 1], vec![0.0; p]);
                    for i in 0..m {
                        all.gather_into(&[i as u32], &mut one);
                        let case = format!("{kernel} {what} m {m} row {i}");
                        if ok_v && ev.residuals(&x, &one, &mut v1) {
                            assert_eq!(v[i].to_bits(), v1[0].to_bits(), "{case} value");
                            compared += 1;
                        }
                        if ok && ev.residuals_and_jacobian(&x, &one, &mut r1, &mut j1) {
                            assert_eq!(r[i].to_bits(), r1[0].to_bits(), "{case}");
                            for j in 0..p {
                                assert_eq!(
                                    jac[j * m + i].to_bits(),
                                    j1[j].to_bits(),
                                    "{case} col {j}"
                                );
                            }
                            compared += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(compared > 10_000, "only {compared} comparisons");
}
