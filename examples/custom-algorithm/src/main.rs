//! `custom-algorithm`: the whole `brdf-sls` command line (`run`, `check`, `stats`, `plot`,
//! `report`, `compare`, `merge`, `slurm`, ...) with the `coordinate-search` kind registered, so
//! experiments that use it run, resume, shard, merge and re-plot like any other.
//!
//! `custom-algorithm run SPEC [--out DIR] [--threads N] [--shard K/N]`; `--help` lists the rest.

use std::process::ExitCode;

fn main() -> ExitCode {
    if let Err(e) = custom_algorithm::register() {
        eprintln!("error: {e}");
        return ExitCode::from(1);
    }
    // Named, so results record this program and its version beside the harness's.
    harness::cli_main_as(env!("CARGO_PKG_NAME"), env!("CARGO_PKG_VERSION"))
}
