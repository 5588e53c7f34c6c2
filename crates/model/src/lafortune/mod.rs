//! The Lafortune model (Lafortune, Foo, Torrance and Greenberg, "Non-Linear Approximation of
//! Reflectance Functions", SIGGRAPH 1997) as the SLS paper fits it: the first model
//! [`Family`], with anisotropic lobes rotated by a pan angle.
//!
//! - `f(u, v) = kd + sum_k max(0, Cx u'x v'x + Cy u'y v'y + Cz uz vz)^n_k`.
//! - A mirror-like (forward) lobe has `Cx = Cy < 0 < Cz`, a retro-reflective one `Cx = Cy > 0`;
//!   Phong is `-Cx = -Cy = Cz`.
//! - `u'`, `v'` are `u`, `v` rotated about the normal by the lobe's pan angle (degrees):
//!   `u'x = cos(p) ux + sin(p) uy`, `u'y = -sin(p) ux + cos(p) uy`: a positive pan turns the
//!   lobe's axes counter-clockwise about the normal seen from above (+x towards +y).
//! - `kd` is the constant BRDF term (the paper's "Diffuse"); the diffuse albedo is
//!   `rho_d = pi * kd`. Each lobe's scale `rho_s` is folded into its C's.
//! - A clamped dot product `d <= 0` contributes 0 for every `n` (also `n = 0`).
//! - Table 1 bounds: C in [-1.5, 1.5], n in [0, 10000], pan in [-90, 90] degrees, kd in [0, 1].
//! - Parameters: `kd`; per anisotropic lobe `cx, cy, cz, n, pan`; per isotropic lobe `cxy`
//!   (setting `cx = cy`), `cz, n`. The exponent is seen by the optimiser as `ln(1 + n)` by
//!   default ([`crate::ExponentCoord`]), pan angles in degrees.
//!
//! [`BrdfParams`] is the family's typed parameter set; it converts to and from the generic
//! [`Params`] losslessly.

#[cfg(target_arch = "x86_64")]
mod avx512;
mod coef;
mod eval;
mod params;
mod samples;

pub use eval::POWERS_MIN_ROWS;
pub use params::{
    BrdfParams, C_BOUNDS, KD_BOUNDS, Lobe, N_BOUNDS, NAMED_PARAMS, PAN_BOUNDS, named_params,
};
pub use samples::NAME;
pub(crate) use samples::prepare;

use crate::data::DataSet;
use crate::evaluate::Evaluate;
use crate::family::{Coord, Family, FamilyRef, FieldDef, LayoutParam, LobeKind, ParamDef, Role};
use crate::params::{ParamError, Params};
use crate::samples::Samples;
use brdf_simd::{Kernel, KernelError};
use std::sync::{Arc, OnceLock};

/// The Lafortune family.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lafortune;

/// The one shared instance (what the registry and [`FamilyRef::lafortune`] hand out).
pub(crate) fn family() -> Arc<dyn Family> {
    static F: OnceLock<Arc<dyn Family>> = OnceLock::new();
    F.get_or_init(|| Arc::new(Lafortune)).clone()
}

const fn field(name: &'static str, key: &'static str, bounds: (f64, f64)) -> FieldDef {
    FieldDef {
        name,
        key,
        default: 0.0,
        optional: false,
        bounds,
    }
}

const SHARED_FIELDS: [FieldDef; 1] = [field("kd", "kd", KD_BOUNDS)];

/// Field indices of a lobe.
const CX: usize = 0;
const CY: usize = 1;
const CZ: usize = 2;
const N: usize = 3;
const PAN: usize = 4;

const LOBE_FIELDS: [FieldDef; 5] = [
    field("cx", "cx", C_BOUNDS),
    field("cy", "cy", C_BOUNDS),
    field("cz", "cz", C_BOUNDS),
    field("n", "n", N_BOUNDS),
    FieldDef {
        optional: true,
        ..field("pan", "pan_deg", PAN_BOUNDS)
    },
];

const fn def(name: &'static str, fields: &'static [usize], coord: Coord, role: Role) -> ParamDef {
    ParamDef {
        name,
        fields,
        coord,
        role,
    }
}

const SHARED_PARAMS: [ParamDef; 1] = [def("kd", &[0], Coord::Identity, Role::Linear)];

const ANISOTROPIC: [ParamDef; 5] = [
    def("cx", &[CX], Coord::Identity, Role::Linear),
    def("cy", &[CY], Coord::Identity, Role::Linear),
    def("cz", &[CZ], Coord::Identity, Role::Linear),
    def("n", &[N], Coord::Log1p, Role::Shape),
    def("pan", &[PAN], Coord::Identity, Role::Angle),
];

const ISOTROPIC: [ParamDef; 3] = [
    def("cxy", &[CX, CY], Coord::Identity, Role::Linear),
    def("cz", &[CZ], Coord::Identity, Role::Linear),
    def("n", &[N], Coord::Log1p, Role::Shape),
];

