//! Standard least-squares test problems as [`crate::Problem`]s, for tests, benchmarks and
//! stress-test crates.
//!
//! - [`mgh`]: the Moré, Garbow and Hillstrom (1981) collection, with analytic Jacobians,
//!   standard starts and known minima.
//! - [`nist`]: the NIST StRD nonlinear regression problems (data embedded).
//!
//! Constructing a problem allocates; evaluating it does not.

pub mod mgh;
pub mod nist;
