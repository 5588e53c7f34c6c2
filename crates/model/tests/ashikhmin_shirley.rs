//! The Ashikhmin-Shirley family: the normalisation of its half-vector distribution by
//! quadrature over the hemisphere, values computed by hand, the horizon and the extreme
//! bounds.

mod quadrature;

use brdf_model::{DataSet, Evaluator, Kernel, Layout, LobeKind, Params, family};
use quadrature::{over_half_vectors, reflect};
use std::f64::consts::PI;

/// One lobe `ks, nu, nv, f0, pan` (degrees), no constant term.
fn lobe(ks: f64, nu: f64, nv: f64, f0: f64, pan: f64) -> Params {
    let fam = family("ashikhmin-shirley").unwrap();
    let p = Params::new(fam, vec![0.0], vec![vec![ks, nu, nv, f0, pan]]).unwrap();
    p.validate().unwrap();
    p
}

/// The direction at polar angle `theta_deg` and azimuth `phi_deg`; exactly on the horizon
/// for `theta_deg = 90`.
fn dir(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    if theta_deg == 90.0 {
        [cp, sp, 0.0]
    } else {
        [st * cp, st * sp, ct]
    }
}

/// The lobe is `ks D(h) F / (4 (u.h) max(uz, vz))` with the distribution
/// `D(h) = sqrt((nu + 1)(nv + 1)) / (2 pi) hz^e(phi_h)`, `e = nu cos^2 + nv sin^2`, which
/// integrates to 1 over the hemisphere of `h` (exactly: `int_0^(pi/2) cos^e sin = 1/(e + 1)`
/// and `int dphi / (1 + e(phi)) = 2 pi / sqrt((nu + 1)(nv + 1))`). At normal incidence with
/// `f0 = 1` (`F = 1`), `u.h = hz`, `max = 1` and `dw_v = 4 hz dw_h`, so
/// `int f(z, v) dw_v = ks (1 - tail)` over the `h` that keep `v` above the horizon
/// (`theta_h < 45` degrees), with `tail = (1/2pi) int sqrt((nu+1)(nv+1)) 2^(-(e+1)/2) / (e+1)
/// dphi` (for an isotropic lobe `2^(-(n+1)/2)`).
///
/// Measured (quadrature: 200 panels of 8 Gauss-Legendre points in `theta_h` on [0, 45]
/// degrees, 512 azimuths): within 1e-10 relative of `ks (1 - tail)` (in fact 3e-13) for
/// (nu, nv, pan) = (0, 0, 0) (the uniform distribution, tail 0.7071), (10, 10, 0) (tail
/// 0.0221), (100, 100, 0), (1000, 1000, 0), (10, 1000, 30) and (5000, 200, -70).
#[test]
fn distribution_integrates_to_one() {
    let ks = 0.6;
    let z = [0.0, 0.0, 1.0];
    for (nu, nv, pan) in [
        (0.0, 0.0, 0.0),
        (10.0, 10.0, 0.0),
        (100.0, 100.0, 0.0),
        (1000.0, 1000.0, 0.0),
        (10.0, 1000.0, 30.0),
        (5000.0, 200.0, -70.0),
    ] {
        let p = lobe(ks, nu, nv, 1.0, pan);
        let got = over_half_vectors(PI / 4.0, 200, 512, |h| {
            p.value(z, reflect(z, h)) * 4.0 * h[2]
        });
        let n = 1 << 14;
        let tail = (0..n)
            .map(|k| {
                let (s, c) = (2.0 * PI * k as f64 / n as f64).sin_cos();
                let e = nu * c * c + nv * s * s;
                ((nu + 1.0) * (nv + 1.0)).sqrt() * 0.5f64.powf((e + 1.0) / 2.0) / (e + 1.0)
            })
            .sum::<f64>()
            / n as f64;
        let want = ks * (1.0 - tail);
        eprintln!("({nu}, {nv}, {pan}): {got:.15} want {want:.15} tail {tail:.3e}");
        assert!((got - want).abs() <= 1e-10 * want, "{got} vs {want}");
    }
}

/// Values computed by hand (the arithmetic in the comments).
#[test]
fn hand_computed_values() {
    let close = |a: f64, b: f64| assert!((a - b).abs() <= 1e-14 * b.abs(), "{a} vs {b}");
    let z = [0.0, 0.0, 1.0];
    // u = v = z: h = z, (n.h)^e = 1, F(1) = f0, (u.h) max(uz, vz) = 1:
    // 0.5 (99 + 1)/(8 pi) 0.3 = 0.596831036594608; plus the constant term.
    let mut p = lobe(0.5, 99.0, 99.0, 0.3, 0.0);
    p.shared_mut()[0] = 0.2;
    close(p.value(z, z), 0.2 + 0.596_831_036_594_607_5);
    // u = (sin 60, 0, cos 60), v = z: h = (1/2, 0, sqrt(3)/2), u.h = sqrt(3)/2, max = 1;
    // e = n (h along x), hz^10 = (3/4)^5 = 0.2373046875;
    // F = 0.1 + 0.9 (1 - sqrt(3)/2)^5 = 0.100038846759193;
    // 0.8 (11 / (8 pi)) 0.2373046875 F / (sqrt(3)/2) = 0.00959814207671234.
    let u = [0.75f64.sqrt(), 0.0, 0.5];
    close(
        lobe(0.8, 10.0, 10.0, 0.1, 0.0).value(u, z),
        0.009_598_142_076_712_337,
    );
    // Anisotropic nu = 1000, nv = 10, u = (0, sin 60, cos 60), v = z: h along y, so e = nv
    // = 10: 0.7 sqrt(1001 * 11) / (8 pi) 0.2373046875 (0.2 + 0.8 (1 - sqrt(3)/2)^5) /
    // (sqrt(3)/2) = 0.160196202957363. A pan of 90 degrees puts h along the lobe's x: e = nu
    // = 1000, (3/4)^500: 2.29074948140230e-63.
    let u = [0.0, 0.75f64.sqrt(), 0.5];
    close(
        lobe(0.7, 1000.0, 10.0, 0.2, 0.0).value(u, z),
        0.160_196_202_957_362_84,
    );
    let sharp = lobe(0.7, 1000.0, 10.0, 0.2, 90.0).value(u, z);
    assert!(
        (sharp - 2.290_749_481_402_297_5e-63).abs() <= 1e-12 * 2.29e-63,
        "{sharp}"
    );
    // An isotropic lobe is the anisotropic one with nu = nv.
    let fam = family("ashikhmin-shirley").unwrap();
    let iso = Layout::builder_for(&fam, &[LobeKind::Isotropic])
        .unwrap()
        .build()
        .unwrap();
    let q = iso.decode(&iso.encode(lobe(0.7, 40.0, 40.0, 0.2, 0.0)));
    close(
        q.value(u, dir(30.0, 200.0)),
        lobe(0.7, 40.0, 40.0, 0.2, 0.0).value(u, dir(30.0, 200.0)),
    );
}

