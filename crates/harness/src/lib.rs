//! The brdf-sls experiment harness: TOML experiment specs, parallel seeded trials, a
//! crash-safe results store, run-time distribution statistics and plots.
//!
//! The command line ([`cli_main`]: `src/cli/` declares the flags, `src/cmd/` runs the
//! commands; built with the default `cli` feature, the only user of clap) is a thin layer over
//! this library. `src/main.rs`, the `brdf-sls` binary, only calls it.
//!
//! - [`spec`]: experiment specs (the format: `docs/experiment-format.md`) read in stages: the
//!   TOML as parsed, validation with stated [`spec::limits`], sweep expansion, the resolved
//!   [`spec::Spec`] with its trial plan and fingerprint, the printed description.
//! - [`seed`]: stable per-trial seeds, spec fingerprints and data hashes.
//! - [`store`]: the results file `trials.jsonl`, with an advisory lock per folder, appends
//!   per line, resume, torn-line recovery, packed `.gz` read transparently, refusal of a
//!   different spec or different data; and atomic writes of derived files.
//! - [`prepare`]: the one step before a run: lock, read the results once, build each instance
//!   once, resolve the best-known RMSEs.
//! - [`run`]: the parallel runner (rayon), data sets built once and shared.
//! - [`stats`]: run-time distributions (Kaplan-Meier), quantiles, ERT with bootstrap, pairwise
//!   tests (Mann-Whitney, KS, log-rank) with Holm's correction, tables.
//! - [`figures`]: RTD, sweep, trace, scatter, error-time and COCO-style ECDF charts built from
//!   the statistics (drawn by `brdf_graphics`).
//! - [`report`]: statistics and plots for a finished (or partial) results directory.
//! - [`progress`]: progress bars or plain progress lines.
//! - [`machine`]: CPU model and thread count recorded with results.
//! - [`tune`]: automatic tuning with irace (scenario files, target runner, elites).
//! - [`instance`]: building an experiment's data sets and layouts.
//! - [`export`]: results in IOHprofiler's format (IOHanalyzer, iohinspector).
//! - [`best_known`]: the best-known RMSE of an instance (relative targets, closeness warnings).
//! - Leaf modules (importing nothing of the crate) holding the plain types the others share:
//!   [`best_known_record`], [`trial_key`], [`duration`], [`choice`].
//! - [`shard`]: splitting the trial plan into `K/N` shards (one process or job array task each).
//! - [`merge`]: merging shard folders into one results folder (duplicates, missing trials).
//! - [`params`]: the one reader of parameter sets (a name, JSON, `@FILE` or a TOML table).
//! - [`fit`]: one fit of one data set (what `brdf-sls fit` and the Python package share).
//! - [`folder`]: a results folder read whole (records, stored spec, notes) for pages and
//!   comparisons.
//! - [`html`]: self-contained HTML pages: the report of results folders, a comparison, and
//!   the stress and bench pages.
//! - [`stress_charts`]: the charts of a stress report (files and page alike).
//! - [`compare`]: before and after: matched results of two folders judged faster, slower, not
//!   significantly different or not comparable (and why).

/// Where `run` writes when no `--out` is given: `runs/<spec file stem>/`. The repository's
/// committed reference results live apart, in `results/`, so a user's first run never collides
/// with them.
pub const DEFAULT_RUNS_DIR: &str = "runs";

/// The program version recorded with results and printed by `--version`: the crate version and
/// the git commit of the build, e.g. `0.2.0 (git 80f45a0c1d2e)`; `-modified` after the commit
/// means the code differed from it, `git unknown` that the build had no git checkout.
pub const PROGRAM_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (git ",
    env!("BRDF_SLS_GIT"),
    ")"
);

pub mod best_known;
pub mod best_known_record;
pub mod choice;
pub mod compare;
pub mod duration;
pub mod export;
pub mod figures;
pub mod fit;
pub mod folder;
pub mod html;
pub mod input_file;
pub mod instance;
pub mod machine;
pub mod merge;
pub mod params;
pub mod prepare;
pub mod progress;
pub mod python_kind;
pub mod report;
pub mod run;
pub mod seed;
pub mod seed_check;
pub mod shard;
pub mod signals;
pub mod spec;
pub mod stats;
pub mod store;
pub mod stress_charts;
pub mod threads;
pub mod trial_key;
pub mod tune;

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

#[cfg(test)]
mod tests {
    #[test]
    fn program_version_names_the_crate_version_and_the_commit() {
        let v = super::PROGRAM_VERSION;
        let rest = v
            .strip_prefix(concat!(env!("CARGO_PKG_VERSION"), " (git "))
            .and_then(|r| r.strip_suffix(')'))
            .unwrap_or_else(|| panic!("unexpected form: {v}"));
        let id = rest.strip_suffix("-modified").unwrap_or(rest);
        let commit = id.len() == 12 && id.chars().all(|c| c.is_ascii_hexdigit());
        assert!(commit || id == "unknown", "not a commit: {v}");
    }
}
