//! Parameter layouts: which parameters of a family's lobes are free, their bounds and the
//! coordinates the optimiser sees.
//!
//! Parameters are named after the family's fields: the shared ones as they are (`"kd"`), then
//! per lobe `k` (from 1) `"lobeK.<name>"` for each parameter of the lobe's kind (Lafortune:
//! `cx, cy, cz, n, pan` for an anisotropic lobe, `cxy, cz, n` for an isotropic one). The free
//! vector seen by an optimiser holds the free parameters in that order, in *internal*
//! coordinates: each parameter's [`Coord`] (Lafortune's `n` as `ln(1 + n)` by default, its
//! other parameters as they are; pan angles in degrees), with [`ExponentCoord::Raw`] putting
//! every shape parameter ([`Role::Shape`]) in its own units instead; bounds are mapped the same
//! way.

use crate::data::DataSet;
use crate::family::{Coord, FamilyRef, FieldDef, LayoutParam, LobeKind, ParamDef, Role};
use crate::params::{MAX_LOBES, Params};
use crate::samples::Samples;
use serde::{Deserialize, Serialize};

/// Errors building a layout.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The name is not a parameter of this layout.
    #[error("unknown parameter `{name}` (expected one of: {expected})")]
    UnknownParameter {
        /// The name given.
        name: String,
        /// The names of this layout, comma-separated.
        expected: String,
    },
    /// Bounds with `lo > hi`, non-finite, or outside the coordinate's domain.
    #[error("invalid bounds for `{name}`: [{lo}, {hi}] ({why})")]
    InvalidBounds {
        /// Parameter name.
        name: String,
        /// Lower bound given.
        lo: f64,
        /// Upper bound given.
        hi: f64,
        /// What is wrong.
        why: &'static str,
    },
    /// A fixed value outside the parameter's bounds or not finite.
    #[error("fixed value {value} for `{name}` is outside its bounds [{lo}, {hi}]")]
    FixedOutOfBounds {
        /// Parameter name.
        name: String,
        /// Value given.
        value: f64,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// The family has no lobe of this kind.
    #[error("the {family} family has no {kind} lobes (it has: {available})")]
    UnsupportedKind {
        /// The family.
        family: String,
        /// The kind asked for.
        kind: &'static str,
        /// The kinds it has.
        available: String,
    },
    /// More lobes than [`MAX_LOBES`].
    #[error("{count} lobes: expected at most {MAX_LOBES}")]
    TooManyLobes {
        /// Lobes asked for.
        count: usize,
    },
    /// Bounds reaching beyond the family's box where that box may not be widened (only an
    /// exponent's may, up to [`MAX_EXPONENT`]; see [`LayoutBuilder::bounds`]).
    #[error("bounds [{lo}, {hi}] for `{name}` reach beyond {limit}")]
    BeyondBox {
        /// Parameter name.
        name: String,
        /// Lower bound given.
        lo: f64,
        /// Upper bound given.
        hi: f64,
        /// The widest bounds allowed, in words (`its box [-1.5, 1.5] (only an exponent's box
        /// may be widened)`).
        limit: String,
    },
}

/// The largest exponent a bound may admit (Lafortune's `n`; the Ashikhmin-Shirley and
/// Blinn-Phong exponents' boxes already reach it). Table 1's box stops at 10,000, but measured
/// materials need more: 5 of Ngan et al.'s 86 MERL fits reach 16,600. The kernels' accuracy
/// depends on `n ln d`, not on `n` (the result is 0 or overflows outside `|n ln d| <= 745`),
/// and `crates/model/tests/kernels.rs` checks every kernel up to this exponent.
pub const MAX_EXPONENT: f64 = 1e6;

/// The coordinate of the shape parameters ([`Role::Shape`]: Lafortune's exponent, a
/// roughness): the spec's `exponent` key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ExponentCoord {
    /// The optimiser sees the parameter itself.
    Raw,
    /// The optimiser sees the family's log coordinate of it (Lafortune: `u = ln(1 + n)`).
    #[default]
    Log1p,
}

