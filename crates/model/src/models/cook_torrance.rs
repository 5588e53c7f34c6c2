//! Cook-Torrance microfacet lobes: Cook and Torrance, "A Reflectance Model for Computer
//! Graphics" (ACM Transactions on Graphics 1(1), 1982), with the Beckmann distribution
//! normalised as a microfacet distribution (as in Walter, Marschner, Li and Torrance, EGSR
//! 2007, and in Ngan, Durand and Matusik's fits, EGSR 2005), its anisotropic form with two
//! roughnesses along the axes of the lobe's frame (Ward, SIGGRAPH 1992; Walter et al. 2007),
//! the paper's V-cavity masking term, and Schlick's Fresnel approximation (Schlick 1994).
//!
//! One lobe, with `h = (u + v) / |u + v|`, `theta_h` its angle to the normal and `x'`, `y'`
//! components in the lobe's frame rotated by the pan angle (as in the Lafortune family):
//!
//! `lobe = ks D(h) F(u.h) G(u, v) / (4 uz vz)`
//! - `D(h) = exp(-tan^2(theta_h) (cos^2(phi_h) / mx^2 + sin^2(phi_h) / my^2)) /
//!   (pi mx my cos^4(theta_h))`, `phi_h` the azimuth of `h` in the rotated frame; with
//!   `mx = my = m` it is the paper's `exp(-tan^2(theta_h)/m^2) / (m^2 cos^4(theta_h))` divided
//!   by `pi`, so that `D(h) hz` integrates to 1 over the hemisphere (tested by quadrature);
//! - `G = min(1, 2 hz uz / (u.h), 2 hz vz / (u.h))`, the V-cavity term of the paper (Torrance
//!   and Sparrow's), with no parameter;
//! - `F(c) = f0 + (1 - f0) (1 - c)^5`, `c = u.h` (equal to `v.h`).
//!
//! This is Walter's form `ks D G F / (4 uz vz)`; the paper writes `F D G / (pi uz vz)` with an
//! unnormalised `D`, which is this lobe with `ks = 4 / pi` times the paper's scale (Ngan's fits
//! are converted by `brdf_published::NganCookTorrance`).
//!
//! # Fields and bounds
//! - `ks` in [0, 10]: the scale (as GGX's); the published fits reach 1.25 (`4 albedo / pi`).
//! - `mx`, `my` in [0.001, 2.5]: Beckmann's roughness (the RMS slope of the microfacets) along
//!   `x'` and `y'`; the same box as GGX's roughness. Ngan's fits lie in [0.00512, 0.943], Löw's
//!   reach 2.09; below 0.001 the lobe is narrower than any measurement resolves.
//! - `f0` in [0, 1]: the Fresnel reflectance at normal incidence (optional, default 1: no
//!   Fresnel effect); Ngan's `eta` lies in [0.00173, 0.999].
//! - `pan` in [-90, 90] degrees (optional, default 0): the rotation of the lobe's frame.
//!
//! An anisotropic lobe fits `ks`, `mx`, `my`, `f0` and `pan`; an isotropic lobe fits `ks`, `m`
//! (setting `mx = my`) and `f0`, with no rotation work. The roughnesses are shape parameters
//! ([`Role::Shape`]) seen by the optimiser as `ln m` ([`Coord::Log`]) unless the spec says
//! `exponent = "raw"` (docs/model.md gives the measurement behind the default).
//!
//! # Numerics
//! Everything that does not depend on the parameters is prepared once per sample, from
//! `s = u + v` (no normalised `h` is needed):
//! - the slopes `s'x / sz`, `s'y / sz` (`tan(theta_h)` along each axis) and `tan^2(theta_h)`:
//!   computed from the components, the exponent has no cancellation at small roughness, where
//!   the textbook `(1 - cos^2) / cos^2` loses every digit of a small angle;
//! - `E = ln(G / (4 uz vz)) + 2 ln(1 + tan^2(theta_h))`, the logarithm of the V-cavity factor
//!   and of `1 / cos^4(theta_h)`. The V-cavity factor is computed as `min(1, q lo) / (4 lo hi)`
//!   with `lo`, `hi` the smaller and larger of `uz`, `vz` and `q = 2 hz / (u.h) = 4 sz / |s|^2`
//!   (since `u.h = |s| / 2` for unit vectors), i.e. `1 / (4 lo hi)` or `q / (4 hi)`: no 0/0 at
//!   the horizon (at `uz = 0` it is the finite limit `hz / (2 (u.h) vz)`);
//! - `1 - u.h = |u - v|^2 / (2 (2 + |s|))` (accurate near retro-reflection, for Schlick's
//!   `(1 - u.h)^5`) and `u.h = |s| / 2` (symmetric in `u` and `v`, accurate near grazing
//!   back-scatter, for the derivative by `f0`, `1 - (1 - u.h)^5 = u.h (1 + q + ... + q^4)`,
//!   which as `1 - q^5` would cancel there).
//!
//! The lobe is then `ks F(u.h) exp(E - T) / (pi mx my)`, `T = s'x^2 / (mx^2 sz^2) + s'y^2 /
//! (my^2 sz^2)`: one `exp` per sample, which [`Math::exp_cut`] takes as 0 below `e^-690`
//! (the tails, identically in every kernel). Where `sz < 1e-100` (both directions within
//! 1e-100 of the horizon) or a direction is below the horizon the lobe is 0: there `D`
//! underflows to 0 for every roughness in the box, except within 1e-100 rad of the grazing
//! mirror configuration (`v = -u` on the horizon), where the model diverges. Elsewhere
//! `ln(G / (4 uz vz)) <= 461` (from `sz >= 1e-100`) and `2 ln(1 + t) - t / 2.5^2 <= 3.2`, so
//! `E - T <= 465`: no value in the box overflows (at most about `5e208`) and none is NaN.

