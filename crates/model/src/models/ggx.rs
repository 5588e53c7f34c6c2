//! GGX (Trowbridge-Reitz) microfacet lobes: Walter, Marschner, Li and Torrance, "Microfacet
//! Models for Refraction through Rough Surfaces" (EGSR 2007), with the anisotropic roughness
//! of Burley, "Physically Based Shading at Disney" (SIGGRAPH 2012 course) and the matching
//! Smith masking of Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based
//! BRDFs" (JCGT 2014), and Schlick's Fresnel approximation (Schlick 1994).
//!
//! One lobe, with `h = (u + v) / |u + v|` and `x'`, `y'` the components in the lobe's frame
//! rotated by the pan angle (as in the Lafortune family):
//!
//! `lobe = ks D(h) G1(u) G1(v) F(u.h) / (4 uz vz)`
//! - `D(h) = 1 / (pi ax ay (h'x^2 / ax^2 + h'y^2 / ay^2 + hz^2)^2)` (unit `h`; this form has no
//!   cancellation at small roughness, where the textbook `(n.h)^2 (a^2 - 1) + 1` loses digits);
//! - `G1(w) = 2 wz / (wz + sqrt(wz^2 + ax^2 w'x^2 + ay^2 w'y^2))`, the separable
//!   (height-uncorrelated) Smith form; the code computes `G1(w) / wz = 2 / (wz + sqrt(..))`, so
//!   no division by a cosine can reach 0/0 at the horizon;
//! - `F(c) = f0 + (1 - f0) (1 - c)^5`, with `1 - c` prepared as `|u - v|^2 / (2 (2 + |u + v|))`
//!   (accurate near retro-reflection) and, for the derivative by `f0`, `1 - (1 - c)^5` as
//!   `c (1 + q + ... + q^4)` from the prepared `c = |u + v| / 2` (accurate near grazing
//!   back-scatter, where `1 - q^5` would cancel).
//!
//! Fields: `ks` (specular scale, in [0, 10]), `ax`, `ay` (roughness, in [0.001, 2.5]: the
//! published fits reach 2.09), `f0` (Fresnel reflectance at normal incidence, in [0, 1]) and
//! `pan` (degrees, in [-90, 90]). An isotropic lobe fits `ks`, `alpha` (setting `ax = ay`) and
//! `f0`. The roughness is seen by the optimiser as `ln(alpha)` ([`Coord::Log`]) unless the
//! spec says `exponent = "raw"`.

use super::geometry::{self, H, ONE_MINUS_UH, U, UH, V, rotate};
use crate::family::{Coord, FieldDef, ParamDef, Role};
use crate::lobes::{LobeShape, MAX_COLUMNS, MAX_FIELDS, Math};

/// The family's name.
pub const NAME: &str = "ggx";

/// Bounds of `ks`.
pub const KS_BOUNDS: (f64, f64) = (0.0, 10.0);
/// Bounds of the roughnesses `ax`, `ay`.
pub const ALPHA_BOUNDS: (f64, f64) = (0.001, 2.5);
/// Bounds of `f0`.
pub const F0_BOUNDS: (f64, f64) = (0.0, 1.0);
/// Bounds of the pan angle, degrees.
pub const PAN_BOUNDS: (f64, f64) = (-90.0, 90.0);

const KS: usize = 0;
const AX: usize = 1;
const AY: usize = 2;
const F0: usize = 3;
const PAN: usize = 4;

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
    field("ax", ALPHA_BOUNDS, 0.1, false),
    field("ay", ALPHA_BOUNDS, 0.1, false),
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
    def("ax", &[AX], Coord::Log, Role::Shape),
    def("ay", &[AY], Coord::Log, Role::Shape),
    def("f0", &[F0], Coord::Identity, Role::Linear),
    def("pan", &[PAN], Coord::Identity, Role::Angle),
];

const ISOTROPIC: [ParamDef; 3] = [
    def("ks", &[KS], Coord::Identity, Role::Linear),
    def("alpha", &[AX, AY], Coord::Log, Role::Shape),
    def("f0", &[F0], Coord::Identity, Role::Linear),
];

/// The GGX lobe shape.
#[derive(Clone, Copy, Debug, Default)]
pub struct Ggx;