impl ExponentCoord {
    /// The coordinate a parameter defined as `def` gets under this choice.
    pub fn coord_of(self, def: &ParamDef) -> Coord {
        match (self, def.role) {
            (ExponentCoord::Raw, Role::Shape) => Coord::Identity,
            _ => def.coord,
        }
    }

    /// Lafortune's exponent `n` -> internal coordinate.
    pub fn to_internal(self, n: f64) -> f64 {
        self.lafortune().to_internal(n)
    }

    /// Internal coordinate -> Lafortune's exponent `n`.
    pub fn to_physical(self, x: f64) -> f64 {
        self.lafortune().to_physical(x)
    }

    /// `dn / dx` at Lafortune's exponent `n`.
    pub fn dn_dx(self, n: f64) -> f64 {
        self.lafortune().dv_dx(n)
    }

    fn lafortune(self) -> Coord {
        match self {
            ExponentCoord::Raw => Coord::Identity,
            ExponentCoord::Log1p => Coord::Log1p,
        }
    }
}

/// Builder for [`Layout`]: start from [`Layout::builder`] or [`Layout::builder_for`], then fix
/// parameters, override bounds and choose the shape coordinate.
#[derive(Clone, Debug)]
pub struct LayoutBuilder {
    family: FamilyRef,
    kinds: Vec<LobeKind>,
    params: Vec<LayoutParam>,
    coord: ExponentCoord,
}

