//! The parameter-independent geometry the microfacet-style families share: the directions and
//! the half vector, as prepared columns.

use crate::lobes::Math;

/// Column of `u`'s x component; `u` takes columns `U..U + 3`.
pub const U: usize = 0;
/// First column of `v`.
pub const V: usize = 3;
/// First column of the unit half vector `h = (u + v) / |u + v|`.
pub const H: usize = 6;
/// Column of `1 - u . h` (`u . h = v . h`), computed without cancellation (see
/// [`one_minus_cos_half`]): Schlick's Fresnel term raises it to the fifth power.
pub const ONE_MINUS_UH: usize = 9;
/// Column of `u . h` itself ([`cos_half`]): with [`ONE_MINUS_UH`] it gives the derivative of
/// Schlick's term by `f0`, `1 - (1 - u.h)^5`, without cancellation ([`one_minus_pow5`]).
pub const UH: usize = 10;
/// The number of columns [`half_vector_columns`] writes.
pub const COLUMNS: usize = 11;

/// Writes `u`, `v`, the unit half vector, `1 - u . h` and `u . h` into `cols` (at least
/// [`COLUMNS`] long).
/// For `v = -u` (no half vector; impossible for two directions above the surface) `h` is the
/// normal.
pub fn half_vector_columns(u: [f64; 3], v: [f64; 3], cols: &mut [f64]) {
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let h = if len > 0.0 {
        [s[0] / len, s[1] / len, s[2] / len]
    } else {
        [0.0, 0.0, 1.0]
    };
    cols[U..U + 3].copy_from_slice(&u);
    cols[V..V + 3].copy_from_slice(&v);
    cols[H..H + 3].copy_from_slice(&h);
    cols[ONE_MINUS_UH] = one_minus_cos_half(u, v);
    cols[UH] = cos_half(u, v);
}

/// `1 - q^5` for `q = 1 - c`, from both (each accurate where it is small, as [`cos_half`] and
/// [`one_minus_cos_half`] are): `c (1 + q + q^2 + q^3 + q^4)`, a sum of positive terms, good
/// to a few ulps for every `c` in [0, 1]. This is `d F / d f0` of Schlick's
/// `F = f0 + (1 - f0) q^5`; `1 - q^5` itself cancels where `c` is small (near grazing
/// back-scatter, where some lobes are largest), losing `eps / (5 c)` relative.
#[inline(always)]
pub fn one_minus_pow5<M: Math>(c: f64, q: f64) -> f64 {
    c * M::mad(q, M::mad(q, M::mad(q, q + 1.0, 1.0), 1.0), 1.0)
}

/// `1 - u . h` for unit `u`, `v` and `h = (u + v) / |u + v|`: since `u . h = |u + v| / 2` and
/// `|u + v|^2 + |u - v|^2 = 4`, it is `|u - v|^2 / (2 (2 + |u + v|))`, which keeps its digits
/// where `u` and `v` are close (retro-reflection), where `1 - |u + v| / 2` cancels (the
/// Fresnel term `(1 - u.h)^5` at `f0 = 0` was then off by 1e-12 relative). In [0, 1].
pub fn one_minus_cos_half(u: [f64; 3], v: [f64; 3]) -> f64 {
    let s2 = (u[0] + v[0]).powi(2) + (u[1] + v[1]).powi(2) + (u[2] + v[2]).powi(2);
    let d2 = (u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2) + (u[2] - v[2]).powi(2);
    (d2 / (2.0 * (2.0 + s2.sqrt()))).clamp(0.0, 1.0)
}

/// `u . h` (`= v . h`) for unit `u`, `v` and `h = (u + v) / |u + v|`: `|u + v| / 2`, symmetric
/// in `u` and `v` and accurate to rounding where it is small (near the grazing back-scatter
/// configuration, `v` near `-u`), where `1 - (1 - u.h)` loses its digits, and where the dot
/// products `u . h` and `v . h` of directions that are unit only to rounding differ by
/// `(|u|^2 - |v|^2) / (2 |u + v|)`. In [0, 1] (up to rounding).
pub fn cos_half(u: [f64; 3], v: [f64; 3]) -> f64 {
    let s2 = (u[0] + v[0]).powi(2) + (u[1] + v[1]).powi(2) + (u[2] + v[2]).powi(2);
    0.5 * s2.sqrt()
}

/// The in-plane components `(x', y')` of `(x, y)` in a frame rotated by the pan angle
/// (`cos p`, `sin p`): `x' = cos(p) x + sin(p) y`, `y' = -sin(p) x + cos(p) y`, as in the
/// Lafortune family.
#[inline(always)]
pub fn rotate(c: f64, s: f64, x: f64, y: f64) -> (f64, f64) {
    (c * x + s * y, c * y - s * x)
}

/// `(sin, cos)` of an angle in degrees in [-180, 180], with the cosine exact to rounding near
/// 90 degrees: there `90 - |a|` is exact and its sine is taken instead, where
/// `cos(a * pi / 180)` would carry the `6e-17` of `pi / 2`'s rounding. A narrow lobe turned by
/// 90 degrees has rotated slopes far below the unrotated ones, and a Gaussian lobe exponents
/// in the hundreds, so that absolute error costs up to 1e-12 of relative value.
pub fn sin_cos_deg(a: f64) -> (f64, f64) {
    const DEG: f64 = std::f64::consts::PI / 180.0;
    if a.abs() <= 45.0 {
        (a * DEG).sin_cos()
    } else {
        let (s, c) = ((90.0 - a.abs()) * DEG).sin_cos();
        (c.copysign(a), s)
    }
}