use super::geometry::{rotate, sin_cos_deg};
use crate::family::{Coord, FieldDef, ParamDef, Role};
use crate::lobes::{LobeShape, MAX_COLUMNS, MAX_FIELDS, Math};

/// The family's name.
pub const NAME: &str = "cook-torrance";

/// Bounds of `ks`.
pub const KS_BOUNDS: (f64, f64) = (0.0, 10.0);
/// Bounds of the roughnesses `mx`, `my`.
pub const M_BOUNDS: (f64, f64) = (0.001, 2.5);
/// Bounds of `f0`.
pub const F0_BOUNDS: (f64, f64) = (0.0, 1.0);
/// Bounds of the pan angle, degrees.
pub const PAN_BOUNDS: (f64, f64) = (-90.0, 90.0);

const KS: usize = 0;
const MX: usize = 1;
const MY: usize = 2;
const F0: usize = 3;
const PAN: usize = 4;

/// Column of the slope `sx / sz` (rotated by the pan angle in the kernels).
pub const SLOPE_X: usize = 0;
/// Column of the slope `sy / sz`.
pub const SLOPE_Y: usize = 1;
/// Column of `tan^2(theta_h)` (the isotropic lobe's exponent times `m^2`).
pub const TAN2: usize = 2;
/// Column of `E = ln(G / (4 uz vz)) + 2 ln(1 + tan^2(theta_h))` (`-f64::MAX` where the lobe
/// is 0).
pub const LOG_GEOMETRY: usize = 3;
/// Column of `1 - u.h`, computed without cancellation ([`super::geometry::one_minus_cos_half`]).
pub const ONE_MINUS_COS_D: usize = 4;
/// Column of `u.h = |u + v| / 2` ([`super::geometry::cos_half`]), for the derivative by `f0`.
pub const COS_D: usize = 5;
/// The number of prepared columns.
pub const COLUMNS: usize = 6;

/// Below this `sz` (both directions at the horizon) the lobe is 0: `tan^2(theta_h)` is above
/// about `1e199` and `D` underflows for every roughness in the box.
const SZ_MIN: f64 = 1e-100;

const fn field(name: &'static str, bounds: (f64, f64), default: f64, optional: bool) -> FieldDef {
    FieldDef {
        name,
        key: name,
        default,
        optional,
        bounds,
    }
}