impl LayoutBuilder {
    fn find(&mut self, name: &str) -> Result<&mut LayoutParam, ModelError> {
        match self.params.iter().position(|p| p.name == name) {
            Some(i) => Ok(&mut self.params[i]),
            None => Err(ModelError::UnknownParameter {
                name: name.to_string(),
                expected: self
                    .params
                    .iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }

    /// Fixes parameter `name` at physical `value` (angles in degrees, shape parameters in
    /// their own units): it gets no entry in the free vector. Checked against the bounds in
    /// [`LayoutBuilder::build`].
    pub fn fix(mut self, name: &str, value: f64) -> Result<Self, ModelError> {
        self.find(name)?.fixed = Some(value);
        Ok(self)
    }

    /// Overrides the physical bounds of `name`: inside the family's box (its field's bounds,
    /// Table 1 for Lafortune) any finite `lo <= hi` in the coordinate's domain; beyond it only
    /// for an exponent (a shape parameter in the `ln(1 + n)` coordinate: Lafortune's `n`), up
    /// to `[0, MAX_EXPONENT]` ([`MAX_EXPONENT`]).
    pub fn bounds(mut self, name: &str, lo: f64, hi: f64) -> Result<Self, ModelError> {
        let family = self.family.clone();
        let p = self.find(name)?;
        // The family's box: the bounds of the (first) field the parameter sets.
        let fields = match p.lobe {
            Some(_) => family.lobe_fields(),
            None => family.shared_fields(),
        };
        let (box_lo, box_hi) = fields[p.def.fields[0]].bounds;
        let bad = |why| ModelError::InvalidBounds {
            name: name.to_string(),
            lo,
            hi,
            why,
        };
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(bad("bounds must be finite"));
        }
        if lo > hi {
            return Err(bad("lower bound above upper bound"));
        }
        if !p.def.coord.admits(lo) {
            return Err(bad(match p.def.coord {
                Coord::Log => "the parameter must be > 0",
                _ => "the exponent must be >= 0",
            }));
        }
        if p.def.coord == Coord::Log1p && lo < 0.0 {
            return Err(bad("the exponent must be >= 0"));
        }
        if lo < box_lo || hi > box_hi {
            let exponent = p.def.role == Role::Shape && p.def.coord == Coord::Log1p;
            let limit = if !exponent {
                Some(format!(
                    "its box [{box_lo}, {box_hi}] (only an exponent's box may be widened)"
                ))
            } else if hi > MAX_EXPONENT {
                Some(format!(
                    "[{box_lo}, {MAX_EXPONENT:e}], the widest an exponent's bounds may be (the \
                     range the kernels are checked over)"
                ))
            } else {
                None
            };
            if let Some(limit) = limit {
                return Err(ModelError::BeyondBox {
                    name: name.to_string(),
                    lo,
                    hi,
                    limit,
                });
            }
        }
        p.lo = lo;
        p.hi = hi;
        Ok(self)
    }

    /// Chooses the shape parameters' internal coordinate (default [`ExponentCoord::Log1p`]).
    pub fn exponent_coord(mut self, c: ExponentCoord) -> Self {
        self.coord = c;
        self
    }

    /// Validates fixed values against bounds and builds the layout.
    pub fn build(mut self) -> Result<Layout, ModelError> {
        if self.kinds.len() > MAX_LOBES {
            return Err(ModelError::TooManyLobes {
                count: self.kinds.len(),
            });
        }
        for p in &mut self.params {
            p.coord = self.coord.coord_of(&p.def);
            if let Some(v) = p.fixed
                && !(v.is_finite() && v >= p.lo && v <= p.hi)
            {
                return Err(ModelError::FixedOutOfBounds {
                    name: p.name.clone(),
                    value: v,
                    lo: p.lo,
                    hi: p.hi,
                });
            }
        }
        let mut free = Vec::new();
        let mut free_names = Vec::new();
        let mut lower = Vec::new();
        let mut upper = Vec::new();
        for (i, p) in self.params.iter().enumerate() {
            if p.fixed.is_none() {
                free.push(i);
                free_names.push(p.name.clone());
                lower.push(p.coord.to_internal(p.lo));
                upper.push(p.coord.to_internal(p.hi));
            }
        }
        Ok(Layout {
            family: self.family,
            kinds: self.kinds,
            params: self.params,
            coord: self.coord,
            free,
            free_names,
            lower,
            upper,
        })
    }
}

/// A parameter layout: the family, lobe kinds, free and fixed parameters, bounds in internal
/// coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    family: FamilyRef,
    kinds: Vec<LobeKind>,
    params: Vec<LayoutParam>,
    coord: ExponentCoord,
    /// Indices into `params` of the free parameters, in free-vector order.
    free: Vec<usize>,
    free_names: Vec<String>,
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl Layout {
    /// A Lafortune layout with one lobe per entry of `kinds`, all parameters free, Table 1
    /// bounds (C in [-1.5, 1.5], n in [0, 10000], pan in [-90, 90] degrees, kd in [0, 1]).
    pub fn builder(kinds: &[LobeKind]) -> LayoutBuilder {
        Self::builder_for(&FamilyRef::lafortune(), kinds).expect("Lafortune has both lobe kinds")
    }

    /// A layout of `family` with one lobe per entry of `kinds`, every parameter free within
    /// its field's bounds.
    ///
    /// # Errors
    /// [`ModelError::UnsupportedKind`] when the family has no lobe of a kind asked for (more
    /// than [`MAX_LOBES`] lobes fail in [`LayoutBuilder::build`]).
    pub fn builder_for(
        family: &FamilyRef,
        kinds: &[LobeKind],
    ) -> Result<LayoutBuilder, ModelError> {
        let mut params: Vec<LayoutParam> = family
            .shared_params()
            .iter()
            .map(|d| param(family.shared_fields(), d.name.to_string(), *d, None))
            .collect();
        for (k, &kind) in kinds.iter().enumerate() {
            let defs = family
                .lobe_params(kind)
                .ok_or_else(|| ModelError::UnsupportedKind {
                    family: family.name().to_string(),
                    kind: kind.name(),
                    available: family
                        .kinds()
                        .iter()
                        .map(|k| k.name())
                        .collect::<Vec<_>>()
                        .join(", "),
                })?;
            for d in defs {
                let name = format!("lobe{}.{}", k + 1, d.name);
                params.push(param(family.lobe_fields(), name, *d, Some(k)));
            }
        }
        Ok(LayoutBuilder {
            family: family.clone(),
            kinds: kinds.to_vec(),
            params,
            coord: ExponentCoord::default(),
        })
    }

    /// A layout that evaluates `p` as given: as many lobes, each of the family's fullest kind
    /// (anisotropic where the family has it, so every lobe field is its own parameter), all
    /// free. Encoding `p` with it and evaluating gives `p`'s model (values outside the default
    /// bounds are not clamped by [`Layout::encode`]).
    ///
    /// # Errors
    /// [`ModelError::TooManyLobes`] beyond [`MAX_LOBES`] lobes.
    pub fn of_params(p: &Params) -> Result<Layout, ModelError> {
        let family = p.family();
        let kind = if family.kinds().contains(&LobeKind::Anisotropic) {
            LobeKind::Anisotropic
        } else {
            family.kinds()[0]
        };
        Self::builder_for(family, &vec![kind; p.lobe_count()])?.build()
    }

    /// The model family.
    pub fn family(&self) -> &FamilyRef {
        &self.family
    }
    /// Number of free parameters (length of the internal vector).
    pub fn dim(&self) -> usize {
        self.free.len()
    }
    /// Lower bounds of the free parameters, internal coordinates.
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }
    /// Upper bounds of the free parameters, internal coordinates.
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }
    /// Names of the free parameters in free-vector order.
    pub fn free_names(&self) -> &[String] {
        &self.free_names
    }
    /// Names of all parameters (free and fixed) in canonical order.
    pub fn all_names(&self) -> Vec<&str> {
        self.params.iter().map(|p| p.name.as_str()).collect()
    }
    /// Every parameter (free and fixed) in canonical order.
    pub fn params(&self) -> &[LayoutParam] {
        &self.params
    }
    /// The free parameter at `free_index`.
    pub fn free_param(&self, free_index: usize) -> Option<&LayoutParam> {
        self.free.get(free_index).map(|&i| &self.params[i])
    }
    /// The value a parameter is fixed at (physical), or `None` if it is free or unknown.
    pub fn fixed_value(&self, name: &str) -> Option<f64> {
        self.params.iter().find(|p| p.name == name)?.fixed
    }
    /// Physical bounds of any parameter by name.
    pub fn physical_bounds(&self, name: &str) -> Option<(f64, f64)> {
        let p = self.params.iter().find(|p| p.name == name)?;
        Some((p.lo, p.hi))
    }
    /// The lobe kinds.
    pub fn kinds(&self) -> &[LobeKind] {
        &self.kinds
    }
    /// Number of lobes.
    pub fn lobe_count(&self) -> usize {
        self.kinds.len()
    }
    /// One line for a printed fit saying which other parameter sets give the same BRDF, or
    /// `None` when there are none (a single lobe without a pan). A fit reached from another
    /// seed, or a generating parameter set, may be printed in another of these forms, which
    /// looks like a different answer without it (issue 45.23); docs/model.md, "Equivalent
    /// parameter sets", states and the model's tests check each form.
    pub fn equivalence_note(&self) -> Option<String> {
        let mut forms = Vec::new();
        if self.kinds.len() > 1 {
            forms.push("the lobes in another order");
        }
        let panned = self.kinds.contains(&LobeKind::Anisotropic)
            && self
                .family
                .lobe_params(LobeKind::Anisotropic)
                .is_some_and(|defs| defs.iter().any(|d| d.role == Role::Angle));
        if panned {
            forms.push(
                "an anisotropic lobe with pan + or - 90 degrees and its x and y parameters \
                 swapped (pan -90 and 90 are one angle)",
            );
        }
        (!forms.is_empty()).then(|| {
            format!(
                "note: the same BRDF has other parameter sets ({}); see docs/model.md, \
                 \"Equivalent parameter sets\"",
                forms.join("; ")
            )
        })
    }

