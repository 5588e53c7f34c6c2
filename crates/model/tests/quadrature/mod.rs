//! Quadrature over the hemisphere for the families' normalisation and albedo tests: composite
//! Gauss-Legendre in the polar angle (on panels that follow the lobe's width, or uniform), the
//! periodic trapezoid rule in the azimuth (exponentially accurate for smooth periodic
//! integrands).

// Each test crate that includes this module uses part of it.
#![allow(dead_code)]

use std::f64::consts::PI;

/// Gauss-Legendre nodes and weights of order `n` on [-1, 1] (Newton's iteration on the
/// Legendre polynomial from the usual cosine guesses).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p1, mut p2) = (1.0, 0.0);
            for j in 1..=n {
                let p3 = p2;
                p2 = p1;
                p1 = ((2 * j - 1) as f64 * x * p2 - (j - 1) as f64 * p3) / j as f64;
            }
            dp = n as f64 * (x * p1 - p2) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// Panel ends in the polar angle for a lobe of angular width about `width` (radians):
/// `0`, then `atan(width 2^k)` for `k = -4, -3, ...` while below `atan(1e8)`, then `pi / 2`.
pub fn panels(width: f64) -> Vec<f64> {
    let mut ends = vec![0.0];
    let mut t = width / 16.0;
    while t < 1e8 {
        ends.push(t.atan());
        t *= 2.0;
    }
    ends.push(PI / 2.0);
    ends
}

/// `int_0^{pi/2} int_0^{2 pi} g(w) sin(theta) dphi dtheta` for a unit vector `w` at polar angle
/// `theta` and azimuth `phi`: `phis` azimuths, 32 Gauss-Legendre nodes per panel of
/// [`panels`]`(width)`.
pub fn hemisphere(width: f64, phis: usize, mut g: impl FnMut([f64; 3]) -> f64) -> f64 {
    let gl = gauss_legendre(32);
    let ends = panels(width);
    let mut total = 0.0;
    for w in ends.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        for &(x, wt) in &gl {
            let theta = mid + half * x;
            let (st, ct) = theta.sin_cos();
            let mut ring = 0.0;
            for k in 0..phis {
                let phi = 2.0 * PI * (k as f64 + 0.5) / phis as f64;
                let (sp, cp) = phi.sin_cos();
                ring += g([st * cp, st * sp, ct]);
            }
            total += half * wt * st * ring * (2.0 * PI / phis as f64);
        }
    }
    total
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
