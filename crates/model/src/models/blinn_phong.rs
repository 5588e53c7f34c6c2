//! Normalised Blinn-Phong lobes: Blinn, "Models of Light Reflection for Computer Synthesized
//! Pictures" (SIGGRAPH 1977), the half-vector form of Phong's highlight, with the approximate
//! energy normalisation `(p + 8) / (8 pi)` of Akenine-Möller, Haines and Hoffman, *Real-Time
//! Rendering* (3rd edition, 2008, section 7.6), derived by Giesen, "On the Blinn-Phong
//! normalization factor" (2009).
//!
//! One lobe, with `h = (u + v) / |u + v|`:
//!
//! `lobe = ks (p + 8) / (8 pi) max(0, n.h)^p`
//!
//! Isotropic only (no pan angle). Reciprocal: `h` is symmetric in `u` and `v`.
//!
//! # The normalisation
//! `(p + 2) / (2 pi) (n.h)^p` is the exactly normalised *distribution* of half vectors
//! (`int (p + 2) / (2 pi) (n.h)^p (n.h) dw_h = 1` over the hemisphere; Ngan's fits use it).
//! The factor `(p + 8) / (8 pi)` instead approximately normalises the *BRDF*: with `ks = 1`
//! the directional albedo at normal view, `A(p) = int f (n.l) dw_l` with `v = n`, is
//!
//! `A(p) = (p + 8) (p + 2^(-p/2)) / ((p + 2) (p + 4))`,
//!
//! which is 1 at `p = 0`, rises to at most 1.075201 (at `p = 8.76`) and tends to 1 from
//! above as `p` grows (`1 + 2/p`): the lobe reflects `ks` of the light it receives at normal
//! view to within 8%. `crates/model/tests/blinn_phong.rs` checks this closed form and its
//! bounds by quadrature. So `ks` is (nearly) the lobe's albedo at normal view, whatever `p`;
//! a fit with the `(p + 2) / (2 pi)` factor and scale `a` is this lobe with
//! `ks = 4 a (p + 2) / (p + 8)` (`brdf_published::NganBlinnPhong`).
//!
//! # Fields and bounds
//! - `ks` in [0, 10]: the scale (as the microfacet families'); Ngan's fits convert to at most
//!   0.3.
//! - `p` in [0, 1e6]: the exponent. Ngan's Blinn-Phong fits (whose `sharpness` behaves as the
//!   exponent of `n.h`, see docs/published-fits.md) lie in [1.45, 121000]; `p = 1e6` is a lobe
//!   of half-width about 1e-3 rad (Beckmann `m = sqrt(2 / p)` = 0.0014, near the microfacet
//!   families' lower roughness bound 0.001). `p = 0` is a constant `ks / pi`.
//!
//! The exponent is a shape parameter ([`Role::Shape`]) seen by the optimiser as `ln(1 + p)`
//! ([`Coord::Log1p`], as Lafortune's `n`) unless the spec says `exponent = "raw"`
//! (docs/model.md gives the measurement behind the default).
//!
//! # Numerics
//! One prepared column, `L = ln(n.h) = -ln(1 + tan^2(theta_h)) / 2` with `tan^2(theta_h) =
//! (sx^2 + sy^2) / sz^2` from `s = u + v`: accurate to a few ulps (relative) at every angle, with
//! no `ln` of a number near 1 and no cancellation for narrow lobes, where `p L` is what
//! matters. The lobe is `ks (p + 8) / (8 pi) exp(p L)`: one `exp` per sample, which
//! [`Math::exp_cut`] takes as 0 below `e^-690` (the tails, identically in every kernel). Where
//! `hz = 0` (both directions on the horizon, or below it) `L = -f64::MAX`, so that `0^p` is 0
//! for `p > 0` and 1 for `p = 0`. The value is at most `10 (1e6 + 8) / (8 pi)`, so nothing
//! overflows and nothing is NaN.

use crate::family::{Coord, FieldDef, ParamDef, Role};
use crate::lobes::{LobeShape, MAX_COLUMNS, MAX_FIELDS, Math};
use std::f64::consts::PI;

/// The family's name.
pub const NAME: &str = "blinn-phong";

/// Bounds of `ks`.
pub const KS_BOUNDS: (f64, f64) = (0.0, 10.0);
/// Bounds of the exponent `p`.
pub const P_BOUNDS: (f64, f64) = (0.0, 1e6);