impl Family for Lafortune {
    fn name(&self) -> &'static str {
        NAME
    }

    fn summary(&self) -> &'static str {
        "Lafortune et al. 1997: kd + generalised cosine lobes max(0, Cx x + Cy y + Cz z)^n, \
         anisotropic lobes rotated by a pan angle"
    }

    fn shared_fields(&self) -> &'static [FieldDef] {
        &SHARED_FIELDS
    }

    fn lobe_fields(&self) -> &'static [FieldDef] {
        &LOBE_FIELDS
    }

    fn shared_params(&self) -> &'static [ParamDef] {
        &SHARED_PARAMS
    }

    fn lobe_params(&self, kind: LobeKind) -> Option<&'static [ParamDef]> {
        Some(match kind {
            LobeKind::Anisotropic => &ANISOTROPIC,
            LobeKind::Isotropic => &ISOTROPIC,
        })
    }

    fn prepare(&self, data: &DataSet) -> Samples {
        prepare(data)
    }

    fn value(&self, shared: &[f64], lobes: &[Vec<f64>], u: [f64; 3], v: [f64; 3]) -> f64 {
        let lobes = lobes.iter().map(|l| lobe_of(l).value(u, v));
        shared[0] + lobes.sum::<f64>()
    }

    fn evaluator(
        &self,
        kinds: &[LobeKind],
        params: &[LayoutParam],
        kernel: Kernel,
    ) -> Result<Box<dyn Evaluate>, KernelError> {
        let kernel = kernel.resolve()?;
        Ok(Box::new(eval::LafortuneEval::new(kinds, params, kernel)))
    }
}

fn lobe_of(l: &[f64]) -> Lobe {
    Lobe {
        cx: l[CX],
        cy: l[CY],
        cz: l[CZ],
        n: l[N],
        pan_deg: l[PAN],
    }
}

impl From<&BrdfParams> for Params {
    fn from(p: &BrdfParams) -> Params {
        let lobes = p
            .lobes
            .iter()
            .map(|l| vec![l.cx, l.cy, l.cz, l.n, l.pan_deg])
            .collect();
        Params::new(FamilyRef::lafortune(), vec![p.kd], lobes)
            .expect("Lafortune's parts have the family's lengths")
    }
}

impl From<BrdfParams> for Params {
    fn from(p: BrdfParams) -> Params {
        Params::from(&p)
    }
}

impl TryFrom<&Params> for BrdfParams {
    type Error = ParamError;
    /// The Lafortune view of a Lafortune parameter set.
    fn try_from(p: &Params) -> Result<BrdfParams, ParamError> {
        if !p.family().is_lafortune() {
            return Err(ParamError::WrongFamily {
                expected: NAME.into(),
                found: p.family().name().into(),
            });
        }
        Ok(BrdfParams {
            kd: p.shared()[0],
            lobes: p.lobes().iter().map(|l| lobe_of(l)).collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::samples::view;
    use super::*;

    #[test]
    fn generic_params_round_trip_and_serialise_as_before() {
        let b = named_params("cross").unwrap();
        let p = Params::from(&b);
        assert_eq!(BrdfParams::try_from(&p).unwrap(), b);
        assert_eq!(p.get("lobe2.pan"), Some(-45.0));
        let u = [0.3, -0.4, (1.0f64 - 0.25).sqrt()];
        let v = [-0.6, 0.1, (1.0f64 - 0.37).sqrt()];
        assert_eq!(p.value(u, v), b.value(u, v));
        let json = serde_json::to_string(&p).unwrap();
        assert_eq!(json, serde_json::to_string(&b).unwrap());
        let back: Params = serde_json::from_str(&json).unwrap();
        assert_eq!(back, p);
        let no_pan: Params =
            serde_json::from_str(r#"{"kd":0.1,"lobes":[{"cx":1,"cy":1,"cz":1,"n":2}]}"#).unwrap();
        assert_eq!(no_pan.get("lobe1.pan"), Some(0.0));
        let e = serde_json::from_str::<Params>(
            r#"{"kd":0.1,"lobes":[{"cx":1,"cy":1,"cz":1,"n":2,"pan":3}]}"#,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("unknown field `pan`") && e.contains("`pan_deg`"),
            "{e}"
        );
        let e = serde_json::from_str::<Params>(r#"{"kd":0.1,"lobes":[{"cx":1,"cy":1,"n":2}]}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing field `cz`"), "{e}");
        let e = serde_json::from_str::<Params>(r#"{"kd":0.1,"kx":2,"lobes":[]}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown field `kx`"), "{e}");
    }

    #[test]
    fn prepared_products_follow_the_directions() {
        let a = crate::synthetic(&named_params("cross").unwrap(), 300, 0.1, 3);
        let s = prepare(&a);
        let v = view(&s, 0, s.len());
        for i in 0..a.len() {
            let (u, w) = (a.u(i), a.v(i));
            assert_eq!(v.pxx[i], u[0] * w[0]);
            assert_eq!(v.pyy[i], u[1] * w[1]);
            assert_eq!(v.pxy[i], u[0].mul_add(w[1], u[1] * w[0]));
            assert_eq!(v.pzz[i], u[2] * w[2]);
            assert_eq!(v.value[i], a.value(i));
        }
    }
}
