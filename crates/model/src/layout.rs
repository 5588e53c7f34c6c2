//! Parameter layouts: which parameters are free, their bounds and internal coordinates.
//!
//! Parameters are named `"kd"`, then per lobe `k` (from 1) `"lobeK.cx"`, `"lobeK.cy"`,
//! `"lobeK.cz"`, `"lobeK.n"`, `"lobeK.pan"` for an anisotropic lobe and `"lobeK.cxy"`,
//! `"lobeK.cz"`, `"lobeK.n"` for an isotropic one. The free vector seen by an optimiser holds
//! the free parameters in that order, in *internal* coordinates:
//! - C's and kd: as they are;
//! - pan: degrees (so Jacobian columns of pan are per degree);
//! - n: raw `n` ([`ExponentCoord::Raw`]) or `u = ln(1 + n)` ([`ExponentCoord::Log1p`], the
//!   default); bounds are mapped the same way.

use crate::params::{BrdfParams, Lobe, parse_lobe_name};
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
    /// Bounds with `lo > hi`, non-finite, or (exponent) below 0.
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
}

/// The kind of a lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LobeKind {
    /// Cx, Cy, Cz, n, pan: the directions are rotated about the normal by pan.
    Anisotropic,
    /// Cxy, Cz, n: Cx = Cy, no pan and no rotation work.
    Isotropic,
}

/// Internal coordinate of the specular exponent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ExponentCoord {
    /// The optimiser sees `n` itself.
    Raw,
    /// The optimiser sees `u = ln(1 + n)`.
    #[default]
    Log1p,
}

impl ExponentCoord {
    /// Physical `n` -> internal coordinate.
    pub fn to_internal(self, n: f64) -> f64 {
        match self {
            ExponentCoord::Raw => n,
            ExponentCoord::Log1p => n.ln_1p(),
        }
    }
    /// Internal coordinate -> physical `n`.
    pub fn to_physical(self, x: f64) -> f64 {
        match self {
            ExponentCoord::Raw => x,
            ExponentCoord::Log1p => x.exp_m1(),
        }
    }
    /// `dn / dx` at internal coordinate `x` (physical `n`).
    pub fn dn_dx(self, n: f64) -> f64 {
        match self {
            ExponentCoord::Raw => 1.0,
            ExponentCoord::Log1p => 1.0 + n,
        }
    }
}

/// What a parameter is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Field {
    Kd,
    Cx,
    Cy,
    Cxy,
    Cz,
    N,
    Pan,
}

impl Field {
    fn suffix(self) -> &'static str {
        match self {
            Field::Kd => "kd",
            Field::Cx => "cx",
            Field::Cy => "cy",
            Field::Cxy => "cxy",
            Field::Cz => "cz",
            Field::N => "n",
            Field::Pan => "pan",
        }
    }
    fn default_bounds(self) -> (f64, f64) {
        match self {
            Field::Kd => (0.0, 1.0),
            Field::Cx | Field::Cy | Field::Cxy | Field::Cz => (-1.5, 1.5),
            Field::N => (0.0, 10000.0),
            Field::Pan => (-90.0, 90.0),
        }
    }
}

/// One parameter of a layout (physical bounds, optional fixed value).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Param {
    pub name: String,
    pub field: Field,
    /// Zero-based lobe index (unused for kd).
    pub lobe: usize,
    pub lo: f64,
    pub hi: f64,
    pub fixed: Option<f64>,
}

/// Builder for [`Layout`]: start from [`Layout::builder`], then fix parameters, override
/// bounds and choose the exponent coordinate.
#[derive(Clone, Debug)]
pub struct LayoutBuilder {
    kinds: Vec<LobeKind>,
    params: Vec<Param>,
    coord: ExponentCoord,
}

