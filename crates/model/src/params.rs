//! Physical parameters of any family ([`Params`]) and the errors of parameter sets.

use crate::data::DataSet;
use crate::family::{FamilyRef, FieldDef};
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

/// Most lobes a parameter set or layout has (the paper fits up to 3).
pub const MAX_LOBES: usize = 64;

/// Invalid parameters or synthetic-instance settings; each message names the offending
/// parameter and what was expected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// A parameter is not finite or outside its bounds.
    #[error("{name} = {}: expected a finite value in [{lo}, {hi}]", num(*.value))]
    OutOfRange {
        /// Parameter name as in [`Params::get`] (`kd`, `lobe1.cz`, `lobe2.pan`, ...).
        name: String,
        /// The value given.
        value: f64,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// A name that is not a parameter or field of the family.
    #[error("unknown parameter `{name}` of the {family} family (expected one of: {expected})")]
    UnknownName {
        /// The name given.
        name: String,
        /// The family.
        family: String,
        /// The valid names, comma-separated.
        expected: String,
    },
    /// Parameters of one family given where another's are expected.
    #[error("parameters of the {found} family given where the {expected} family's are expected")]
    WrongFamily {
        /// The family expected.
        expected: String,
        /// The family given.
        found: String,
    },
    /// A lobe or the shared part has the wrong number of values.
    #[error("{what}: {found} values, expected {expected}")]
    WrongLength {
        /// Which part (`shared fields`, `lobe 2`).
        what: String,
        /// Values given.
        found: usize,
        /// Values expected.
        expected: usize,
    },
    /// The family's own checks refused the values.
    #[error("{message}")]
    Invalid {
        /// What is wrong, naming the parameter.
        message: String,
    },
    /// More lobes than [`MAX_LOBES`].
    #[error("{count} lobes: expected at most {MAX_LOBES} (MAX_LOBES)")]
    TooManyLobes {
        /// Lobes given.
        count: usize,
    },
    /// A synthetic sample count of 0 or above [`crate::data::MAX_SAMPLES`].
    #[error(
        "sample count {count}: expected 1 to {} (MAX_SAMPLES)",
        crate::data::MAX_SAMPLES
    )]
    SampleCount {
        /// Count given.
        count: usize,
    },
    /// A noise level that is not finite, negative or above [`crate::data::MAX_SIGMA`].
    #[error(
        "sigma = {}: expected a finite value in [0, {}] (MAX_SIGMA)",
        num(*.sigma),
        crate::data::MAX_SIGMA
    )]
    Sigma {
        /// Sigma given.
        sigma: f64,
    },
    /// The parameters give a NaN or infinite model value (a huge exponent overflowing).
    #[error(
        "the parameters give the non-finite value {} at synthetic sample {index}: \
         expected finite values (lower the exponents or the C's)",
        num(*.value)
    )]
    NonFiniteValue {
        /// Sample index (from 0).
        index: usize,
        /// The value.
        value: f64,
    },
}

/// Formats a number readably: exponent form when huge or tiny (`1e300`, not 301 digits).
pub(crate) fn num(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

pub(crate) fn check(
    name: impl FnOnce() -> String,
    value: f64,
    (lo, hi): (f64, f64),
) -> Result<(), ParamError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(ParamError::OutOfRange {
            name: name(),
            value,
            lo,
            hi,
        })
    }
}

/// A parameter set that gives a model value at any pair of directions: what synthetic
/// instances, polar plots and renders need. [`Params`] (any family) and the Lafortune
/// family's [`crate::BrdfParams`] implement it.
pub trait Reflectance {
    /// The model's value at incident `u` and exitant `v` (both pointing away from the surface,
    /// z the normal), by the family's scalar reference.
    fn value(&self, u: [f64; 3], v: [f64; 3]) -> f64;
    /// Checks the values against the family's bounds (see [`Params::validate`]).
    fn check(&self) -> Result<(), ParamError>;

    /// RMSE of the model (its scalar reference) against the values of `data`; 0 when empty.
    fn rmse_on(&self, data: &DataSet) -> f64 {
        if data.is_empty() {
            return 0.0;
        }
        let ss: f64 = (0..data.len())
            .map(|i| {
                let e = self.value(data.u(i), data.v(i)) - data.value(i);
                e * e
            })
            .sum();
        (ss / data.len() as f64).sqrt()
    }
}

impl Reflectance for Params {
    fn value(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        Params::value(self, u, v)
    }
    fn check(&self) -> Result<(), ParamError> {
        self.validate()
    }
}

