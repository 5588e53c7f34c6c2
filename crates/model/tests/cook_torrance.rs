//! Cook-Torrance: the Beckmann distribution's normalisation by quadrature through the kernels'
//! code, values computed by hand, the exponent without cancellation at small roughness, and
//! the horizon and the box's edges (finite values and Jacobians, no NaN).

// Expected values are mpmath's digits as printed, some beyond f64's precision.
#![allow(clippy::excessive_precision)]

mod quadrature;

use brdf_model::lobes::{FusedMath, Libm, LobeShape, MAX_COLUMNS, PlainMath};
use brdf_model::models::cook_torrance::{
    CookTorrance, LOG_GEOMETRY, ONE_MINUS_COS_D, SLOPE_X, SLOPE_Y, TAN2, columns,
};
use brdf_model::{
    DataSet, Evaluator, ExponentCoord, Kernel, Layout, LobeKind, Params, family, uniform_hemisphere,
};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::f64::consts::PI;

/// `D(h)` as the lobe computes it: with the geometric factor `G / (4 uz vz)` set to 1 (the
/// column `E` holding only `ln(1 / cos^4)`), `u.h = 1` (`F = f0`), `ks = 1` and `f0 = 1`, the
/// lobe is `D(h)`. `math`: 0 libm, 1 the portable kernel's, 2 the AVX kernels'.
fn d_of<const ANISO: bool>(fields: &[f64; 5], h: [f64; 3], math: usize) -> f64 {
    let c = CookTorrance::coef(fields, ANISO);
    let mut s = [0.0; MAX_COLUMNS];
    let (sx, sy) = (h[0] / h[2], h[1] / h[2]);
    let tan2 = sx * sx + sy * sy;
    s[SLOPE_X] = sx;
    s[SLOPE_Y] = sy;
    s[TAN2] = tan2;
    s[LOG_GEOMETRY] = 2.0 * tan2.ln_1p();
    s[ONE_MINUS_COS_D] = 0.0;
    match math {
        0 => CookTorrance::value::<Libm, ANISO>(&c, &s),
        1 => CookTorrance::value::<PlainMath, ANISO>(&c, &s),
        _ => CookTorrance::value::<FusedMath, ANISO>(&c, &s),
    }
}

/// `int D(h) (n.h) dw_h = 1` over the hemisphere, isotropic and anisotropic (`my = mx / 3`,
/// pan 30 degrees), at roughness 0.01, 0.05, 0.3, 1, 2 and 2.5 (the upper bound), with the
/// libm and both fast arithmetics. 32-point Gauss-Legendre on panels in `theta` (ends at
/// `atan(m 2^k)`), 1024 azimuths. Measured (2026-12-07): every integral within 1.9e-15 of 1;
/// the tolerance is 1e-12.
#[test]
fn beckmann_distribution_is_normalised() {
    let mut worst = 0.0f64;
    for m in [0.01f64, 0.05, 0.3, 1.0, 2.0, 2.5] {
        for (aniso, fields) in [
            (false, [1.0, m, m, 1.0, 0.0]),
            (true, [1.0, m, m / 3.0, 1.0, 30.0]),
        ] {
            for math in 0..3 {
                let width = fields[1].min(fields[2]);
                let integral = quadrature::hemisphere(width, 1024, |h| {
                    let d = if aniso {
                        d_of::<true>(&fields, h, math)
                    } else {
                        d_of::<false>(&fields, h, math)
                    };
                    d * h[2]
                });
                worst = worst.max((integral - 1.0).abs());
                assert!(
                    (integral - 1.0).abs() <= 1e-12,
                    "m = {m}, aniso {aniso}, math {math}: {integral}"
                );
            }
        }
    }
    eprintln!("Beckmann normalisation: largest |integral - 1| = {worst:.1e}");
}

fn sph(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    [st * cp, st * sp, ct]
}

fn params(kd: f64, lobe: [f64; 5]) -> Params {
    Params::new(
        family("cook-torrance").unwrap(),
        vec![kd],
        vec![lobe.to_vec()],
    )
    .unwrap()
}

/// The value by every kernel (residuals against 0 at the pair `u`, `v`), for a layout of the
/// lobe's kind.
fn kernel_values(p: &Params, kind: LobeKind, u: [f64; 3], v: [f64; 3]) -> Vec<f64> {
    let layout = Layout::builder_for(p.family(), &[kind])
        .unwrap()
        .build()
        .unwrap();
    let mut data = DataSet::new();
    data.push(u, v, 0.0);
    let samples = layout.prepare(&data);
    let x = layout.encode(p.clone());
    Kernel::available()
        .into_iter()
        .map(|k| {
            let mut ev = Evaluator::with_kernel(&layout, k).unwrap();
            let mut r = [0.0];
            assert!(ev.residuals(&x, &samples, &mut r), "{k}");
            r[0]
        })
        .collect()
}

