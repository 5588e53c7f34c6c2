//! Normalised Blinn-Phong: the approximate energy normalisation `(p + 8) / (8 pi)` by
//! quadrature through every kernel, values computed by hand, the sharpest lobe in the box,
//! and the horizon and the box's edges (finite values and Jacobians, no NaN).

// Expected values are mpmath's digits as printed, some beyond f64's precision.
#![allow(clippy::excessive_precision)]

mod quadrature;

use brdf_model::models::blinn_phong::ln_cos_h;
use brdf_model::{
    DataSet, Evaluator, ExponentCoord, Kernel, Layout, LobeKind, Params, family, uniform_hemisphere,
};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::f64::consts::PI;

fn params(kd: f64, ks: f64, p: f64) -> Params {
    Params::new(family("blinn-phong").unwrap(), vec![kd], vec![vec![ks, p]]).unwrap()
}

fn layout(coord: ExponentCoord) -> Layout {
    Layout::builder_for(&family("blinn-phong").unwrap(), &[LobeKind::Isotropic])
        .unwrap()
        .exponent_coord(coord)
        .build()
        .unwrap()
}

/// The values of `p` at `data`'s directions by kernel `k` (residuals against `data`'s values,
/// which are 0 here).
fn kernel_values(p: &Params, data: &DataSet, k: Kernel) -> Vec<f64> {
    let layout = layout(ExponentCoord::Log1p);
    let samples = layout.prepare(data);
    let x = layout.encode(p.clone());
    let mut ev = Evaluator::with_kernel(&layout, k).unwrap();
    let mut r = vec![0.0; data.len()];
    assert!(ev.residuals(&x, &samples, &mut r), "{k}");
    r
}

/// The directional albedo at normal view, `A(p) = int f(l, n) (n.l) dw_l` with `ks = 1`, has
/// the closed form `(p + 8) (p + 2^(-p/2)) / ((p + 2) (p + 4))` (with `v = n`, `n.h =
/// cos(theta_l / 2)`; substitute `c = cos(theta_l / 2)`), which lies in [1, 1.075202]: the
/// normalisation conserves energy at normal view to within 7.6%, exactly at `p = 0` and as
/// `p` grows. Quadrature (32-point Gauss-Legendre on panels in `theta_l` following the lobe's
/// width `2 / sqrt(p + 1)`, 4 azimuths) through every kernel agrees with the closed form;
/// measured (2026-12-07) within 3.3e-15 for every `p` and kernel; the tolerance is 1e-12.
#[test]
fn albedo_at_normal_view_matches_the_closed_form() {
    let n = [0.0, 0.0, 1.0];
    let mut worst = 0.0f64;
    for p in [0.0, 1.0, 2.0, 8.76, 100.0, 1e4, 1e6] {
        let closed = (p + 8.0) * (p + (-p / 2.0f64).exp2()) / ((p + 2.0) * (p + 4.0));
        assert!((1.0..=1.075_202).contains(&closed), "p = {p}: {closed}");
        let width = 2.0 / (p + 1.0f64).sqrt();
        // First pass: the quadrature's directions; then the values by each kernel, in order.
        let mut data = DataSet::new();
        quadrature::hemisphere(width, 4, |l| {
            data.push(l, n, 0.0);
            0.0
        });
        let bp = params(0.0, 1.0, p);
        for k in Kernel::available() {
            let values = kernel_values(&bp, &data, k);
            let mut it = values.iter();
            let integral = quadrature::hemisphere(width, 4, |l| it.next().unwrap() * l[2]);
            worst = worst.max((integral - closed).abs());
            assert!(
                (integral - closed).abs() <= 1e-12,
                "p = {p}, {k}: {integral} vs {closed}"
            );
            eprintln!("p = {p}, {k}: A = {integral:.16} (closed form {closed:.16})");
        }
    }
    eprintln!(
        "Blinn-Phong albedo at normal view: largest |quadrature - closed form| = {worst:.1e}"
    );
}

fn sph(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    [st * cp, st * sp, ct]
}

/// Values computed by hand (mpmath at 50 digits, from the exact angles).
#[test]
fn hand_computed_values() {
    let cases = [
        // u = v = n: 0.05 + 0.5 (10 + 8) / (8 pi) = 0.05 + 9 / (8 pi) = 0.40809862195676451.
        (
            0.05,
            0.5,
            10.0,
            sph(0.0, 0.0),
            sph(0.0, 0.0),
            0.408_098_621_956_764_51,
        ),
        // u at (60, 0), v at (30, 180): theta_h = 15 degrees, n.h = 0.965925826289068;
        // 0.01 + 0.2 (108 / (8 pi)) 0.965925826289068^100 = 0.036828210282761516.
        (
            0.01,
            0.2,
            100.0,
            sph(60.0, 0.0),
            sph(30.0, 180.0),
            0.036_828_210_282_761_516,
        ),
        // u at (50, 10), v at (40, 200): n.h = 0.992489346752518;
        // (1008 / (8 pi)) 0.992489346752518^1000 = 0.021334107243530150.
        (
            0.0,
            1.0,
            1000.0,
            sph(50.0, 10.0),
            sph(40.0, 200.0),
            0.021_334_107_243_530_150,
        ),
    ];
    for (i, (kd, ks, p, u, v, want)) in cases.into_iter().enumerate() {
        let bp = params(kd, ks, p);
        let rel = |a: f64| (a - want).abs() / want;
        assert!(rel(bp.value(u, v)) <= 1e-13, "case {i}: {}", bp.value(u, v));
        assert!(rel(bp.value(v, u)) <= 1e-13, "case {i} swapped");
        let mut data = DataSet::new();
        data.push(u, v, 0.0);
        for k in Kernel::available() {
            let got = kernel_values(&bp, &data, k)[0];
            assert!(rel(got) <= 1e-13, "case {i} {k}: {got}");
        }
    }
}

