//! The model seam: a reflectance model family ([`Family`]) describes its parameters, prepares
//! per-sample data from a [`DataSet`] and builds evaluators (residuals and Jacobian) for a
//! [`crate::Layout`]; everything above the model crate (the objective, the searches, best-known, fit,
//! diagnose, stress, polar, render, the Python package) works through it.
//!
//! # Parameters, fields and coordinates
//! A family's *fields* are its physical quantities: shared ones (a diffuse term) and, per
//! lobe, the lobe's ([`FieldDef`], with the Table-style bounds a value must lie in). A layout
//! exposes *parameters* to the optimiser ([`ParamDef`]): for an anisotropic lobe usually one
//! per field; for an isotropic lobe some parameters set several fields at once (Lafortune's
//! `cxy` sets `cx` and `cy`) and the fields no parameter sets keep their default (the pan
//! angle, 0). Each parameter has a [`Coord`], the coordinate the optimiser sees (Lafortune's
//! exponent as `ln(1 + n)`), and a [`Role`] (which parameters a start distribution or a
//! coordinate switch applies to).
//!
//! # Registry
//! Families are found by name ([`crate::family()`], [`crate::family_names`]); the built-in ones
//! are always there and a program adds its own with [`crate::register_family`] before reading
//! specs that name them (as search algorithms are registered in the `sls` crate).

mod defs;

pub use defs::{Coord, FieldDef, LayoutParam, LobeKind, ParamDef, Role};

use crate::data::DataSet;
use crate::evaluate::Evaluate;
use crate::samples::Samples;
use brdf_simd::{Kernel, KernelError};
use std::sync::Arc;

/// The name of the default family (left out of canonical forms and JSON).
pub const DEFAULT_FAMILY: &str = "lafortune";

/// A reflectance model family: its parameters, per-sample preparation, evaluators and a scalar
/// reference value. Implementations are stateless descriptions, shared between threads.
///
/// Conventions every family follows (docs/model.md): directions `u` (incident) and `v`
/// (exitant) are unit vectors in the surface frame, both pointing away from the surface, `z`
/// the normal; values are BRDF values (per steradian); Jacobian columns are per unit of the
/// optimiser's coordinate (column-major, `jac[j * m + i] = d r_i / d x_j`); an evaluation that
/// overflows returns `false` (never NaN values).
pub trait Family: Send + Sync + 'static {
    /// The name specs and commands use (`"lafortune"`, `"ggx"`), lowercase.
    fn name(&self) -> &'static str;

    /// One line for listings: the model and its source.
    fn summary(&self) -> &'static str;

    /// The shared fields, in canonical order (usually just the diffuse term).
    fn shared_fields(&self) -> &'static [FieldDef];

    /// The fields of one lobe, in canonical order.
    fn lobe_fields(&self) -> &'static [FieldDef];

    /// The shared parameters (each sets shared fields).
    fn shared_params(&self) -> &'static [ParamDef];

    /// The parameters of a lobe of `kind`, in canonical order; `None` when the family has no
    /// such lobe (Blinn-Phong has no anisotropic lobe).
    fn lobe_params(&self, kind: LobeKind) -> Option<&'static [ParamDef]>;

    /// The per-sample columns this family's evaluators read, computed once per data set.
    fn prepare(&self, data: &DataSet) -> Samples;

    /// The model's value at directions `u`, `v` for physical values `shared` (the shared
    /// fields) and `lobes` (each lobe's fields), of this family: the plain reference the fast
    /// kernels are tested against ([`crate::Params::value`] calls it).
    fn value(&self, shared: &[f64], lobes: &[Vec<f64>], u: [f64; 3], v: [f64; 3]) -> f64;

    /// An evaluator of a layout of this family, given as its lobe kinds and parameters
    /// ([`crate::Layout::kinds`], [`crate::Layout::params`]), with the concrete kernel
    /// `kernel` (never [`Kernel::Auto`]; callers resolve it first).
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the family has no such kernel on this CPU.
    fn evaluator(
        &self,
        kinds: &[LobeKind],
        params: &[LayoutParam],
        kernel: Kernel,
    ) -> Result<Box<dyn Evaluate>, KernelError>;

    /// Extra checks of physical values beyond each field's bounds (for example a relation
    /// between fields), as a message naming the parameter. The default accepts everything.
    fn check(&self, shared: &[f64], lobes: &[Vec<f64>]) -> Result<(), String> {
        let _ = (shared, lobes);
        Ok(())
    }
}

/// A shared handle on a registered family; equal when the names are.
#[derive(Clone)]
pub struct FamilyRef(pub(crate) Arc<dyn Family>);

impl FamilyRef {
    /// Wraps a family (not registering it).
    pub fn new(f: Arc<dyn Family>) -> Self {
        FamilyRef(f)
    }

    /// The family's name.
    pub fn name(&self) -> &'static str {
        self.0.name()
    }

    /// Whether this is the Lafortune family (the default, left out of canonical forms).
    pub fn is_lafortune(&self) -> bool {
        self.name() == DEFAULT_FAMILY
    }

    /// The names of a shared field then lobe fields, for messages: the full list of names
    /// a parameter set of `lobes` lobes of kinds `kinds` has.
    pub fn field_names(&self, lobes: usize) -> Vec<String> {
        let mut out: Vec<String> = self
            .shared_fields()
            .iter()
            .map(|f| f.name.to_string())
            .collect();
        for k in 1..=lobes {
            for f in self.lobe_fields() {
                out.push(format!("lobe{k}.{}", f.name));
            }
        }
        out
    }

    /// The lobe kinds the family supports.
    pub fn kinds(&self) -> Vec<LobeKind> {
        [LobeKind::Anisotropic, LobeKind::Isotropic]
            .into_iter()
            .filter(|&k| self.lobe_params(k).is_some())
            .collect()
    }
}

impl std::ops::Deref for FamilyRef {
    type Target = dyn Family;
    fn deref(&self) -> &Self::Target {
        &*self.0
    }
}

impl std::fmt::Debug for FamilyRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Family({})", self.name())
    }
}

impl PartialEq for FamilyRef {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for FamilyRef {}