/// Values computed by hand from the formula (mpmath at 50 digits, from the exact angles;
/// the directions below are their `f64` roundings, so agreement is to about 1e-15).
#[test]
fn hand_computed_values() {
    // (kd, [ks, mx, my, f0, pan], u, v, value, kind)
    let cases = [
        // A: u = v = n. h = n, tan = 0, D = 1/(pi m^2) = 1.27323954474 (m = 0.5), G = 1,
        // F(1) = f0 = 0.04, 4 uz vz = 4: 0.1 + 2 * 1.27323954474 * 0.04 / 4
        // = 0.1 + 0.08 / pi = 0.12546479089470326.
        (
            0.1,
            [2.0, 0.5, 0.5, 0.04, 0.0],
            sph(0.0, 0.0),
            sph(0.0, 0.0),
            0.125_464_790_894_703_26,
            LobeKind::Isotropic,
        ),
        // B: u at 60 degrees (azimuth 0), v at 30 degrees (azimuth 180): theta_h = 15 degrees,
        // u.h = cos 45 = 0.707106781187; tan^2(15) = 0.0717967697245; m = 0.3:
        // D = exp(-0.0717967697245 / 0.09) / (pi 0.09 cos^4 15) = 1.82969038747;
        // G = min(1, 2 cos15 cos60 / cos45, ...) = min(1, 1.366, 2.366) = 1;
        // F = 0.05 + 0.95 (1 - 0.707106781187)^5 = 0.052047718196;
        // 0.02 + 1.5 D F / (4 cos60 cos30) = 0.10247264680992283.
        (
            0.02,
            [1.5, 0.3, 0.3, 0.05, 0.0],
            sph(60.0, 0.0),
            sph(30.0, 180.0),
            0.102_472_646_809_922_83,
            LobeKind::Isotropic,
        ),
        // C: anisotropic, mx = 0.2, my = 0.4, pan 30; u at (50, 10), v at (40, 200) degrees:
        // tan^2(theta_h) = 0.0151922469878, phi_h - pan the azimuth in the lobe's frame,
        // D = exp(-tan^2 (cos^2/0.04 + sin^2/0.16)) / (pi 0.08 hz^4) = 3.47289853495 with
        // hz = 0.992489346753; G = 1; u.h = 0.709746687667, F = 0.101854079842;
        // 0.03 + 0.8 D F / (4 uz vz) = 0.17367428915157839.
        (
            0.03,
            [0.8, 0.2, 0.4, 0.1, 30.0],
            sph(50.0, 10.0),
            sph(40.0, 200.0),
            0.173_674_289_151_578_39,
            LobeKind::Anisotropic,
        ),
        // D: grazing, the V-cavity term below 1: u at (85, 0), v at (85, 90), m = 2, f0 = 1:
        // hz = 0.122791346617, u.h = 0.709787335578, tan^2 = 65.3230478219,
        // D = exp(-65.323 / 4) / (pi 4 hz^4) = 2.82982308245e-5,
        // G = 2 hz uz / (u.h) = 0.0301554296083; D G / (4 uz vz) = 2.8084894497537998e-5.
        (
            0.0,
            [1.0, 2.0, 2.0, 1.0, 0.0],
            sph(85.0, 0.0),
            sph(85.0, 90.0),
            2.808_489_449_753_799_8e-5,
            LobeKind::Isotropic,
        ),
        // E: u on the horizon (1, 0, 0), v at (30, 180): h = (0.5, 0, cos 30), u.h = 0.5,
        // tan^2 = 1/3; m = 0.5: D = exp(-4/3) / (pi 0.25 (3/4)^2); G / (4 uz vz) is its limit
        // hz / (2 (u.h) vz) = 1; F = 0.2 + 0.8 * 0.5^5 = 0.225: value 0.13424892005118390.
        (
            0.0,
            [1.0, 0.5, 0.5, 0.2, 0.0],
            [1.0, 0.0, 0.0],
            sph(30.0, 180.0),
            0.134_248_920_051_183_90,
            LobeKind::Isotropic,
        ),
    ];
    for (i, (kd, lobe, u, v, want, kind)) in cases.into_iter().enumerate() {
        let p = params(kd, lobe);
        let got = p.value(u, v);
        let rel = |a: f64| (a - want).abs() / want;
        assert!(rel(got) <= 2e-14, "case {i}: {got} vs {want}");
        // Reciprocity, and every kernel.
        assert!(rel(p.value(v, u)) <= 2e-14, "case {i} swapped");
        for k in kernel_values(&p, kind, u, v) {
            assert!(rel(k) <= 2e-14, "case {i}: kernel {k} vs {want}");
        }
    }
}

