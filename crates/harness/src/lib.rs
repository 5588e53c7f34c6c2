//! The `brdf-sls` command line: every command, flag, message and exit status, over the
//! libraries that do the work (`brdf_experiment`, `brdf_analysis`, `brdf_tune`, `brdf_bench`).
//!
//! [`cli_main`] is the whole program; `src/cli/` declares the flags (clap derive) and the
//! shared value parsers, `src/cmd/` runs the commands (one file each). `src/main.rs`, the
//! `brdf-sls` binary, only calls [`cli_main`], so a crate that registers algorithms of its own
//! gets the same program by calling it too.
#![warn(missing_docs)]

mod cli;
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
pub fn cli_main() -> std::process::ExitCode {
    cmd::main()
}

/// [`cli_main`] for a program of its own, which names itself: `name` and `version` (its
/// crate's, `env!("CARGO_PKG_NAME")` and `env!("CARGO_PKG_VERSION")`) are recorded with the
/// results it writes, beside a hash of each custom kind's settings schema, so that a run
/// resumed after a change of the program says so.
///
/// ```no_run
/// fn main() -> std::process::ExitCode {
///     // sls::registry::register::<MyAlgorithm>().expect("a kind of its own");
///     harness::cli_main_as(env!("CARGO_PKG_NAME"), env!("CARGO_PKG_VERSION"))
/// }
/// ```
pub fn cli_main_as(name: &str, version: &str) -> std::process::ExitCode {
    brdf_experiment::run::set_program(name, version);
    cmd::main()
}
