//! The Ashikhmin-Shirley lobe in double-double, written from the paper's formula in the
//! textbook order (Ashikhmin and Shirley 2000, the specular term with Schlick's Fresnel and a
//! separate scale `ks`), independently of the kernels' rearrangements (the prepared
//! `ln(hz) / (hx^2 + hy^2)`, the cut of `exp` below -700; `u.h` of the directions
//! normalised, [`super::cos_half`]):
//!
//! `ks sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^e F(u.h) / ((u.h) max(uz, vz))`,
//! `e = (nu (h.t)^2 + nv (h.b)^2) / (1 - (n.h)^2)`, `F(c) = f0 + (1 - f0)(1 - c)^5`,
//! with `t`, `b` the lobe's tangent frame rotated by the pan angle.
//!
//! The family's stated value where the formula has none: 0 when both directions lie on the
//! horizon (`max(uz, vz) = 0`).

use crate::dd::{DD, DEG};

/// Fields: `ks, nu, nv, f0, pan` (degrees).
pub(super) fn lobe(f: &[DD], u: [f64; 3], v: [f64; 3]) -> DD {
    let (ks, nu, nv, f0, pan) = (f[0], f[1], f[2], f[3], f[4]);
    if u[2].max(v[2]) <= 0.0 {
        return DD::ZERO;
    }
    let uh = super::cos_half(u, v);
    let u: [DD; 3] = u.map(DD::new);
    let v: [DD; 3] = v.map(DD::new);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let h = [s[0] / len, s[1] / len, s[2] / len];
    let (sin, cos) = (pan * DEG).sin_cos();
    let ht = cos * h[0] + sin * h[1];
    let hb = cos * h[1] - sin * h[0];
    let nh = h[2];
    let one_minus = DD::ONE - nh * nh;
    // At the peak (n.h = 1) the power is 1 whatever the exponent.
    let power = if one_minus.hi <= 0.0 {
        DD::ONE
    } else {
        let e = (nu * ht * ht + nv * hb * hb) / one_minus;
        (e * nh.ln()).exp()
    };
    let q = DD::ONE - uh;
    let fresnel = f0 + (DD::ONE - f0) * q * q * q * q * q;
    let pi = DD::new(std::f64::consts::PI) + DD::new(1.224_646_799_147_353_2e-16);
    let norm = ((nu + DD::ONE) * (nv + DD::ONE)).sqrt() / (DD::new(8.0) * pi);
    let m = if u[2] > v[2] { u[2] } else { v[2] };
    ks * norm * power * fresnel / (uh * m)
}

/// The lobe's condition ([`super::LobeCondition`]): the exponent's, `2 |g| (nu |h'x| A_x +
/// nv |h'y| A_y)` for `(nu h'x^2 + nv h'y^2) g`, `g = ln(hz) / (hx^2 + hy^2)`, with the half
/// vector's components rotated by the pan angle ([`super::rotated_condition`]; `2 |n ln(hz)|`
/// for an isotropic lobe).
pub(super) fn condition(f: &[f64], u: [f64; 3], v: [f64; 3]) -> f64 {
    let (nu, nv, pan) = (f[1], f[2], f[4]);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    if !(len > 0.0 && s[2] > 0.0) {
        return 0.0;
    }
    let h = s.map(|c| c / len);
    let r2 = h[0] * h[0] + h[1] * h[1];
    if r2 == 0.0 {
        return 0.0;
    }
    let ln_hz = if r2 < 0.5 {
        0.5 * (-r2).ln_1p()
    } else {
        h[2].ln()
    };
    let g = ln_hz / r2;
    super::rotated_condition(h[0], h[1], pan, nu * g.abs(), nv * g.abs())
}