/// At `m = 0.001` and `theta_h = 1e-3` the exponent `tan^2(theta_h) / m^2` is about 1: the
/// textbook `(1 - cos^2) / cos^2` in `f64` keeps only about 10 of its digits (cos^2 is 1 -
/// 1e-6), the slopes keep all of them.
#[test]
fn no_cancellation_at_small_roughness() {
    let m = 0.001;
    let p = params(0.0, [1.0, m, m, 1.0, 0.0]);
    let (a, b): (f64, f64) = (0.3, 0.3 - 2e-3);
    let u = [a.sin(), 0.0, a.cos()];
    let v = [-b.sin(), 0.0, b.cos()];
    // h bisects u and v: theta_h = (a - b) / 2.
    let th = (a - b) / 2.0;
    let d = (-(th.tan() / m).powi(2)).exp() / (PI * m * m * th.cos().powi(4));
    let want = d / (4.0 * u[2] * v[2]); // G = 1, F = 1
    let got = p.value(u, v);
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    // The textbook order loses digits here (shown, not relied on).
    let hz = (u[2] + v[2]) / ((u[0] + v[0]).powi(2) + (u[2] + v[2]).powi(2)).sqrt();
    let naive_tan2 = (1.0 - hz * hz) / (hz * hz);
    let naive = (-naive_tan2 / (m * m)).exp() / (PI * m * m * hz.powi(4)) / (4.0 * u[2] * v[2]);
    eprintln!(
        "theta_h = 1e-3, m = 1e-3: ours {got:e}, accurate {want:e}, textbook order {naive:e} \
         (rel {:.1e})",
        (naive - want).abs() / want
    );
}

/// The horizon: a direction exactly on it gives the finite limit of `G / (4 uz vz)` (and
/// nearly the same value just above it); both on it, or one below, give 0.
#[test]
fn horizon_values() {
    let p = params(0.0, [1.0, 0.5, 0.5, 0.2, 0.0]);
    let v = sph(30.0, 180.0);
    let on = p.value([1.0, 0.0, 0.0], v);
    let e = 1e-9f64;
    let above = p.value([(1.0 - e * e).sqrt(), 0.0, e], v);
    assert!(on.is_finite() && on > 0.0);
    assert!((above - on).abs() <= 1e-8 * on, "{above} vs {on}");
    // Both on the horizon: D(h) is 0 (h on the horizon or sz = 0).
    assert_eq!(p.value([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), 0.0);
    assert_eq!(p.value([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]), 0.0);
    // One below the horizon.
    assert_eq!(p.value(sph(100.0, 0.0), sph(30.0, 180.0)), 0.0);
    // The columns there: E = -MAX, no NaN.
    let c = columns([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    assert!(c.iter().all(|x| !x.is_nan()) && c[LOG_GEOMETRY] == -f64::MAX);
}

/// Directions for the edge checks: uniform, grazing (1e-6 above the horizon and on it), the
/// normal, and the grazing mirror configuration.
fn edge_directions() -> DataSet {
    let mut rng = Pcg64Mcg::seed_from_u64(5);
    let mut d = DataSet::new();
    for _ in 0..200 {
        d.push(
            uniform_hemisphere(&mut rng),
            uniform_hemisphere(&mut rng),
            0.0,
        );
    }
    for k in 0..40 {
        let t: f64 = if k % 2 == 0 { 0.0 } else { 1e-6 };
        let (a, b) = (k as f64 * 0.7, k as f64 * 1.9);
        let (ct, st) = (t.cos(), t.sin());
        d.push(
            [ct * a.cos(), ct * a.sin(), st],
            [ct * b.cos(), ct * b.sin(), st],
            0.0,
        );
        d.push([ct * a.cos(), ct * a.sin(), st], sph(40.0, 77.0), 0.0);
    }
    d.push([0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 0.0);
    let g = 1e-6f64;
    d.push([g.cos(), 0.0, g.sin()], [-g.cos(), 0.0, g.sin()], 0.0);
    d
}

/// Every corner of the box (roughness 0.001 and 2.5, ks 0 and 10, f0 0 and 1, kd 0 and 1,
/// pan -90 and 90), both coordinates, every kernel: values and Jacobians finite, no NaN.
#[test]
fn finite_at_the_edges_of_the_box() {
    let data = edge_directions();
    let fam = family("cook-torrance").unwrap();
    for kind in [LobeKind::Isotropic, LobeKind::Anisotropic] {
        for coord in [ExponentCoord::Log1p, ExponentCoord::Raw] {
            let layout = Layout::builder_for(&fam, &[kind])
                .unwrap()
                .exponent_coord(coord)
                .build()
                .unwrap();
            let samples = layout.prepare(&data);
            let (lo, hi) = (layout.lower().to_vec(), layout.upper().to_vec());
            let dim = layout.dim();
            let m = data.len();
            for corner in 0..(1usize << dim) {
                let x: Vec<f64> = (0..dim)
                    .map(|j| if corner >> j & 1 == 1 { hi[j] } else { lo[j] })
                    .collect();
                for k in Kernel::available() {
                    let mut ev = Evaluator::with_kernel(&layout, k).unwrap();
                    let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * dim]);
                    let ok = ev.residuals_and_jacobian(&x, &samples, &mut r, &mut jac);
                    assert!(ok, "{kind:?} {coord:?} {k} at {x:?}");
                    assert!(r.iter().chain(&jac).all(|v| v.is_finite()));
                    assert!(r.iter().all(|&v| v >= 0.0), "{x:?}");
                }
                let p = layout.decode(&x);
                for i in 0..m {
                    let f = p.value(data.u(i), data.v(i));
                    assert!(f.is_finite() && f >= 0.0, "{x:?} sample {i}: {f}");
                }
            }
        }
    }
}
