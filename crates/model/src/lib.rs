//! Reflectance models for fitting: the model seam ([`Family`]) with the Lafortune model as the
//! SLS paper fits it as its first family, parameter layouts, fast evaluators (residuals,
//! analytic Jacobian, RMSE), data sets, readers and subsampling.
//!
//! # Conventions (every family)
//! - `u` (incident) and `v` (exitant) are unit vectors in the surface frame, **both pointing
//!   away from the surface**, `z` = the surface normal; values are BRDF values.
//! - Jacobians are column-major: `jac[j * m + i] = d r_i / d x_j`, `r_i = f_i - y_i`, in the
//!   optimiser's coordinates.
//! - The Lafortune family's own conventions (lobes, pan, Table 1 bounds): [`lafortune`].
//!
//! # Modules
//! - [`family`](mod@family): the [`Family`] trait (parameters, coordinates, preparation, evaluators) and
//!   [`FamilyRef`]; the registry: [`family()`], [`family_names`], [`register_family`].
//! - [`lafortune`]: the Lafortune family, its typed parameters ([`BrdfParams`], [`Lobe`]) and
//!   [`named_params`].
//! - [`lobes`]: the framework of the other families (a constant plus lobes of one formula,
//!   [`lobes::LobeShape`]), and [`models`]: those families (GGX, ...).
//! - [`fastmath`]: the branch-free `exp` and `ln` the vectorised kernels use.
//! - [`params`]: physical parameters of any family ([`Params`]) and [`ParamError`].
//! - [`layout`]: [`Layout`] (free/fixed parameters, bounds, coordinates).
//! - [`eval`]: [`Evaluator`] (residuals, Jacobian, sum of squares, RMSE) over a family's
//!   [`Evaluate`], with the kernel vocabulary of `brdf-simd` ([`Kernel`], re-exported).
//! - [`synthetic()`], [`try_synthetic`]: synthetic instances of any family.
//! - [`samples`]: [`Samples`], a family's per-sample columns of a data set.
//! - [`data`]: [`DataSet`], [`synthetic`], [`Filters`], [`FilterReport`], [`Subsampler`].

#![warn(missing_docs)]

pub mod data;
pub mod eval;
mod evaluate;
pub mod family;
pub mod fastmath;
pub mod lafortune;
pub mod layout;
pub mod lobes;
pub mod models;
pub mod params;
mod registry;
pub mod samples;
mod synthetic;

pub use data::{
    DataSet, FilterReport, Filters, MAX_SAMPLES, MAX_SIGMA, Subsampler, uniform_hemisphere,
};
pub use eval::{Evaluator, Kernel, KernelError, SUM_BLOCK, SumBelow};
pub use evaluate::{Evaluate, all_finite, grown};
pub use family::{
    Coord, DEFAULT_FAMILY, Family, FamilyRef, FieldDef, LayoutParam, LobeKind, ParamDef, Role,
};
pub use lafortune::{BrdfParams, Lobe, NAMED_PARAMS, named_params};
pub use layout::{
    ExponentCoord, Layout, LayoutBuilder, MAX_EXPONENT, ModelError, is_parameter_name,
};
pub use params::{MAX_LOBES, ParamError, Params, Reflectance};
pub use registry::{FamilyError, family, family_names, register_family};
pub use samples::Samples;
pub use synthetic::{synthetic, try_synthetic};
