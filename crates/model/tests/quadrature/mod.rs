//! Quadrature over the hemisphere of half vectors, shared by the family tests that check a
//! lobe's normalisation or albedo: composite Gauss-Legendre in the polar angle, the
//! (spectrally accurate) periodic trapezoid rule in the azimuth.

// Each test crate that includes this module uses part of it.
#![allow(dead_code)]

use std::f64::consts::PI;

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton's method on the Legendre polynomial
/// from the Chebyshev guesses; converges to rounding for the orders used here).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// `int_a^b g(t) dt` by `panels` equal panels of 8-point Gauss-Legendre.
pub fn integrate(a: f64, b: f64, panels: usize, mut g: impl FnMut(f64) -> f64) -> f64 {
    let nodes = gauss_legendre(8);
    let w = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let lo = a + w * p as f64;
        for &(x, wt) in &nodes {
            sum += wt * 0.5 * w * g(lo + 0.5 * w * (x + 1.0));
        }
    }
    sum
}

/// `int g(h) dw_h` over the half vectors with polar angle in `[0, theta_max]` (a hemisphere
/// for `pi/2`): `panels` Gauss-Legendre panels in the polar angle, `azimuths` trapezoid
/// points in the azimuth.
pub fn over_half_vectors(
    theta_max: f64,
    panels: usize,
    azimuths: usize,
    mut g: impl FnMut([f64; 3]) -> f64,
) -> f64 {
    let dphi = 2.0 * PI / azimuths as f64;
    integrate(0.0, theta_max, panels, |t| {
        let (st, ct) = t.sin_cos();
        let ring: f64 = (0..azimuths)
            .map(|k| {
                let (sp, cp) = (dphi * k as f64).sin_cos();
                g([st * cp, st * sp, ct])
            })
            .sum();
        ring * dphi * st
    })
}

/// The exitant direction whose half vector with `u` is `h`: `v = 2 (u.h) h - u`.
pub fn reflect(u: [f64; 3], h: [f64; 3]) -> [f64; 3] {
    let d = u[0] * h[0] + u[1] * h[1] + u[2] * h[2];
    [
        2.0 * d * h[0] - u[0],
        2.0 * d * h[1] - u[1],
        2.0 * d * h[2] - u[2],
    ]
}

/// `int f(u, v) vz dw_v` over the exitant hemisphere, as an integral over half vectors
/// (`dw_v = 4 (u.h) dw_h`; half vectors whose `v` falls below the horizon contribute 0).
pub fn albedo(
    u: [f64; 3],
    panels: usize,
    azimuths: usize,
    f: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> f64 {
    over_half_vectors(PI / 2.0, panels, azimuths, |h| {
        let v = reflect(u, h);
        let uh = u[0] * h[0] + u[1] * h[1] + u[2] * h[2];
        if v[2] <= 0.0 || uh <= 0.0 {
            0.0
        } else {
            f(u, v) * v[2] * 4.0 * uh
        }
    })
}