impl LayoutBuilder {
    fn find(&mut self, name: &str) -> Result<&mut Param, ModelError> {
        let expected = || {
            self.params
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        match self.params.iter().position(|p| p.name == name) {
            Some(i) => Ok(&mut self.params[i]),
            None => Err(ModelError::UnknownParameter {
                name: name.to_string(),
                expected: expected(),
            }),
        }
    }

    /// Fixes parameter `name` at physical `value` (pan in degrees, n raw): it gets no entry in
    /// the free vector. Checked against the bounds in [`LayoutBuilder::build`].
    pub fn fix(mut self, name: &str, value: f64) -> Result<Self, ModelError> {
        self.find(name)?.fixed = Some(value);
        Ok(self)
    }

    /// Overrides the physical bounds of `name` (pan in degrees, n raw).
    pub fn bounds(mut self, name: &str, lo: f64, hi: f64) -> Result<Self, ModelError> {
        let p = self.find(name)?;
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
        if p.field == Field::N && lo < 0.0 {
            return Err(bad("the exponent must be >= 0"));
        }
        p.lo = lo;
        p.hi = hi;
        Ok(self)
    }

    /// Chooses the exponent's internal coordinate (default [`ExponentCoord::Log1p`]).
    pub fn exponent_coord(mut self, c: ExponentCoord) -> Self {
        self.coord = c;
        self
    }

    /// Validates fixed values against bounds and builds the layout.
    pub fn build(self) -> Result<Layout, ModelError> {
        for p in &self.params {
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
                let (lo, hi) = if p.field == Field::N {
                    (self.coord.to_internal(p.lo), self.coord.to_internal(p.hi))
                } else {
                    (p.lo, p.hi)
                };
                lower.push(lo);
                upper.push(hi);
            }
        }
        Ok(Layout {
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

/// A parameter layout: lobe kinds, free and fixed parameters, bounds in internal coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    kinds: Vec<LobeKind>,
    pub(crate) params: Vec<Param>,
    coord: ExponentCoord,
    /// Indices into `params` of the free parameters, in free-vector order.
    pub(crate) free: Vec<usize>,
    free_names: Vec<String>,
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl Layout {
    /// Starts a layout with one lobe per entry of `kinds`, all parameters free, Table 1 bounds
    /// (C in [-1.5, 1.5], n in [0, 10000], pan in [-90, 90] degrees, kd in [0, 1]).
    pub fn builder(kinds: &[LobeKind]) -> LayoutBuilder {
        let mut params = vec![param("kd".into(), Field::Kd, 0)];
        for (k, kind) in kinds.iter().enumerate() {
            let fields: &[Field] = match kind {
                LobeKind::Anisotropic => &[Field::Cx, Field::Cy, Field::Cz, Field::N, Field::Pan],
                LobeKind::Isotropic => &[Field::Cxy, Field::Cz, Field::N],
            };
            for &f in fields {
                params.push(param(format!("lobe{}.{}", k + 1, f.suffix()), f, k));
            }
        }
        LayoutBuilder {
            kinds: kinds.to_vec(),
            params,
            coord: ExponentCoord::default(),
        }
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
    /// The exponent's internal coordinate.
    pub fn exponent_coord(&self) -> ExponentCoord {
        self.coord
    }
    /// True when free parameter `free_index` is an exponent `n`.
    pub fn is_exponent(&self, free_index: usize) -> bool {
        self.free
            .get(free_index)
            .is_some_and(|&i| self.params[i].field == Field::N)
    }
    /// True when free parameter `free_index` is a pan angle (degrees).
    pub fn is_pan(&self, free_index: usize) -> bool {
        self.free
            .get(free_index)
            .is_some_and(|&i| self.params[i].field == Field::Pan)
    }

    /// Internal free vector -> physical parameters (fixed parameters filled in; isotropic lobes
    /// get `cx = cy = cxy`, pan 0). Missing entries of a short `x` read as 0.
    pub fn decode(&self, x: &[f64]) -> BrdfParams {
        let mut out = BrdfParams {
            kd: 0.0,
            lobes: vec![
                Lobe {
                    cx: 0.0,
                    cy: 0.0,
                    cz: 0.0,
                    n: 0.0,
                    pan_deg: 0.0
                };
                self.kinds.len()
            ],
        };
        let mut next = 0;
        for p in &self.params {
            let v = match p.fixed {
                Some(v) => v,
                None => {
                    let v = x.get(next).copied().unwrap_or(0.0);
                    next += 1;
                    if p.field == Field::N {
                        self.coord.to_physical(v)
                    } else {
                        v
                    }
                }
            };
            match p.field {
                Field::Kd => out.kd = v,
                Field::Cx => out.lobes[p.lobe].cx = v,
                Field::Cy => out.lobes[p.lobe].cy = v,
                Field::Cxy => {
                    out.lobes[p.lobe].cx = v;
                    out.lobes[p.lobe].cy = v;
                }
                Field::Cz => out.lobes[p.lobe].cz = v,
                Field::N => out.lobes[p.lobe].n = v,
                Field::Pan => out.lobes[p.lobe].pan_deg = v,
            }
        }
        out
    }

    /// Physical parameters -> internal free vector. Isotropic lobes take `cxy` from `cx`;
    /// lobes missing from `p` read as zeros. Values are not clamped to the bounds.
    pub fn encode(&self, p: &BrdfParams) -> Vec<f64> {
        self.free
            .iter()
            .map(|&i| {
                let q = &self.params[i];
                let lobe = p.lobes.get(q.lobe).copied().unwrap_or(Lobe {
                    cx: 0.0,
                    cy: 0.0,
                    cz: 0.0,
                    n: 0.0,
                    pan_deg: 0.0,
                });
                match q.field {
                    Field::Kd => p.kd,
                    Field::Cx | Field::Cxy => lobe.cx,
                    Field::Cy => lobe.cy,
                    Field::Cz => lobe.cz,
                    Field::N => self.coord.to_internal(lobe.n),
                    Field::Pan => lobe.pan_deg,
                }
            })
            .collect()
    }

    /// Index in the free vector of parameter `name`, if it is free.
    pub fn free_index(&self, name: &str) -> Option<usize> {
        self.free_names.iter().position(|n| n == name)
    }
}

fn param(name: String, field: Field, lobe: usize) -> Param {
    let (lo, hi) = field.default_bounds();
    Param {
        name,
        field,
        lobe,
        lo,
        hi,
        fixed: None,
    }
}

/// Checks that a name has the `lobeK.field` or `kd` shape (used in error messages elsewhere).
pub fn is_parameter_name(name: &str) -> bool {
    name == "kd"
        || parse_lobe_name(name)
            .is_some_and(|(_, f)| matches!(f, "cx" | "cy" | "cxy" | "cz" | "n" | "pan"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::named_params;

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
        let x = l.encode(&p);
        let q = l.decode(&x);
        assert!((q.lobes[0].n - 20.0).abs() < 1e-12);
        assert!((q.lobes[1].n - 7.0).abs() < 1e-12);
        assert_eq!(q.lobes[1].cy, 0.5);
        assert_eq!(q.lobes[0].pan_deg, 45.0);
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
        let tuning = named_params("tuning").unwrap();
        assert_eq!(raw.decode(&raw.encode(&tuning)), tuning);
        assert!(is_parameter_name("lobe2.cxy") && !is_parameter_name("lobe2.q"));
    }
}
