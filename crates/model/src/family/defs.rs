//! The plain definitions a family describes itself with: lobe kinds, fields, parameters,
//! coordinates, roles, and a layout's parameters as an evaluator reads them.

use serde::{Deserialize, Serialize};

/// The kind of a lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LobeKind {
    /// Every lobe field is a parameter of its own (anisotropic lobes rotate by a pan angle).
    Anisotropic,
    /// The lobe's anisotropic pairs are tied (Lafortune's `Cx = Cy`, GGX's `alpha_x =
    /// alpha_y`) and no pan angle is fitted.
    Isotropic,
}

impl LobeKind {
    /// The lowercase name used in specs (`"anisotropic"`, `"isotropic"`).
    pub fn name(self) -> &'static str {
        match self {
            LobeKind::Anisotropic => "anisotropic",
            LobeKind::Isotropic => "isotropic",
        }
    }
}

/// One physical quantity of a family (a shared one such as `kd`, or one of each lobe).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldDef {
    /// The name in parameter names (`kd`, `lobe1.cx`, `lobe1.pan`).
    pub name: &'static str,
    /// The key in the JSON form of [`crate::Params`] (usually [`FieldDef::name`]; Lafortune's pan
    /// is stored as `pan_deg`).
    pub key: &'static str,
    /// The value a lobe's field takes when no parameter of the lobe's kind sets it (the pan of
    /// an isotropic lobe) and when a JSON lobe leaves it out (only where
    /// [`FieldDef::optional`]).
    pub default: f64,
    /// Whether the JSON form may leave the field out (it then reads as `default`).
    pub optional: bool,
    /// The bounds a physical value must lie in ([`crate::Params::validate`]) and the default bounds
    /// of the parameters that set it.
    pub bounds: (f64, f64),
}

/// How a parameter's physical value maps to the coordinate the optimiser sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Coord {
    /// The value itself.
    Identity,
    /// `u = ln(1 + v)` (for values `>= 0`: Lafortune's exponent).
    Log1p,
    /// `u = ln v` (for values `> 0`: roughnesses, whose lower bound must then be positive).
    Log,
}

impl Coord {
    /// Physical value -> optimiser coordinate.
    #[inline]
    pub fn to_internal(self, v: f64) -> f64 {
        match self {
            Coord::Identity => v,
            Coord::Log1p => v.ln_1p(),
            Coord::Log => v.ln(),
        }
    }

    /// Optimiser coordinate -> physical value.
    #[inline]
    pub fn to_physical(self, x: f64) -> f64 {
        match self {
            Coord::Identity => x,
            Coord::Log1p => x.exp_m1(),
            Coord::Log => x.exp(),
        }
    }

    /// `dv / dx` at the physical value `v` (the chain-rule factor of a Jacobian column).
    #[inline]
    pub fn dv_dx(self, v: f64) -> f64 {
        match self {
            Coord::Identity => 1.0,
            Coord::Log1p => 1.0 + v,
            Coord::Log => v,
        }
    }

    /// Whether `[lo, hi]` is inside the coordinate's domain (`Log1p`: `lo > -1`; `Log`:
    /// `lo > 0`).
    pub fn admits(self, lo: f64) -> bool {
        match self {
            Coord::Identity => true,
            Coord::Log1p => lo > -1.0,
            Coord::Log => lo > 0.0,
        }
    }
}

/// What a parameter is, for the choices that apply to a class of parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// A weight or scale (coefficients, `kd`, `ks`, Fresnel): always in its own units.
    Linear,
    /// A shape parameter whose useful range spans decades (an exponent, a roughness): the
    /// `exponent` coordinate switch (raw or the family's log coordinate) and the start
    /// distributions apply to it.
    Shape,
    /// An angle in degrees (a lobe's pan rotation).
    Angle,
}

/// A parameter of a lobe kind (or a shared one) as the optimiser sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamDef {
    /// The name after `lobeK.` (or the whole name for a shared parameter).
    pub name: &'static str,
    /// The fields it sets (indices into [`crate::Family::lobe_fields`] or [`crate::Family::shared_fields`]);
    /// more than one ties them (all take the parameter's value).
    pub fields: &'static [usize],
    /// The coordinate the optimiser sees by default.
    pub coord: Coord,
    /// What the parameter is.
    pub role: Role,
}

/// One parameter of a layout: its definition, lobe, physical bounds, coordinate and fixed
/// value if any (what [`crate::Family::evaluator`] reads to map the free vector).
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutParam {
    /// The full name (`kd`, `lobe2.n`).
    pub name: String,
    /// The family's definition.
    pub def: ParamDef,
    /// The lobe (from 0), `None` for a shared parameter.
    pub lobe: Option<usize>,
    /// Lower physical bound.
    pub lo: f64,
    /// Upper physical bound.
    pub hi: f64,
    /// The coordinate the optimiser sees.
    pub coord: Coord,
    /// The physical value it is fixed at, `None` when free.
    pub fixed: Option<f64>,
}
