//! The experiments of brdf-sls: TOML experiment specs, seeded trials run in parallel, a
//! crash-safe results store.
//!
//! - [`spec`]: experiment specs (the format: `docs/experiment-format.md`) read in stages: the
//!   TOML as parsed, validation with stated [`spec::limits`], sweep expansion, the resolved
//!   [`spec::Spec`] with its trial plan and fingerprint, the printed description, and the
//!   optional `[tune]` table ([`spec::tune`]).
//! - [`seed`]: stable per-trial seeds, spec fingerprints and data hashes.
//! - [`seed_check`]: on resume, every stored trial carries the seed the plan derives for it.
//! - [`store`]: the results file `trials.jsonl`, with an advisory lock per folder, appends
//!   per line, resume, torn-line recovery, packed `.gz` read transparently, refusal of a
//!   different spec or different data; and atomic writes of derived files.
//! - [`run`]: the parallel runner (rayon), data sets built once and shared.
//! - [`progress`]: progress bars or plain progress lines.
//! - [`machine`]: CPU model and thread count recorded with results.
//! - [`threads`]: how many worker threads a run may ask for, and how many can help.
//! - [`signals`]: signal dispositions the program sets at start.
//! - [`instance`]: building an experiment's data sets and layouts.
//! - [`input_file`]: reading a spec or results file only when it is a regular file of bounded
//!   size.
//! - The best-known RMSE (relative targets, closeness warnings), the lobes' sample coverage,
//!   the polish and the one step before a run (`prepare`) are the `brdf-best-known` crate's.
//! - Leaf modules (importing nothing of the crate) holding the plain types the others share:
//!   [`best_known_record`], [`trial_key`], [`duration`], [`choice`], [`terminal`] (control
//!   characters of input escaped for the terminal).
//! - [`shard`]: splitting the trial plan into `K/N` shards (one process or job array task each).
//! - [`params`]: the one reader of parameter sets (a name, JSON, `@FILE` or a TOML table).
//! - [`python_kind`]: `kind = "python"`, algorithms written in Python, as specs and results
//!   name them.
#![warn(missing_docs)]

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

pub mod best_known_record;
pub mod choice;
pub mod duration;

pub mod input_file;
pub mod instance;
pub mod machine;
pub mod params;
pub mod progress;
pub mod python_kind;
pub mod run;
pub mod seed;
pub mod seed_check;
pub mod shard;
pub mod signals;
pub mod spec;
pub mod store;
pub mod terminal;
pub mod threads;
pub mod trial_key;

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
