//! The normalised Blinn-Phong lobe in double-double, written from the formula
//! `ks (p + 8) / (8 pi) (n.h)^p` in the textbook order (the half vector normalised, `n.h` its
//! z component, the power as `exp(p ln(n.h))`), independently of the kernels' `ln(1 + tan^2)`.

use crate::dd::DD;

/// Fields: `ks, p`.
pub(super) fn lobe(f: &[DD], u: [f64; 3], v: [f64; 3]) -> DD {
    let (ks, p) = (f[0], f[1]);
    let u: [DD; 3] = u.map(DD::new);
    let v: [DD; 3] = v.map(DD::new);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let pi = DD::new(std::f64::consts::PI) + DD::new(1.224_646_799_147_353_2e-16);
    let norm = (p + DD::new(8.0)) / (DD::new(8.0) * pi);
    let power = if s[2].hi > 0.0 && len.hi > 0.0 {
        (p * (s[2] / len).ln()).exp()
    } else if p.hi == 0.0 {
        // 0^0 = 1: the constant lobe.
        DD::ONE
    } else {
        DD::ZERO
    };
    ks * norm * power
}

/// The lobe's condition ([`super::LobeCondition`]): `|p ln(n.h)|`, the exponent, whose
/// factors are each good to a few ulps (`p` from its coordinate, the prepared `ln(n.h)`).
pub(super) fn condition(f: &[f64], u: [f64; 3], v: [f64; 3]) -> f64 {
    let p = f[1];
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    if p == 0.0 || s[2] <= 0.0 {
        return 0.0;
    }
    let ln_hz = s[2].ln() - 0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).ln();
    (p * ln_hz).abs()
}