/// The evaluator's residuals and Jacobian at `p` on `data` (one lobe of `kind`), checking
/// that every kernel succeeds or fails alike and gives no NaN.
fn evaluate(p: &Params, kind: LobeKind, data: &DataSet) -> (bool, Vec<f64>, Vec<f64>) {
    let layout = Layout::builder_for(p.family(), &[kind])
        .unwrap()
        .build()
        .unwrap();
    let x = layout.encode(p);
    let samples = layout.prepare(data);
    let (m, n) = (data.len(), layout.dim());
    let mut ev = Evaluator::with_kernel(&layout, Kernel::Scalar).unwrap();
    let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * n]);
    let ok = ev.residuals_and_jacobian(&x, &samples, &mut r, &mut jac);
    for k in Kernel::available() {
        let mut e = Evaluator::with_kernel(&layout, k).unwrap();
        let (mut r2, mut j2) = (vec![0.0; m], vec![0.0; m * n]);
        assert_eq!(
            e.residuals_and_jacobian(&x, &samples, &mut r2, &mut j2),
            ok,
            "{k}"
        );
        assert!(r2.iter().chain(&j2).all(|v| !v.is_nan()), "{k}: NaN");
    }
    (ok, r, jac)
}

/// On the horizon: with one direction there the value is the formula's finite value; with
/// both (also `v = -u`) the lobe is 0.
#[test]
fn horizon_values() {
    // u = (1, 0, 0), v = z: h = (1, 0, 1)/sqrt(2), hz^10 = 1/32, u.h = 1/sqrt(2), max = 1;
    // 0.6 (11 / (8 pi)) (1/32) (0.05 + 0.95 (1 - 1/sqrt(2))^5) / (1/sqrt(2))
    // = 6.04047080878829e-4.
    let p = lobe(0.6, 10.0, 10.0, 0.05, 0.0);
    let (on, z) = ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    let a = p.value(on, z);
    assert!((a - 6.040_470_808_788_285e-4).abs() <= 1e-14 * a, "{a}");
    assert_eq!(a, p.value(z, on));
    for v in [dir(90.0, 70.0), dir(90.0, 180.0), on] {
        assert_eq!(p.value(on, v), 0.0, "{v:?}");
    }
    let mut data = DataSet::new();
    data.push(on, z, 0.1);
    data.push(on, dir(90.0, 70.0), 0.1);
    data.push(on, [-1.0, 0.0, 0.0], 0.1);
    let (ok, r, jac) = evaluate(&p, LobeKind::Isotropic, &data);
    assert!(ok && r.iter().chain(&jac).all(|v| v.is_finite()), "{r:?}");
}

/// At the corners of the box, at the peak, near and on the horizon, below it: finite values,
/// never NaN, in every kernel.
#[test]
fn extreme_bounds_are_finite() {
    let mut dirs = vec![[0.0, 0.0, 1.0]];
    for (t, p) in [
        (10.0, 0.0),
        (45.0, 100.0),
        (80.0, 250.0),
        (89.9999, 33.0),
        (90.0, 213.0),
    ] {
        dirs.push(dir(t, p));
    }
    let mut data = DataSet::new();
    for &u in &dirs {
        for &v in &dirs {
            data.push(u, v, 0.5);
        }
    }
    // Below the horizon (kept by `Filters::none`): no NaN either.
    data.push(dir(100.0, 0.0), dir(30.0, 10.0), 0.5);
    data.push(dir(100.0, 0.0), dir(120.0, 180.0), 0.5);
    for ks in [0.0, 1.0] {
        for (nu, nv) in [(0.0, 0.0), (1e6, 1e6), (0.0, 1e6), (1e6, 0.0)] {
            for f0 in [0.0, 1.0] {
                for pan in [-90.0, 90.0] {
                    let p = lobe(ks, nu, nv, f0, pan);
                    for i in 0..data.len() {
                        let v = p.value(data.u(i), data.v(i));
                        assert!(v.is_finite(), "{ks} {nu} {nv} {f0}: {v}");
                    }
                    let kind = if nu == nv {
                        LobeKind::Isotropic
                    } else {
                        LobeKind::Anisotropic
                    };
                    let (ok, _, jac) = evaluate(&p, kind, &data);
                    assert!(ok && jac.iter().all(|v| v.is_finite()));
                }
            }
        }
    }
}