/// Constants of one GGX lobe.
#[derive(Clone, Copy, Debug, Default)]
pub struct GgxCoef {
    ks: f64,
    ax: f64,
    ay: f64,
    f0: f64,
    cos: f64,
    sin: f64,
    inv_ax2: f64,
    inv_ay2: f64,
    ax2: f64,
    ay2: f64,
    /// `1 / (pi ax ay)`.
    norm: f64,
}

/// Radians per degree.
const DEG: f64 = std::f64::consts::PI / 180.0;

/// The parts of one lobe at one sample shared by the value and the derivatives.
struct Parts {
    /// `h'x^2 / ax^2 + h'y^2 / ay^2 + hz^2`.
    t: f64,
    d: f64,
    /// `G1(u) / uz`, `G1(v) / vz` and the square roots in them.
    gu: f64,
    gv: f64,
    lu: f64,
    lv: f64,
    /// The Fresnel term.
    f: f64,
    /// Rotated components: `h`, `u`, `v` (x', y').
    h: (f64, f64),
    u: (f64, f64),
    v: (f64, f64),
}

#[inline(always)]
fn parts<M: Math, const ANISO: bool>(c: &GgxCoef, s: &[f64; MAX_COLUMNS]) -> Parts {
    let (uz, vz, hz) = (s[U + 2], s[V + 2], s[H + 2]);
    let (h, u, v, t, qu, qv);
    if ANISO {
        h = rotate(c.cos, c.sin, s[H], s[H + 1]);
        u = rotate(c.cos, c.sin, s[U], s[U + 1]);
        v = rotate(c.cos, c.sin, s[V], s[V + 1]);
        t = M::mad(h.0 * h.0, c.inv_ax2, M::mad(h.1 * h.1, c.inv_ay2, hz * hz));
        qu = M::mad(c.ax2, u.0 * u.0, M::mad(c.ay2, u.1 * u.1, uz * uz));
        qv = M::mad(c.ax2, v.0 * v.0, M::mad(c.ay2, v.1 * v.1, vz * vz));
    } else {
        // Isotropic: only the squared lengths of the tangential parts matter.
        let hxy = M::mad(s[H], s[H], s[H + 1] * s[H + 1]);
        let uxy = M::mad(s[U], s[U], s[U + 1] * s[U + 1]);
        let vxy = M::mad(s[V], s[V], s[V + 1] * s[V + 1]);
        h = (hxy, 0.0);
        u = (uxy, 0.0);
        v = (vxy, 0.0);
        t = M::mad(hxy, c.inv_ax2, hz * hz);
        qu = M::mad(c.ax2, uxy, uz * uz);
        qv = M::mad(c.ax2, vxy, vz * vz);
    }
    let d = c.norm / (t * t);
    let (lu, lv) = (M::sqrt(qu), M::sqrt(qv));
    let gu = 2.0 / (uz + lu);
    let gv = 2.0 / (vz + lv);
    let q = s[ONE_MINUS_UH];
    let q2 = q * q;
    let p5 = q2 * q2 * q;
    let f = M::mad(1.0 - c.f0, p5, c.f0);
    Parts {
        t,
        d,
        gu,
        gv,
        lu,
        lv,
        f,
        h,
        u,
        v,
    }
}

impl LobeShape for Ggx {
    const NAME: &'static str = NAME;
    const SUMMARY: &'static str = "GGX / Trowbridge-Reitz microfacet lobes (Walter et al. 2007; \
         anisotropic as in Burley 2012), separable Smith masking, Schlick Fresnel";
    const LOBE_FIELDS: &'static [FieldDef] = &FIELDS;
    const ANISOTROPIC: Option<&'static [ParamDef]> = Some(&ANISOTROPIC);
    const ISOTROPIC: Option<&'static [ParamDef]> = Some(&ISOTROPIC);
    const COLUMNS: usize = geometry::COLUMNS;
    type Coef = GgxCoef;

    fn prepare(u: [f64; 3], v: [f64; 3], cols: &mut [f64]) {
        geometry::half_vector_columns(u, v, cols);
    }