const KS: usize = 0;
const P: usize = 1;

/// Column of `ln(n.h)`.
pub const LN_COS_H: usize = 0;
/// The number of prepared columns.
pub const COLUMNS: usize = 1;

const FIELDS: [FieldDef; 2] = [
    FieldDef {
        name: "ks",
        key: "ks",
        default: 0.0,
        optional: false,
        bounds: KS_BOUNDS,
    },
    FieldDef {
        name: "p",
        key: "p",
        default: 100.0,
        optional: false,
        bounds: P_BOUNDS,
    },
];

const ISOTROPIC: [ParamDef; 2] = [
    ParamDef {
        name: "ks",
        fields: &[KS],
        coord: Coord::Identity,
        role: Role::Linear,
    },
    ParamDef {
        name: "p",
        fields: &[P],
        coord: Coord::Log1p,
        role: Role::Shape,
    },
];

/// `ln(n.h)` for directions `u`, `v` (see the module documentation); `-f64::MAX` where
/// `hz <= 0`.
pub fn ln_cos_h(u: [f64; 3], v: [f64; 3]) -> f64 {
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let t = s[0] * s[0] + s[1] * s[1];
    if s[2].is_nan() || s[2] <= 0.0 {
        return -f64::MAX;
    }
    if s[2] > 1e-150 {
        // sz^2 is a normal number: tan^2 keeps full precision.
        -0.5 * (t / (s[2] * s[2])).ln_1p()
    } else {
        // Both directions within 1e-150 of the horizon: ln(hz) directly (no digits to lose).
        s[2].ln() - 0.5 * (t + s[2] * s[2]).ln()
    }
}

/// The Blinn-Phong lobe shape.
#[derive(Clone, Copy, Debug, Default)]
pub struct BlinnPhong;

/// Constants of one Blinn-Phong lobe.
#[derive(Clone, Copy, Debug, Default)]
pub struct BlinnPhongCoef {
    ks: f64,
    p: f64,
    /// `ks (p + 8) / (8 pi)`.
    kn: f64,
    /// `(p + 8) / (8 pi)`.
    norm: f64,
}

impl LobeShape for BlinnPhong {
    const NAME: &'static str = NAME;
    const SUMMARY: &'static str = "normalised Blinn-Phong lobes ks (p + 8)/(8 pi) (n.h)^p \
         (Blinn 1977; the normalisation of Akenine-Möller et al. 2008)";
    const LOBE_FIELDS: &'static [FieldDef] = &FIELDS;
    const ANISOTROPIC: Option<&'static [ParamDef]> = None;
    const ISOTROPIC: Option<&'static [ParamDef]> = Some(&ISOTROPIC);
    const COLUMNS: usize = COLUMNS;
    type Coef = BlinnPhongCoef;

    fn prepare(u: [f64; 3], v: [f64; 3], cols: &mut [f64]) {
        cols[LN_COS_H] = ln_cos_h(u, v);
    }

    fn coef(f: &[f64], _aniso: bool) -> BlinnPhongCoef {
        let norm = (f[P] + 8.0) / (8.0 * PI);
        BlinnPhongCoef {
            ks: f[KS],
            p: f[P],
            kn: f[KS] * norm,
            norm,
        }
    }

    #[inline(always)]
    fn value<M: Math, const ANISO: bool>(c: &BlinnPhongCoef, s: &[f64; MAX_COLUMNS]) -> f64 {
        c.kn * M::exp_cut(c.p * s[LN_COS_H])
    }

    #[inline(always)]
    fn value_grad<M: Math, const ANISO: bool>(
        c: &BlinnPhongCoef,
        s: &[f64; MAX_COLUMNS],
        g: &mut [f64; MAX_FIELDS],
    ) -> f64 {
        let e = M::exp_cut(c.p * s[LN_COS_H]);
        // The value exactly as `value` computes it, so residuals agree bit for bit.
        let value = c.kn * e;
        g[KS] = c.norm * e;
        // d/dp [ks (p + 8)/(8 pi) e^(p L)] = ks e / (8 pi) + value L.
        g[P] = c.ks * e * (1.0 / (8.0 * PI)) + value * s[LN_COS_H];
        value
    }
}
