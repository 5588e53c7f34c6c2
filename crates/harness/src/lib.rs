//! The brdf-sls experiment harness: run-time distribution statistics and plots of results
//! folders, and the command line.
//!
//! The command line ([`cli_main`]: `src/cli/` declares the flags, `src/cmd/` runs the
//! commands; built with the default `cli` feature, the only user of clap) is a thin layer over
//! this library and `brdf_experiment`. `src/main.rs`, the `brdf-sls` binary, only calls it.
//!
//! - [`stats`]: run-time distributions (Kaplan-Meier), quantiles, ERT with bootstrap, pairwise
//!   tests (Mann-Whitney, KS, log-rank) with Holm's correction, tables.
//! - [`figures`]: RTD, sweep, trace, scatter, error-time and COCO-style ECDF charts built from
//!   the statistics (drawn by `brdf_graphics`).
//! - [`report`]: statistics and plots for a finished (or partial) results directory.
//! - [`export`]: results in IOHprofiler's format (IOHanalyzer, iohinspector).
//! - [`folder`]: a results folder read whole (records, stored spec, notes) for pages and
//!   comparisons.
//! - [`html`]: self-contained HTML pages: the report of results folders, a comparison, and
//!   the stress and bench pages.
//! - [`stress_charts`]: the charts of a stress report (files and page alike).
//! - [`compare`]: before and after: matched results of two folders judged faster, slower, not
//!   significantly different or not comparable (and why).

pub mod compare;
pub mod export;
pub mod figures;
pub mod folder;
pub mod html;
pub mod report;
pub mod stats;
pub mod stress_charts;

#[cfg(feature = "cli")]
mod cli;
#[cfg(feature = "cli")]
mod cmd;

/// The whole `brdf-sls` command line (every command, flag, message and exit status): parses
/// the process's arguments, runs the command and returns its exit status (0 success or a
/// closed output pipe, 2 bad input, 1 a failure while running).
///
/// A crate with algorithms of its own registers them, then hands over, and gets every
/// command (`run`, `check`, `stats`, `plot`, `report`, `compare`, `merge`, `slurm`, `tune`,
/// ...) with its kinds known, in a program of its own:
///
/// ```no_run
/// fn main() -> std::process::ExitCode {
///     // sls::registry::register::<MyAlgorithm>().expect("a kind of its own");
///     harness::cli_main()
/// }
/// ```
#[cfg(feature = "cli")]
pub fn cli_main() -> std::process::ExitCode {
    cmd::main()
}