    fn coef(f: &[f64], aniso: bool) -> GgxCoef {
        let (ax, ay) = if aniso {
            (f[AX], f[AY])
        } else {
            (f[AX], f[AX])
        };
        let (sin, cos) = if aniso {
            geometry::sin_cos_deg(f[PAN])
        } else {
            (0.0, 1.0)
        };
        GgxCoef {
            ks: f[KS],
            ax,
            ay,
            f0: f[F0],
            cos,
            sin,
            inv_ax2: 1.0 / (ax * ax),
            inv_ay2: 1.0 / (ay * ay),
            ax2: ax * ax,
            ay2: ay * ay,
            norm: 1.0 / (std::f64::consts::PI * ax * ay),
        }
    }

    #[inline(always)]
    fn value<M: Math, const ANISO: bool>(c: &GgxCoef, s: &[f64; MAX_COLUMNS]) -> f64 {
        let p = parts::<M, ANISO>(c, s);
        0.25 * c.ks * p.d * p.f * p.gu * p.gv
    }

    #[inline(always)]
    fn value_grad<M: Math, const ANISO: bool>(
        c: &GgxCoef,
        s: &[f64; MAX_COLUMNS],
        g: &mut [f64; MAX_FIELDS],
    ) -> f64 {
        let p = parts::<M, ANISO>(c, s);
        // The value exactly as `value` computes it, so residuals agree bit for bit.
        let value = 0.25 * c.ks * p.d * p.f * p.gu * p.gv;
        let k = 0.25 * p.d * p.gu * p.gv;
        g[KS] = k * p.f;
        // 1 - (1 - u.h)^5 from u.h, without the cancellation near grazing back-scatter.
        g[F0] = c.ks * k * geometry::one_minus_pow5::<M>(s[UH], s[ONE_MINUS_UH]);
        // d ln(gu) / d q_u = -gu / (4 lu) for q_u = lu^2: gu = 2 / (uz + sqrt(q_u)).
        let su = -0.25 * p.gu / p.lu;
        let sv = -0.25 * p.gv / p.lv;
        let inv_t = 1.0 / p.t;
        if ANISO {
            // ln D = -ln(pi ax ay) - 2 ln t; t depends on ax through h'x^2 / ax^2.
            let hx2 = p.h.0 * p.h.0 * c.inv_ax2;
            let hy2 = p.h.1 * p.h.1 * c.inv_ay2;
            let dlx = (4.0 * hx2 * inv_t - 1.0) / c.ax
                + 2.0 * c.ax * (su * p.u.0 * p.u.0 + sv * p.v.0 * p.v.0);
            let dly = (4.0 * hy2 * inv_t - 1.0) / c.ay
                + 2.0 * c.ay * (su * p.u.1 * p.u.1 + sv * p.v.1 * p.v.1);
            g[AX] = value * dlx;
            g[AY] = value * dly;
            // Rotating by dp: d x' = y' dp, d y' = -x' dp.
            let dd = c.inv_ax2 - c.inv_ay2;
            let dt = 2.0 * p.h.0 * p.h.1 * dd;
            let dq = (c.ax2 - c.ay2) * 2.0;
            let dlp = -2.0 * dt * inv_t + su * dq * p.u.0 * p.u.1 + sv * dq * p.v.0 * p.v.1;
            g[PAN] = value * dlp * DEG;
        } else {
            // One roughness `a`: d ln D / d a = (2 - 4 hz^2 / t) / a (from h_xy^2 / a^2 =
            // t - hz^2) and d ln(G1(w) / wz) / d a = -(1 - wz / lw) / a (from a^2 w_xy^2 =
            // lw^2 - wz^2), so d ln f / d a = (uz / lu + vz / lv - 4 hz^2 / t) / a: small
            // terms only. The textbook sum of the three parts, `2/a`, `-(1 - uz/lu)/a` and
            // `-(1 - vz/lv)/a` near grazing, cancelled there for wide lobes (2e-12 of the
            // column at a = 2).
            let (uz, vz, hz) = (s[U + 2], s[V + 2], s[H + 2]);
            let dla = (uz / p.lu + vz / p.lv - 4.0 * hz * hz * inv_t) / c.ax;
            g[AX] = value * dla;
            g[AY] = 0.0;
            g[PAN] = 0.0;
        }
        value
    }
}
