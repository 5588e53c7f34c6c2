//! Ashikhmin-Shirley lobes: Ashikhmin and Shirley, "An Anisotropic Phong BRDF Model" (Journal
//! of Graphics Tools 5(2), 2000), the specular term, with Schlick's Fresnel approximation
//! (Schlick 1994) as in the paper.
//!
//! One lobe, with `h = (u + v) / |u + v|` and `h'x`, `h'y` its components in the lobe's frame
//! rotated by the pan angle (as in the Lafortune family; the paper's tangent `t` and bitangent
//! `b` are that frame's x and y axes):
//!
//! `lobe = ks sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^e F(u.h) / ((u.h) max(uz, vz))`
//! - `e = (nu h'x^2 + nv h'y^2) / (1 - hz^2)`, the paper's `nu cos^2(phi_h) + nv sin^2(phi_h)`;
//! - `F(c) = f0 + (1 - f0) (1 - c)^5`, the paper's Fresnel with `f0` its `R_s`.
//!
//! The paper uses one `R_s` both as the lobe's scale and as `F0`; here the scale `ks` and `f0`
//! are separate fields (the paper's lobe is `ks = 1`, `f0 = R_s`), as in Ngan et al.'s fits,
//! which have both. The paper's own diffuse term (coupled to `R_s`, vanishing at grazing
//! angles) is not used: the constant term is this project's Lambertian `kd`, as in Ngan et
//! al.'s comparison, which fits the lobe with a Lambertian term.
//!
//! Fields: `ks` (in [0, 1]: at normal incidence the lobe reflects at most `ks F` of the light,
//! since its distribution `sqrt((nu + 1)(nv + 1)) / (2 pi) (n.h)^e` integrates to 1 over the
//! hemisphere of `h`, so a value above 1 would reflect more than arrives; Ngan's fits reach
//! 0.773), `nu`, `nv` (exponents, in [0, 1e6]: 0 is the uniform distribution of `h`; 1e6 is
//! as sharp as the other families' sharpest lobe, a Ward or Beckmann roughness
//! `sqrt(2 / n) = 0.0014` against their 0.001; Ngan's fits span 0.5 to 78200), `f0` (in
//! [0, 1]) and `pan` (degrees, in [-90, 90]). An isotropic lobe fits `ks`, `n` (setting
//! `nu = nv`) and `f0`. The exponents are seen by the optimiser as `ln(1 + n)`
//! ([`Coord::Log1p`], [`Role::Shape`], as Lafortune's exponent) unless the spec says
//! `exponent = "raw"`; that is the coordinate that measured better (docs/model.md, section
//! "Ashikhmin-Shirley").
//!
//! # Numerics
//! `(n.h)^e = exp((nu h'x^2 + nv h'y^2) g)` with the prepared `g = ln(hz) / (hx^2 + hy^2)`:
//! the exponent's `1 - hz^2` is written as `hx^2 + hy^2` from the half vector's components,
//! and `g` tends to `-1/2` as `hz -> 1`, so there is no 0/0 at the peak (`g = -1/2` there).
//! `ln(hz)` is computed as `ln_1p(-(hx^2 + hy^2)) / 2` while `hx^2 + hy^2 < 1/2` (no
//! cancellation at sharp lobes, where `ln(hz)` is tiny and multiplied by a large exponent) and
//! as `ln(hz)` beyond. An isotropic lobe uses the prepared `ln(hz)` directly:
//! `(n.h)^n = exp(n ln(hz))`, with no rotation. The pan's sine and cosine are taken from
//! degrees with `90 - |pan|` near 90 degrees, as GGX's. The factor `1 / ((u.h) max(uz, vz))`
//! is prepared too, with `u.h = |u + v| / 2` (symmetric in `u` and `v`, and accurate to
//! rounding near grazing back-scatter, where it is small and the factor large; Fresnel's
//! `1 - u.h` is prepared as GGX's, accurate near retro-reflection); it is 0 when both directions lie on (or below) the horizon, where the lobe
//! is taken as 0 (its limit there depends on the path and on `e`; bbm gives 0 too), and it is
//! capped at 1e300, so the value, at most `ks (nu + 1)/(8 pi) 1e300`, never overflows. The
//! value is non-smooth in the directions (the `max`), not in the parameters. Derivatives:
//! `d ln f / d nu = 1 / (2 (nu + 1)) + h'x^2 g` (likewise `nv`), `d ln f / d pan = 2 h'x h'y
//! (nu - nv) g` per radian, `d f / d f0 = ks ... (1 - (1 - u.h)^5)` (prepared from `u.h` as
//! `u.h (1 + q + ... + q^4)`, `q = 1 - u.h`: as `1 - q^5` it cancels near grazing
//! back-scatter, where the factor `1 / (u.h)` makes these entries a column's largest).

