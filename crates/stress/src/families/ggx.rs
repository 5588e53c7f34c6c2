//! The GGX lobe in double-double, written from the formula in `brdf_model::models::ggx` (the
//! textbook order of operations: the half vector normalised here, the rotation by the pan
//! angle, `D`, the separable Smith `G1` and Schlick's Fresnel), independently of the kernels'
//! rearrangements; `u.h` of the directions normalised ([`super::cos_half`]).

use crate::dd::{DD, DEG};

/// Fields: `ks, ax, ay, f0, pan` (degrees).
pub(super) fn lobe(f: &[DD], u: [f64; 3], v: [f64; 3]) -> DD {
    let (ks, ax, ay, f0, pan) = (f[0], f[1], f[2], f[3], f[4]);
    let uh = super::cos_half(u, v);
    let u: [DD; 3] = u.map(DD::new);
    let v: [DD; 3] = v.map(DD::new);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let h = [s[0] / len, s[1] / len, s[2] / len];
    let (sin, cos) = (pan * DEG).sin_cos();
    let rot = |w: &[DD; 3]| (cos * w[0] + sin * w[1], cos * w[1] - sin * w[0]);
    let (hx, hy) = rot(&h);
    let t = hx * hx / (ax * ax) + hy * hy / (ay * ay) + h[2] * h[2];
    let pi = DD::new(std::f64::consts::PI) + DD::new(1.224_646_799_147_353_2e-16);
    let d = DD::ONE / (pi * ax * ay * t * t);
    let g1_over_cos = |w: &[DD; 3]| {
        let (wx, wy) = rot(w);
        let l = (w[2] * w[2] + ax * ax * wx * wx + ay * ay * wy * wy).sqrt();
        DD::new(2.0) / (w[2] + l)
    };
    let q = DD::ONE - uh;
    let q5 = q * q * q * q * q;
    let fresnel = f0 + (DD::ONE - f0) * q5;
    ks * d * fresnel * g1_over_cos(&u) * g1_over_cos(&v) / 4.0
}

/// The lobe's condition ([`super::LobeCondition`]): `2 t_abs / t` for `D`'s `t^-2`, with
/// `t = h'x^2 / ax^2 + h'y^2 / ay^2 + hz^2` and `t_abs` its rotated sum's condition
/// ([`super::rotated_condition`]) plus `hz^2`, and `q_abs / (2 l (wz + l))` for each masking
/// factor `2 / (wz + l)`, `l = sqrt(q)`, `q = ax^2 w'x^2 + ay^2 w'y^2 + wz^2`.
pub(super) fn condition(f: &[f64], u: [f64; 3], v: [f64; 3]) -> f64 {
    let (ax, ay, pan) = (f[1], f[2], f[4]);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    if len == 0.0 {
        return 0.0;
    }
    let h = s.map(|c| c / len);
    let (sn, cs) = pan.to_radians().sin_cos();
    let rot = |w: [f64; 3]| (cs * w[0] + sn * w[1], cs * w[1] - sn * w[0]);
    let (hx, hy) = rot(h);
    let t = hx * hx / (ax * ax) + hy * hy / (ay * ay) + h[2] * h[2];
    let t_abs =
        super::rotated_condition(h[0], h[1], pan, 1.0 / (ax * ax), 1.0 / (ay * ay)) + h[2] * h[2];
    let mut kappa = 2.0 * t_abs / t;
    for w in [u, v] {
        let (wx, wy) = rot(w);
        let q = ax * ax * wx * wx + ay * ay * wy * wy + w[2] * w[2];
        let l = q.sqrt();
        if l > 0.0 {
            let q_abs = super::rotated_condition(w[0], w[1], pan, ax * ax, ay * ay) + w[2] * w[2];
            kappa += q_abs / (2.0 * l * (w[2] + l));
        }
    }
    kappa
}