const FIELDS: [FieldDef; 5] = [
    field("ks", KS_BOUNDS, 0.0, false),
    field("mx", M_BOUNDS, 0.1, false),
    field("my", M_BOUNDS, 0.1, false),
    field("f0", F0_BOUNDS, 1.0, true),
    field("pan", PAN_BOUNDS, 0.0, true),
];

const fn def(name: &'static str, fields: &'static [usize], coord: Coord, role: Role) -> ParamDef {
    ParamDef {
        name,
        fields,
        coord,
        role,
    }
}

const ANISOTROPIC: [ParamDef; 5] = [
    def("ks", &[KS], Coord::Identity, Role::Linear),
    def("mx", &[MX], Coord::Log, Role::Shape),
    def("my", &[MY], Coord::Log, Role::Shape),
    def("f0", &[F0], Coord::Identity, Role::Linear),
    def("pan", &[PAN], Coord::Identity, Role::Angle),
];

const ISOTROPIC: [ParamDef; 3] = [
    def("ks", &[KS], Coord::Identity, Role::Linear),
    def("m", &[MX, MY], Coord::Log, Role::Shape),
    def("f0", &[F0], Coord::Identity, Role::Linear),
];

/// The Cook-Torrance lobe shape.
#[derive(Clone, Copy, Debug, Default)]
pub struct CookTorrance;

/// Constants of one Cook-Torrance lobe.
#[derive(Clone, Copy, Debug, Default)]
pub struct CookTorranceCoef {
    ks: f64,
    f0: f64,
    cos: f64,
    sin: f64,
    inv_mx: f64,
    inv_my: f64,
    inv_mx2: f64,
    inv_my2: f64,
    /// `1 / (pi mx my)`.
    norm: f64,
}

/// Radians per degree.
const DEG: f64 = std::f64::consts::PI / 180.0;

/// The parameter-independent columns of one sample (see the module documentation).
pub fn columns(u: [f64; 3], v: [f64; 3]) -> [f64; COLUMNS] {
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let t = s[0] * s[0] + s[1] * s[1];
    let len2 = t + s[2] * s[2];
    let q_d = super::geometry::one_minus_cos_half(u, v);
    let c_d = super::geometry::cos_half(u, v);
    let above = u[2] >= 0.0 && v[2] >= 0.0 && s[2] >= SZ_MIN;
    if !above {
        return [0.0, 0.0, 0.0, -f64::MAX, q_d, c_d];
    }
    let (sx, sy) = (s[0] / s[2], s[1] / s[2]);
    let tan2 = sx * sx + sy * sy;
    // G / (4 uz vz) = min(1, q lo) / (4 lo hi), q = 2 hz / (u.h) = 4 sz / |s|^2.
    let (lo, hi) = (u[2].min(v[2]), u[2].max(v[2]));
    let q = 4.0 * s[2] / len2;
    let ln_w = if q * lo >= 1.0 {
        -(4.0 * lo * hi).ln()
    } else {
        (q / (4.0 * hi)).ln()
    };
    [sx, sy, tan2, ln_w + 2.0 * tan2.ln_1p(), q_d, c_d]
}

/// The parts of one lobe at one sample shared by the value and the derivatives.
struct Parts {
    /// `D(h)` (with the geometric factor of `E`).
    d: f64,
    /// The Fresnel term.
    f: f64,
    /// Rotated slopes (anisotropic) or `tan^2(theta_h)` in `sx` (isotropic).
    sx: f64,
    sy: f64,
}

#[inline(always)]
fn parts<M: Math, const ANISO: bool>(c: &CookTorranceCoef, s: &[f64; MAX_COLUMNS]) -> Parts {
    let (x, sx, sy);
    if ANISO {
        (sx, sy) = rotate(c.cos, c.sin, s[SLOPE_X], s[SLOPE_Y]);
        x = M::mad(
            -sx * sx,
            c.inv_mx2,
            M::mad(-sy * sy, c.inv_my2, s[LOG_GEOMETRY]),
        );
    } else {
        (sx, sy) = (s[TAN2], 0.0);
        x = M::mad(-sx, c.inv_mx2, s[LOG_GEOMETRY]);
    }
    let d = c.norm * M::exp_cut(x);
    let q = s[ONE_MINUS_COS_D];
    let q2 = q * q;
    let p5 = q2 * q2 * q;
    let f = M::mad(1.0 - c.f0, p5, c.f0);
    Parts { d, f, sx, sy }
}