use super::geometry::{self, rotate, sin_cos_deg};
use super::ward::exp_cut;
use crate::family::{Coord, FieldDef, ParamDef, Role};
use crate::lobes::{LobeShape, MAX_COLUMNS, MAX_FIELDS, Math};

/// The family's name.
pub const NAME: &str = "ashikhmin-shirley";

/// Bounds of `ks`.
pub const KS_BOUNDS: (f64, f64) = (0.0, 1.0);
/// Bounds of the exponents `nu`, `nv`.
pub const N_BOUNDS: (f64, f64) = (0.0, 1e6);
/// Bounds of `f0`.
pub const F0_BOUNDS: (f64, f64) = (0.0, 1.0);
/// Bounds of the pan angle, degrees.
pub const PAN_BOUNDS: (f64, f64) = (-90.0, 90.0);

/// Cap of the prepared `1 / ((u.h) max(uz, vz))`.
pub const FACTOR_MAX: f64 = 1e300;
/// `ln(hz)` used where `hz <= 0` (a direction below the horizon): the logarithm of the
/// smallest positive double, so `(n.h)^e` is 0 for `e >= 1` and 1 for `e = 0`, never NaN.
const LN_HZ_MIN: f64 = -745.2;

const KS: usize = 0;
const NU: usize = 1;
const NV: usize = 2;
const F0: usize = 3;
const PAN: usize = 4;

/// Prepared columns: the half vector's x and y, `g = ln(hz) / (hx^2 + hy^2)`, `ln(hz)`,
/// `(1 - u.h)^5`, `1 / ((u.h) max(uz, vz))` and `1 - (1 - u.h)^5` (the derivative of `F` by
/// `f0`, from `u.h` without cancellation: [`geometry::one_minus_pow5`]).
const HX: usize = 0;
const HY: usize = 1;
const G: usize = 2;
const LNHZ: usize = 3;
const Q5: usize = 4;
const DEN: usize = 5;
const OMQ5: usize = 6;

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
    field("nu", N_BOUNDS, 100.0, false),
    field("nv", N_BOUNDS, 100.0, false),
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
    def("nu", &[NU], Coord::Log1p, Role::Shape),
    def("nv", &[NV], Coord::Log1p, Role::Shape),
    def("f0", &[F0], Coord::Identity, Role::Linear),
    def("pan", &[PAN], Coord::Identity, Role::Angle),
];

const ISOTROPIC: [ParamDef; 3] = [
    def("ks", &[KS], Coord::Identity, Role::Linear),
    def("n", &[NU, NV], Coord::Log1p, Role::Shape),
    def("f0", &[F0], Coord::Identity, Role::Linear),
];

/// The Ashikhmin-Shirley lobe shape.
#[derive(Clone, Copy, Debug, Default)]
pub struct AshikhminShirley;

/// Constants of one Ashikhmin-Shirley lobe.
#[derive(Clone, Copy, Debug, Default)]
pub struct AsCoef {
    nu: f64,
    nv: f64,
    f0: f64,
    cos: f64,
    sin: f64,
    /// `sqrt((nu + 1)(nv + 1)) / (8 pi)`.
    k: f64,
    /// `ks k`.
    ksk: f64,
    /// `d ln k / d nu`, `d ln k / d nv` (isotropic: `d ln k / d n` in `dnu`).
    dnu: f64,
    dnv: f64,
}

/// Radians per degree.
const DEG: f64 = std::f64::consts::PI / 180.0;

/// The parts of one lobe at one sample shared by the value and the derivatives.
struct Parts {
    /// `(n.h)^e F`.
    pf: f64,
    /// `(n.h)^e`.
    p: f64,
    /// Rotated half vector (anisotropic only).
    h: (f64, f64),
}

#[inline(always)]
fn parts<M: Math, const ANISO: bool>(c: &AsCoef, s: &[f64; MAX_COLUMNS]) -> Parts {
    let (h, t);
    if ANISO {
        h = rotate(c.cos, c.sin, s[HX], s[HY]);
        t = M::mad(c.nu, h.0 * h.0, c.nv * (h.1 * h.1)) * s[G];
    } else {
        h = (0.0, 0.0);
        t = c.nu * s[LNHZ];
    }
    let p = exp_cut::<M>(t);
    let f = M::mad(1.0 - c.f0, s[Q5], c.f0);
    Parts { pf: p * f, p, h }
}

impl LobeShape for AshikhminShirley {
    const NAME: &'static str = NAME;
    const SUMMARY: &'static str = "Ashikhmin-Shirley anisotropic Phong lobes (Ashikhmin and \
         Shirley, JGT 2000), Schlick Fresnel, constant diffuse term";
    const LOBE_FIELDS: &'static [FieldDef] = &FIELDS;
    const ANISOTROPIC: Option<&'static [ParamDef]> = Some(&ANISOTROPIC);
    const ISOTROPIC: Option<&'static [ParamDef]> = Some(&ISOTROPIC);
    const COLUMNS: usize = 7;
    type Coef = AsCoef;