/// Splits `"lobe3.cz"` into `(2, "cz")` (zero-based lobe index).
pub(crate) fn parse_lobe_name(name: &str) -> Option<(usize, &str)> {
    let rest = name.strip_prefix("lobe")?;
    let (num, field) = rest.split_once('.')?;
    let k: usize = num.parse().ok()?;
    if k == 0 {
        return None;
    }
    Some((k - 1, field))
}

/// A complete physical parameter set of one family: its shared fields (the diffuse term) and
/// each lobe's fields, in the family's canonical order ([`crate::Family::shared_fields`],
/// [`crate::Family::lobe_fields`]).
///
/// The JSON (and TOML) form is an object: `"family"` (left out for Lafortune, the default),
/// each shared field by its key, and `"lobes"`, a list of objects of each lobe's fields by key,
/// e.g. `{"kd": 0.15, "lobes": [{"cx": -1.0, "cy": 0.8, "cz": 0.96, "n": 20.0, "pan_deg":
/// 45.0}]}`. Unknown keys are refused, fields marked optional may be left out (reading is in
/// the registry, which knows the families). Reading does not check values: call
/// [`Params::validate`].
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    family: FamilyRef,
    shared: Vec<f64>,
    lobes: Vec<Vec<f64>>,
}

impl Params {
    /// A parameter set from its values.
    ///
    /// # Errors
    /// [`ParamError::WrongLength`] when a part has the wrong number of values.
    pub fn new(
        family: FamilyRef,
        shared: Vec<f64>,
        lobes: Vec<Vec<f64>>,
    ) -> Result<Self, ParamError> {
        let wrong = |what: String, found, expected| ParamError::WrongLength {
            what,
            found,
            expected,
        };
        let ns = family.shared_fields().len();
        if shared.len() != ns {
            return Err(wrong("shared fields".into(), shared.len(), ns));
        }
        let nl = family.lobe_fields().len();
        if let Some((k, l)) = lobes.iter().enumerate().find(|(_, l)| l.len() != nl) {
            return Err(wrong(format!("lobe {}", k + 1), l.len(), nl));
        }
        Ok(Params {
            family,
            shared,
            lobes,
        })
    }

    /// `lobes` lobes with every field at its default (0 where the default is unset).
    pub fn defaults(family: FamilyRef, lobes: usize) -> Self {
        let shared = family.shared_fields().iter().map(|f| f.default).collect();
        let lobe: Vec<f64> = family.lobe_fields().iter().map(|f| f.default).collect();
        Params {
            family,
            shared,
            lobes: vec![lobe; lobes],
        }
    }

    /// The family.
    pub fn family(&self) -> &FamilyRef {
        &self.family
    }

    /// The shared fields' values.
    pub fn shared(&self) -> &[f64] {
        &self.shared
    }

    /// Mutable shared fields.
    pub fn shared_mut(&mut self) -> &mut [f64] {
        &mut self.shared
    }

    /// Number of lobes.
    pub fn lobe_count(&self) -> usize {
        self.lobes.len()
    }

    /// Lobe `k`'s values (from 0).
    pub fn lobe(&self, k: usize) -> &[f64] {
        &self.lobes[k]
    }

    /// Mutable lobe `k` (from 0).
    pub fn lobe_mut(&mut self, k: usize) -> &mut [f64] {
        &mut self.lobes[k]
    }

    /// Every lobe's values.
    pub fn lobes(&self) -> &[Vec<f64>] {
        &self.lobes
    }

    /// Keeps the first `n` lobes (a nested model's parameters).
    pub fn truncate_lobes(&mut self, n: usize) {
        self.lobes.truncate(n);
    }

    /// Appends a lobe (its values in the family's field order).
    ///
    /// # Errors
    /// [`ParamError::WrongLength`] for a wrong number of values.
    pub fn push_lobe(&mut self, values: Vec<f64>) -> Result<(), ParamError> {
        let nl = self.family.lobe_fields().len();
        if values.len() != nl {
            return Err(ParamError::WrongLength {
                what: format!("lobe {}", self.lobes.len() + 1),
                found: values.len(),
                expected: nl,
            });
        }
        self.lobes.push(values);
        Ok(())
    }

    /// The model's value at directions `u`, `v` (the family's scalar reference).
    pub fn value(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        self.family.value(&self.shared, &self.lobes, u, v)
    }

    /// Every field name of this set, in canonical order (`kd`, `lobe1.cx`, ...).
    pub fn names(&self) -> Vec<String> {
        self.family.field_names(self.lobes.len())
    }