    /// The shape parameters' internal coordinate.
    pub fn exponent_coord(&self) -> ExponentCoord {
        self.coord
    }
    /// The coordinate free parameter `free_index` is held in (identity when out of range).
    pub fn coord(&self, free_index: usize) -> Coord {
        self.free_param(free_index)
            .map_or(Coord::Identity, |p| p.coord)
    }
    /// True when free parameter `free_index` is a shape parameter ([`Role::Shape`]: an
    /// exponent `n`, a roughness).
    pub fn is_exponent(&self, free_index: usize) -> bool {
        self.free_param(free_index)
            .is_some_and(|p| p.def.role == Role::Shape)
    }
    /// True when free parameter `free_index` is an angle in degrees (a pan).
    pub fn is_pan(&self, free_index: usize) -> bool {
        self.free_param(free_index)
            .is_some_and(|p| p.def.role == Role::Angle)
    }

    /// Internal free vector -> physical parameters (fixed parameters filled in; tied fields
    /// take their parameter's value, fields no parameter sets their default). Missing entries
    /// of a short `x` read as 0.
    pub fn decode(&self, x: &[f64]) -> Params {
        let mut out = Params::defaults(self.family.clone(), self.kinds.len());
        let mut next = 0;
        for p in &self.params {
            let v = match p.fixed {
                Some(v) => v,
                None => {
                    let v = x.get(next).copied().unwrap_or(0.0);
                    next += 1;
                    p.coord.to_physical(v)
                }
            };
            let target = match p.lobe {
                None => out.shared_mut(),
                Some(k) => out.lobe_mut(k),
            };
            for &f in p.def.fields {
                target[f] = v;
            }
        }
        out
    }