    fn prepare(u: [f64; 3], v: [f64; 3], cols: &mut [f64]) {
        // The half vector and `1 - u.h` as GGX has them (`h = (u + v) / |u + v|`; `1 - u.h`
        // without cancellation near retro-reflection), and `u.h = |u + v| / 2` itself, which
        // keeps its digits near grazing back-scatter, where the factor divides by it (as
        // `1 - q` it lost them there: 1e-13 relative at `u.h` = 1e-3, 1e-10 at 1e-6).
        let mut geo = [0.0; geometry::COLUMNS];
        geometry::half_vector_columns(u, v, &mut geo);
        let h = [geo[geometry::H], geo[geometry::H + 1], geo[geometry::H + 2]];
        let q = geo[geometry::ONE_MINUS_UH];
        let uh = geometry::cos_half(u, v);
        let s = h[0] * h[0] + h[1] * h[1];
        let ln_hz = if h[2] <= 0.0 {
            LN_HZ_MIN
        } else if s < 0.5 {
            0.5 * (-s).ln_1p()
        } else {
            h[2].ln()
        };
        cols[HX] = h[0];
        cols[HY] = h[1];
        cols[G] = if s > 0.0 { ln_hz / s } else { -0.5 };
        cols[LNHZ] = ln_hz;
        cols[Q5] = q * q * q * q * q;
        cols[OMQ5] = geometry::one_minus_pow5::<crate::lobes::Libm>(uh, q);
        let den = uh * u[2].max(v[2]);
        cols[DEN] = if den <= 0.0 {
            0.0
        } else if den > 1.0 / FACTOR_MAX {
            1.0 / den
        } else {
            FACTOR_MAX
        };
    }

    fn coef(f: &[f64], aniso: bool) -> AsCoef {
        let (nu, nv) = if aniso {
            (f[NU], f[NV])
        } else {
            (f[NU], f[NU])
        };
        // From degrees with `90 - |pan|` near 90 (as GGX and Cook-Torrance): `cos(pi / 2)`
        // in `f64` is 6e-17, not 0, and that absolute error in the rotated slope along a sharp
        // axis cost up to 1.2e-12 of relative value at pan = 90.
        let (sin, cos) = if aniso {
            sin_cos_deg(f[PAN])
        } else {
            (0.0, 1.0)
        };
        let k = if aniso {
            ((nu + 1.0) * (nv + 1.0)).sqrt()
        } else {
            nu + 1.0
        } / (8.0 * std::f64::consts::PI);
        let (dnu, dnv) = if aniso {
            (0.5 / (nu + 1.0), 0.5 / (nv + 1.0))
        } else {
            (1.0 / (nu + 1.0), 0.0)
        };
        AsCoef {
            nu,
            nv,
            f0: f[F0],
            cos,
            sin,
            k,
            ksk: f[KS] * k,
            dnu,
            dnv,
        }
    }

    #[inline(always)]
    fn value<M: Math, const ANISO: bool>(c: &AsCoef, s: &[f64; MAX_COLUMNS]) -> f64 {
        let p = parts::<M, ANISO>(c, s);
        // ks k <= 4e4, (n.h)^e F <= 1 and the factor <= 1e300: this order cannot overflow.
        c.ksk * p.pf * s[DEN]
    }

    #[inline(always)]
    fn value_grad<M: Math, const ANISO: bool>(
        c: &AsCoef,
        s: &[f64; MAX_COLUMNS],
        g: &mut [f64; MAX_FIELDS],
    ) -> f64 {
        let p = parts::<M, ANISO>(c, s);
        // The value exactly as `value` computes it, so residuals agree bit for bit.
        let value = c.ksk * p.pf * s[DEN];
        g[KS] = c.k * p.pf * s[DEN];
        g[F0] = c.ksk * p.p * s[DEN] * s[OMQ5];
        if ANISO {
            let gg = s[G];
            g[NU] = value * M::mad(p.h.0 * p.h.0, gg, c.dnu);
            g[NV] = value * M::mad(p.h.1 * p.h.1, gg, c.dnv);
            // Rotating by dp: d h'x = h'y dp, d h'y = -h'x dp.
            g[PAN] = value * (2.0 * p.h.0 * p.h.1 * (c.nu - c.nv) * gg) * DEG;
        } else {
            // One exponent `n` for both fields: ln f = ln((n + 1) / (8 pi)) + n ln(hz) + ...
            g[NU] = value * (c.dnu + s[LNHZ]);
            g[NV] = 0.0;
            g[PAN] = 0.0;
        }
        value
    }
}
