//! Bounded trust-region Levenberg-Marquardt solver in the role of PORT's N2FB.
//!
//! Minimises `f(x) = 0.5 * sum_i r_i(x)^2` subject to `lower <= x <= upper` and reports *why* it
//! stopped with N2FB's return codes ([`Outcome`]), because the search algorithms built on it
//! (AED, AERS) branch on them.
//!
//! ```
//! use bounded_lm::{Options, Problem, Solver};
//! struct Line; // fit y = a + b t to three points
//! impl Problem for Line {
//!     fn residual_count(&self) -> usize { 3 }
//!     fn parameter_count(&self) -> usize { 2 }
//!     fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
//!         for (i, ri) in r.iter_mut().enumerate() {
//!             *ri = x[0] + x[1] * i as f64 - [1.0, 3.0, 5.0][i];
//!         }
//!         true
//!     }
//!     fn jacobian(&mut self, _x: &[f64], jac: &mut [f64]) -> bool {
//!         jac.copy_from_slice(&[1.0, 1.0, 1.0, 0.0, 1.0, 2.0]); // column-major
//!         true
//!     }
//! }
//! let mut x = [0.0, 0.0];
//! let (lower, upper) = ([f64::NEG_INFINITY; 2], [f64::INFINITY, 1.5]);
//! let options = Options::default();
//! let report = Solver::new().solve(&mut Line, &mut x, &lower, &upper, &options).unwrap();
//! assert!(report.outcome.is_success());
//! assert_eq!(x[1], 1.5); // the optimum lies on the upper bound of b
//! ```
//!
//! Options come as presets: [`Options::default`] (the reference), [`Options::n2fb`] (PORT's
//! N2FB configuration), [`Options::gauss_newton`], and [`Options::search`] (what the searches'
//! descents use; [`Options::for_search`] turns any preset into its search variant).
//!
//! The algorithm, N2FB's return codes, every departure from N2FB with its reason and
//! measurement, and the measured tables are in the repository's `docs/solver.md`.
//!
//! Modules: [`qr`] (Householder QR kernels), [`problems`] (the Moré-Garbow-Hillstrom and NIST
//! StRD problems as [`Problem`]s, for tests, benchmarks and stress tests); the solver itself,
//! its options, its reports and the [`Problem`] trait are re-exported at the crate root.
//! [`Solver`] owns all buffers, so repeated solves of the same or a smaller size allocate
//! nothing (`tests/alloc.rs` proves it with a counting global allocator).

#![warn(missing_docs)]
// `!(a > b)` is deliberate throughout: it is true for NaN, which must count as failure.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Index loops mirror the textbook linear-algebra formulas and touch several arrays at once.
#![allow(clippy::needless_range_loop)]

mod linalg;
mod options;
mod problem;
pub mod problems;
pub mod qr;
mod report;
mod solver;

pub use brdf_simd::{Kernel, KernelError};
pub use linalg::dispatch::{kernel, set_kernel};
pub use options::{
    InvalidOption, Limits, Options, Radius, RadiusUpdate, Safeguards, Scaling, SecantScaling,
    StepModel, Tolerances,
};
pub use problem::{ForwardDifference, Problem, ResidualsOnly};
pub use report::{Outcome, Report, SolveError};
pub use solver::Solver;
