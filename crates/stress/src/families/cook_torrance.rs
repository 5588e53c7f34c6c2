//! The Cook-Torrance lobe in double-double, written from the paper's formula in the textbook
//! order (the half vector normalised, `cos(theta_h)`, `tan^2(theta_h) = (1 - cos^2) / cos^2`,
//! the azimuth of `h` in the lobe's frame, the Beckmann `D`, the V-cavity `G`, Schlick's
//! Fresnel, then `ks D G F / (4 uz vz)`), independently of the kernels' slopes, logarithms
//! and `u.h = |u + v| / 2`.
//! Double-double keeps `1 - cos^2` exact enough even at the smallest roughness.

use crate::dd::{DD, DEG};

/// `pi` to double-double precision.
fn pi() -> DD {
    DD::new(std::f64::consts::PI) + DD::new(1.224_646_799_147_353_2e-16)
}

/// Fields: `ks, mx, my, f0, pan` (degrees).
pub(super) fn lobe(f: &[DD], u: [f64; 3], v: [f64; 3]) -> DD {
    let (ks, mx, my, f0, pan) = (f[0], f[1], f[2], f[3], f[4]);
    // The angle between the directions and h, `c = u.h = v.h`, of the directions normalised
    // ([`super::cos_half`]): the raw directions' `u.h` and `v.h` differ by up to 1e-10
    // relative near the grazing mirror configuration, and `1 - c` of the raw sum moves by
    // rounding of the lengths near retro-reflection.
    let c = super::cos_half(u, v);
    let u: [DD; 3] = u.map(DD::new);
    let v: [DD; 3] = v.map(DD::new);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    if s[2].hi <= 0.0 || len.hi <= 0.0 || u[2].hi < 0.0 || v[2].hi < 0.0 {
        // h on the horizon: D(h) is 0 (its limit); below the surface the model is 0.
        return DD::ZERO;
    }
    let h = [s[0] / len, s[1] / len, s[2] / len];
    let cos = h[2];
    let cos2 = cos * cos;
    let tan2 = (DD::ONE - cos2) / cos2;
    // The azimuth of h in the frame rotated by the pan angle, as cos^2 and sin^2.
    let (sp, cp) = (pan * DEG).sin_cos();
    let (hx, hy) = (cp * h[0] + sp * h[1], cp * h[1] - sp * h[0]);
    let r2 = hx * hx + hy * hy;
    let (c2, s2) = if r2.hi > 0.0 {
        (hx * hx / r2, hy * hy / r2)
    } else {
        (DD::ONE, DD::ZERO)
    };
    let e = -(tan2 * (c2 / (mx * mx) + s2 / (my * my)));
    let d = e.exp() / (pi() * mx * my * cos2 * cos2);
    let q = DD::ONE - c;
    let fresnel = f0 + (DD::ONE - f0) * q * q * q * q * q;
    // G / (4 uz vz); on the horizon (uz = 0 or vz = 0) its limit hz / (2 c max(uz, vz)).
    let g_over = if u[2].hi > 0.0 && v[2].hi > 0.0 {
        let gu = DD::new(2.0) * cos * u[2] / c;
        let gv = DD::new(2.0) * cos * v[2] / c;
        let mut g = DD::ONE;
        if gu < g {
            g = gu;
        }
        if gv < g {
            g = gv;
        }
        g / (DD::new(4.0) * u[2] * v[2])
    } else {
        let other = if u[2].hi > 0.0 { u[2] } else { v[2] };
        cos / (DD::new(2.0) * c * other)
    };
    ks * d * fresnel * g_over
}

/// The lobe's condition ([`super::LobeCondition`]): the exponent's, `2 (|s'x| A_x / mx^2 +
/// |s'y| A_y / my^2)` for the slopes `s = (u + v) / (uz + vz)` rotated by the pan angle
/// ([`super::rotated_condition`]), plus the magnitude of the prepared logarithms
/// `|ln(G / (4 uz vz))| + 2 ln(1 + tan^2(theta_h))` (each good to a few ulps of itself).
pub(super) fn condition(f: &[f64], u: [f64; 3], v: [f64; 3]) -> f64 {
    let (mx, my, pan) = (f[1], f[2], f[4]);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    if !(u[2] >= 0.0 && v[2] >= 0.0 && s[2] > 0.0) {
        return 0.0;
    }
    let (px, py) = (s[0] / s[2], s[1] / s[2]);
    let tan2 = px * px + py * py;
    let (lo, hi) = (u[2].min(v[2]), u[2].max(v[2]));
    let q = 4.0 * s[2] / (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    let w = (q * lo).min(1.0) / (4.0 * lo * hi);
    let ln_w = if w.is_finite() {
        w.ln()
    } else {
        (q / (4.0 * hi)).ln()
    };
    super::rotated_condition(px, py, pan, 1.0 / (mx * mx), 1.0 / (my * my))
        + ln_w.abs()
        + 2.0 * tan2.ln_1p()
}