/// The sharpest lobe of the box, `p = 1e6`, at `theta_h = 1e-3`: `p ln(n.h) = -0.5000000833`
/// is what matters, and `ln(n.h) = -ln(1 + tan^2) / 2` keeps its digits (mpmath: the value is
/// `(1e6 + 8) / (8 pi) cos(1e-3)^1e6 = 24133.279211111516`).
#[test]
fn sharpest_lobe_keeps_its_digits() {
    let (a, b): (f64, f64) = (0.3, 0.3 - 2e-3);
    let u = [a.sin(), 0.0, a.cos()];
    let v = [-b.sin(), 0.0, b.cos()];
    // theta_h = (a - b) / 2 as the f64 directions have it (a - b is exact here).
    let th = (a - b) / 2.0;
    let want = (1e6 + 8.0) / (8.0 * PI) * (-0.5e6 * th.tan().powi(2).ln_1p()).exp();
    let bp = params(0.0, 1.0, 1e6);
    let got = bp.value(u, v);
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    assert!((got - 24133.279211111516).abs() <= 1e-9 * want, "{got}");
}

/// The horizon: where `hz = 0` the lobe is `0^p`: 0 for `p > 0`, `ks / pi` for `p = 0`; the
/// column is `-f64::MAX`, never NaN; just above, the value is continuous.
#[test]
fn horizon_values() {
    let (u, v) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    assert_eq!(ln_cos_h(u, v), -f64::MAX);
    assert_eq!(params(0.1, 2.0, 5.0).value(u, v), 0.1);
    assert_eq!(params(0.1, 2.0, 0.0).value(u, v), 0.1 + 2.0 / PI);
    // 1e-200 above the horizon: ln(n.h) directly (tan^2 would overflow).
    let e = 1e-200;
    let l = ln_cos_h([1.0, 0.0, e], [0.0, 1.0, e]);
    assert!(
        (l - (2e-200f64 / 2f64.sqrt()).ln()).abs() <= 1e-13 * l.abs(),
        "{l}"
    );
}

/// Every corner of the box (`p` 0 and 1e6, `ks` 0 and 10, `kd` 0 and 1), both coordinates,
/// every kernel, at uniform, grazing and on-horizon directions: values and Jacobians finite,
/// no NaN.
#[test]
fn finite_at_the_edges_of_the_box() {
    let mut rng = Pcg64Mcg::seed_from_u64(9);
    let mut data = DataSet::new();
    for k in 0..300 {
        let u = uniform_hemisphere(&mut rng);
        let mut v = uniform_hemisphere(&mut rng);
        if k % 3 == 0 {
            let t: f64 = if k % 2 == 0 { 0.0 } else { 1e-6 };
            let a = k as f64;
            v = [t.cos() * a.cos(), t.cos() * a.sin(), t.sin()];
        }
        data.push(u, v, 0.0);
    }
    data.push([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.0);
    data.push([0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 0.0);
    for coord in [ExponentCoord::Log1p, ExponentCoord::Raw] {
        let layout = layout(coord);
        let samples = layout.prepare(&data);
        let (lo, hi) = (layout.lower().to_vec(), layout.upper().to_vec());
        let (dim, m) = (layout.dim(), data.len());
        for corner in 0..(1usize << dim) {
            let x: Vec<f64> = (0..dim)
                .map(|j| if corner >> j & 1 == 1 { hi[j] } else { lo[j] })
                .collect();
            let p = layout.decode(&x);
            // At p = 0 the exponent's derivative at hz = 0 is -inf (0^p): that sample's
            // Jacobian is left out there.
            let p_zero = p.lobe(0)[1] == 0.0;
            for k in Kernel::available() {
                let mut ev = Evaluator::with_kernel(&layout, k).unwrap();
                let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * dim]);
                ev.residuals_and_jacobian(&x, &samples, &mut r, &mut jac);
                assert!(r.iter().all(|v| v.is_finite() && *v >= 0.0), "{x:?} {k}");
                for (i, v) in jac.iter().enumerate() {
                    let horizon = i % m == m - 2;
                    assert!(!v.is_nan(), "{x:?} {k}: {i}");
                    assert!(v.is_finite() || (p_zero && horizon), "{x:?} {k}: {i} {v}");
                }
            }
            for i in 0..m {
                let f = p.value(data.u(i), data.v(i));
                assert!(f.is_finite() && f >= 0.0, "{x:?} sample {i}: {f}");
            }
        }
    }
}
