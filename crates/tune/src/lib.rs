//! Automatic tuning of brdf-sls's algorithms with irace (`brdf-sls tune`). The spec's `[tune]`
//! table (which configuration, which parameters, the cost of a trial) is
//! [`brdf_experiment::spec::tune`]; this crate speaks irace's language around it.
//!
//! - [`irace`]: irace's syntax: the parameter file, the instance list, the scenario, the
//!   target-runner script, finding the `irace` command, and reading irace's output (progress
//!   lines, the elite configurations and their parameter switches).
//! - [`validation`]: the validation experiment written after tuning, which compares irace's
//!   elites with the defaults on held-out instances.
#![warn(missing_docs)]

pub mod irace;
pub mod validation;