impl LobeShape for CookTorrance {
    const NAME: &'static str = NAME;
    const SUMMARY: &'static str = "Cook-Torrance microfacet lobes (Cook and Torrance 1982): \
         normalised Beckmann distribution (anisotropic with a pan angle), V-cavity masking, \
         Schlick Fresnel";
    const LOBE_FIELDS: &'static [FieldDef] = &FIELDS;
    const ANISOTROPIC: Option<&'static [ParamDef]> = Some(&ANISOTROPIC);
    const ISOTROPIC: Option<&'static [ParamDef]> = Some(&ISOTROPIC);
    const COLUMNS: usize = COLUMNS;
    type Coef = CookTorranceCoef;

    fn prepare(u: [f64; 3], v: [f64; 3], cols: &mut [f64]) {
        cols[..COLUMNS].copy_from_slice(&columns(u, v));
    }

    fn coef(f: &[f64], aniso: bool) -> CookTorranceCoef {
        let (mx, my) = if aniso {
            (f[MX], f[MY])
        } else {
            (f[MX], f[MX])
        };
        let (sin, cos) = if aniso {
            sin_cos_deg(f[PAN])
        } else {
            (0.0, 1.0)
        };
        CookTorranceCoef {
            ks: f[KS],
            f0: f[F0],
            cos,
            sin,
            inv_mx: 1.0 / mx,
            inv_my: 1.0 / my,
            inv_mx2: 1.0 / (mx * mx),
            inv_my2: 1.0 / (my * my),
            norm: 1.0 / (std::f64::consts::PI * mx * my),
        }
    }

    #[inline(always)]
    fn value<M: Math, const ANISO: bool>(c: &CookTorranceCoef, s: &[f64; MAX_COLUMNS]) -> f64 {
        let p = parts::<M, ANISO>(c, s);
        c.ks * p.d * p.f
    }

    #[inline(always)]
    fn value_grad<M: Math, const ANISO: bool>(
        c: &CookTorranceCoef,
        s: &[f64; MAX_COLUMNS],
        g: &mut [f64; MAX_FIELDS],
    ) -> f64 {
        let p = parts::<M, ANISO>(c, s);
        // The value exactly as `value` computes it, so residuals agree bit for bit.
        let value = c.ks * p.d * p.f;
        g[KS] = p.d * p.f;
        // 1 - (1 - u.h)^5 from u.h, without the cancellation near grazing back-scatter.
        let omp5 = super::geometry::one_minus_pow5::<M>(s[COS_D], s[ONE_MINUS_COS_D]);
        g[F0] = c.ks * p.d * omp5;
        if ANISO {
            // ln D = E - sx'^2 / mx^2 - sy'^2 / my^2 - ln(pi mx my).
            let ax = p.sx * p.sx * c.inv_mx2;
            let ay = p.sy * p.sy * c.inv_my2;
            g[MX] = value * (2.0 * ax - 1.0) * c.inv_mx;
            g[MY] = value * (2.0 * ay - 1.0) * c.inv_my;
            // Rotating by dp: d sx' = sy' dp, d sy' = -sx' dp.
            let dt = 2.0 * p.sx * p.sy * (c.inv_mx2 - c.inv_my2);
            g[PAN] = -value * dt * DEG;
        } else {
            // ln D = E - tan^2 / m^2 - 2 ln m - ln pi, one roughness.
            let a = p.sx * c.inv_mx2;
            g[MX] = value * (2.0 * a - 2.0) * c.inv_mx;
            g[MY] = 0.0;
            g[PAN] = 0.0;
        }
        value
    }
}
