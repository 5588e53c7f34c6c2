//! `brdf-sls`: run BRDF-fitting experiments (TOML specs), re-plot and summarise stored results,
//! fit a data set once, and generate, evaluate or describe data sets.
//!
//! The command line lives in the library (`harness::cli_main`), so a crate that registers its
//! own algorithm kinds gets the same program by calling it.

use std::process::ExitCode;

fn main() -> ExitCode {
    harness::cli_main()
}