    /// Physical parameters -> internal free vector (a tied parameter takes its first
    /// field's value); lobes missing from `p` read as zeros. Values are not clamped to the
    /// bounds. Takes [`Params`] or the Lafortune family's [`crate::BrdfParams`], by reference.
    pub fn encode(&self, p: impl Into<Params>) -> Vec<f64> {
        let p: Params = p.into();
        self.free
            .iter()
            .map(|&i| {
                let q = &self.params[i];
                let f = q.def.fields[0];
                let v = match q.lobe {
                    None => p.shared().get(f).copied().unwrap_or(0.0),
                    Some(k) => p
                        .lobes()
                        .get(k)
                        .and_then(|l| l.get(f))
                        .copied()
                        .unwrap_or(0.0),
                };
                q.coord.to_internal(v)
            })
            .collect()
    }

    /// Index in the free vector of parameter `name`, if it is free.
    pub fn free_index(&self, name: &str) -> Option<usize> {
        self.free_names.iter().position(|n| n == name)
    }

    /// The family's per-sample columns of `data` (what this layout's evaluators read).
    pub fn prepare(&self, data: &DataSet) -> Samples {
        self.family.prepare(data)
    }
}

fn param(fields: &[FieldDef], name: String, def: ParamDef, lobe: Option<usize>) -> LayoutParam {
    let (lo, hi) = fields[def.fields[0]].bounds;
    LayoutParam {
        name,
        def,
        lobe,
        lo,
        hi,
        coord: def.coord,
        fixed: None,
    }
}

