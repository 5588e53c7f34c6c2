//! The Lafortune BRDF model as the SLS paper fits it, with parameter layouts, a fast
//! evaluator (residuals, analytic Jacobian, RMSE), data sets, readers and subsampling.
//!
//! # Conventions
//! - `f(u, v) = kd + sum_k max(0, Cx u'x v'x + Cy u'y v'y + Cz uz vz)^n_k`.
//! - `u` (incident) and `v` (exitant) are unit vectors in the surface frame, **both pointing
//!   away from the surface**, `z` = the surface normal. A mirror-like (forward) lobe then has
//!   `Cx = Cy < 0 < Cz`, a retro-reflective one `Cx = Cy > 0`; Phong is `-Cx = -Cy = Cz`.
//! - `u'`, `v'` are `u`, `v` rotated about the normal by the lobe's pan angle (degrees):
//!   `u'x = cos(p) ux + sin(p) uy`, `u'y = -sin(p) ux + cos(p) uy`.
//! - `kd` is the constant BRDF term (the paper's "Diffuse"); the diffuse albedo is
//!   `rho_d = pi * kd`. Each lobe's scale `rho_s` is folded into its C's.
//! - A clamped dot product `d <= 0` contributes 0 for every `n` (also `n = 0`).
//! - Table 1 bounds: C in [-1.5, 1.5], n in [0, 10000], pan in [-90, 90] degrees, kd in [0, 1].
//! - Jacobians are column-major: `jac[j * m + i] = d r_i / d x_j`, `r_i = f_i - y_i`.
//!
//! # Modules
//! - [`params`]: physical parameters ([`BrdfParams`], [`Lobe`]) and [`named_params`].
//! - [`layout`]: [`Layout`] (free/fixed parameters, bounds, exponent coordinate).
//! - [`eval`]: [`Evaluator`] (residuals, Jacobian, sum of squares, RMSE), with SIMD copies of
//!   its loops chosen by [`Kernel`] (the kernel vocabulary of `brdf-simd`, re-exported); pan
//!   Jacobian columns are per degree.
//! - [`data`]: [`DataSet`], [`synthetic`], [`Filters`], [`FilterReport`], [`Subsampler`].
//! - [`io`]: Cornell, CSV, MERL and ALTA readers behind one [`Format`] (documented there).

#![warn(missing_docs)]

#[cfg(target_arch = "x86_64")]
mod avx512;
pub mod data;
pub mod eval;
mod fastmath;
pub mod io;
pub mod layout;
pub mod params;

pub use data::{
    DataSet, FilterReport, Filters, MAX_SAMPLES, MAX_SIGMA, Subsampler, synthetic, try_synthetic,
    uniform_hemisphere,
};
pub use eval::{Evaluator, Kernel, KernelError, SUM_BLOCK, SumBelow};
pub use io::Format;
pub use io::{
    Channel, DataError, MerlBrdf, parse_cornell, parse_csv, read_cornell, read_csv, read_merl,
};
pub use layout::{ExponentCoord, Layout, LayoutBuilder, LobeKind, ModelError, is_parameter_name};
pub use params::{BrdfParams, Lobe, NAMED_PARAMS, ParamError, named_params};

/// Default wavelength (nm) for Cornell files, as in the paper.
pub const DEFAULT_WAVELENGTH_NM: f64 = 550.0;