    /// Where a name points: a shared field, or a lobe's fields (one, or several for a tied
    /// parameter name such as Lafortune's `cxy`).
    fn locate(&self, name: &str) -> Option<(Option<usize>, Vec<usize>)> {
        let f = &self.family;
        if let Some(i) = f.shared_fields().iter().position(|d| d.name == name) {
            return Some((None, vec![i]));
        }
        let (k, rest) = parse_lobe_name(name)?;
        if k >= self.lobes.len() {
            return None;
        }
        if let Some(i) = f.lobe_fields().iter().position(|d| d.name == rest) {
            return Some((Some(k), vec![i]));
        }
        [crate::LobeKind::Anisotropic, crate::LobeKind::Isotropic]
            .iter()
            .filter_map(|&kind| f.lobe_params(kind))
            .flatten()
            .find(|p| p.name == rest)
            .map(|p| (Some(k), p.fields.to_vec()))
    }

    /// A value by name: a shared field (`kd`), a lobe field (`lobeK.cx`, lobes from 1) or a
    /// tied parameter (`lobeK.cxy`: its first field).
    pub fn get(&self, name: &str) -> Option<f64> {
        let (lobe, fields) = self.locate(name)?;
        let i = *fields.first()?;
        Some(match lobe {
            None => self.shared[i],
            Some(k) => self.lobes[k][i],
        })
    }

    /// Sets a value by name (see [`Params::get`]; a tied name sets all its fields). Returns
    /// false when the name does not exist.
    pub fn set(&mut self, name: &str, value: f64) -> bool {
        let Some((lobe, fields)) = self.locate(name) else {
            return false;
        };
        for i in fields {
            match lobe {
                None => self.shared[i] = value,
                Some(k) => self.lobes[k][i] = value,
            }
        }
        true
    }

    /// An error naming the valid names, for a name [`Params::get`] does not know.
    pub fn unknown_name(&self, name: &str) -> ParamError {
        ParamError::UnknownName {
            name: name.to_string(),
            family: self.family.name().to_string(),
            expected: self.names().join(", "),
        }
    }

    /// Checks that every value is finite and inside its field's bounds, that there are at
    /// most [`MAX_LOBES`] lobes, and the family's own checks. The error names the first
    /// offending parameter, e.g. `lobe1.cz = 5: expected a finite value in [-1.5, 1.5]`.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.validate_within(|_| None)
    }

    /// [`Params::validate`] with some bounds replaced: `bounds(name)` gives the bounds to
    /// use instead of the field's (a spec or `fit` that widened one).
    pub fn validate_within(
        &self,
        bounds: impl Fn(&str) -> Option<(f64, f64)>,
    ) -> Result<(), ParamError> {
        let f = &self.family;
        for (d, &v) in f.shared_fields().iter().zip(&self.shared) {
            check(|| d.name.to_string(), v, bounds(d.name).unwrap_or(d.bounds))?;
        }
        if self.lobes.len() > MAX_LOBES {
            return Err(ParamError::TooManyLobes {
                count: self.lobes.len(),
            });
        }
        for (k, lobe) in self.lobes.iter().enumerate() {
            for (d, &v) in f.lobe_fields().iter().zip(lobe) {
                let name = format!("lobe{}.{}", k + 1, d.name);
                let b = bounds(&name).unwrap_or(d.bounds);
                check(|| name, v, b)?;
            }
        }
        f.check(&self.shared, &self.lobes)
            .map_err(|message| ParamError::Invalid { message })
    }
}

impl From<&Params> for Params {
    fn from(p: &Params) -> Params {
        p.clone()
    }
}

impl Serialize for Params {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let f = &self.family;
        let extra = usize::from(!f.is_lafortune());
        let mut m = s.serialize_map(Some(extra + self.shared.len() + 1))?;
        if !f.is_lafortune() {
            m.serialize_entry("family", f.name())?;
        }
        for (d, v) in f.shared_fields().iter().zip(&self.shared) {
            m.serialize_entry(d.key, v)?;
        }
        let lobes: Vec<LobeOut<'_>> = self
            .lobes
            .iter()
            .map(|l| LobeOut(f.lobe_fields(), l))
            .collect();
        m.serialize_entry("lobes", &lobes)?;
        m.end()
    }
}

struct LobeOut<'a>(&'static [FieldDef], &'a [f64]);

impl Serialize for LobeOut<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.1.len()))?;
        for (d, v) in self.0.iter().zip(self.1) {
            m.serialize_entry(d.key, v)?;
        }
        m.end()
    }
}