/// Checks that a name has the `lobeK.field` or `kd` shape of a Lafortune parameter (used in
/// error messages elsewhere).
pub fn is_parameter_name(name: &str) -> bool {
    name == "kd"
        || crate::params::parse_lobe_name(name)
            .is_some_and(|(_, f)| matches!(f, "cx" | "cy" | "cxy" | "cz" | "n" | "pan"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BrdfParams, Lobe, named_params};

    #[test]
    fn names_bounds_and_round_trip() {
        let l = Layout::builder(&[LobeKind::Anisotropic, LobeKind::Isotropic])
            .fix("lobe1.pan", 45.0)
            .unwrap()
            .bounds("lobe2.n", 1.0, 100.0)
            .unwrap()
            .build()
            .unwrap();
        assert_eq!(
            l.free_names(),
            &[
                "kd",
                "lobe1.cx",
                "lobe1.cy",
                "lobe1.cz",
                "lobe1.n",
                "lobe2.cxy",
                "lobe2.cz",
                "lobe2.n"
            ]
        );
        assert_eq!(l.dim(), 8);
        assert!(l.is_exponent(4) && l.is_exponent(7) && !l.is_exponent(0));
        assert!((l.upper()[4] - 10001f64.ln()).abs() < 1e-12);
        assert!((l.lower()[7] - 2f64.ln()).abs() < 1e-12);
        let p = BrdfParams {
            kd: 0.2,
            lobes: vec![
                Lobe {
                    cx: -1.0,
                    cy: 0.8,
                    cz: 0.96,
                    n: 20.0,
                    pan_deg: 45.0,
                },
                Lobe::isotropic(0.5, 0.3, 7.0),
            ],
        };
        let x = l.encode(Params::from(&p));
        let q = BrdfParams::try_from(&l.decode(&x)).unwrap();
        assert!((q.lobes[0].n - 20.0).abs() < 1e-12);
        assert!((q.lobes[1].n - 7.0).abs() < 1e-12);
        assert_eq!(q.lobes[1].cy, 0.5);
        assert_eq!(q.lobes[0].pan_deg, 45.0);
    }

    /// Table 1's box is the default; an exponent's bounds may reach beyond it (measured metals
    /// need n = 16,600) up to MAX_EXPONENT, and no other parameter's may: the error names the
    /// bound.
    #[test]
    fn only_an_exponent_widens_beyond_the_box() {
        let b = Layout::builder(&[LobeKind::Isotropic]);
        let wide = b.clone().bounds("lobe1.n", 0.0, 20000.0).unwrap();
        let l = wide.clone().build().unwrap();
        assert!((l.upper()[3] - 20001f64.ln()).abs() < 1e-12);
        assert_eq!(l.physical_bounds("lobe1.n"), Some((0.0, 20000.0)));
        assert!(wide.fix("lobe1.n", 16600.0).unwrap().build().is_ok());
        assert!(b.clone().fix("lobe1.n", 16600.0).unwrap().build().is_err());
        let e = b.clone().bounds("lobe1.n", 0.0, 2e6).unwrap_err();
        assert_eq!(
            e.to_string(),
            "bounds [0, 2000000] for `lobe1.n` reach beyond [0, 1e6], the widest an exponent's \
             bounds may be (the range the kernels are checked over)"
        );
        let e = b.clone().bounds("kd", 0.0, 2.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "bounds [0, 2] for `kd` reach beyond its box [0, 1] (only an exponent's box may be \
             widened)"
        );
        assert!(matches!(
            b.bounds("lobe1.cz", -2.0, 1.0),
            Err(ModelError::BeyondBox { .. })
        ));
        // Other families: Ashikhmin-Shirley's exponents already reach 1e6; a roughness (GGX's
        // alpha, in a log coordinate) keeps its box.
        let ash = crate::family("ashikhmin-shirley").unwrap();
        let a = Layout::builder_for(&ash, &[LobeKind::Isotropic]).unwrap();
        assert!(a.clone().bounds("lobe1.n", 0.0, 1e6).is_ok());
        assert!(a.bounds("lobe1.n", 0.0, 2e6).is_err());
        let ggx = crate::family("ggx").unwrap();
        let g = Layout::builder_for(&ggx, &[LobeKind::Isotropic]).unwrap();
        assert!(matches!(
            g.bounds("lobe1.alpha", 1e-4, 1.0),
            Err(ModelError::BeyondBox { .. })
        ));
    }

    #[test]
    fn errors_are_typed() {
        let b = Layout::builder(&[LobeKind::Isotropic]);
        assert!(matches!(
            b.clone().fix("lobe1.pan", 0.0),
            Err(ModelError::UnknownParameter { .. })
        ));
        assert!(matches!(
            b.clone().bounds("lobe1.n", -2.0, 1.0),
            Err(ModelError::InvalidBounds { .. })
        ));
        assert!(matches!(
            b.clone().bounds("kd", 1.0, 0.0),
            Err(ModelError::InvalidBounds { .. })
        ));
        assert!(matches!(
            b.fix("lobe1.cz", 2.0).unwrap().build(),
            Err(ModelError::FixedOutOfBounds { .. })
        ));
        let raw = Layout::builder(&[LobeKind::Anisotropic])
            .exponent_coord(ExponentCoord::Raw)
            .build()
            .unwrap();
        assert_eq!(raw.upper()[4], 10000.0);
        assert_eq!(raw.lower()[5], -90.0);
        let tuning = Params::from(named_params("tuning").unwrap());
        assert_eq!(raw.decode(&raw.encode(&tuning)), tuning);
        assert!(is_parameter_name("lobe2.cxy") && !is_parameter_name("lobe2.q"));
    }
}
