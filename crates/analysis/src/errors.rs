//! Which errors are the user's input and which are failures while running: `brdf-sls` exits 2
//! for the first and 1 for the second, and the Python package raises `InputError` or
//! `RunError`. Both ask [`is_input_cause`], so a new kind of refusal (an edited seed, a changed
//! target, a negative time in a results file) is classified once and the two cannot drift
//! apart, as they did when each kept its own list. [`message`] is the text both print.

use brdf_experiment::run::RunError;
use brdf_experiment::store::StoreError;

use crate::folder::FolderError;
use crate::pipeline::ConfigurationsFailed;

/// True when `e` or one of its causes is bad input (see [`is_input_cause`]).
pub fn is_input_error(e: &anyhow::Error) -> bool {
    e.chain().any(is_input_cause)
}

/// True when this one error (not its causes) is bad input: a spec, flag value, data file,
/// model or settings the user wrote, or a results folder that cannot be used as given (results
/// of another spec, shard or data, a corrupt or edited line, an edited seed or target, a
/// negative time). Errors of the crates above this one (the harness's own, `brdf-fit`'s,
/// `brdf-merge`'s) are classified by their callers, which add them to this.
pub fn is_input_cause(c: &(dyn std::error::Error + 'static)) -> bool {
    brdf_experiment::input_file::is_refused(c)
        || c.is::<brdf_experiment::seed_check::SeedMismatch>()
        || c.is::<brdf_experiment::spec::SpecError>()
        || c.is::<brdf_experiment::instance::InstanceError>()
        || c.is::<ConfigurationsFailed>()
        || c.is::<brdf_io::DataError>()
        || c.is::<brdf_model::ModelError>()
        || c.is::<brdf_model::ParamError>()
        || c.is::<brdf_model::KernelError>()
        || c.is::<sls::ConfigError>()
        || c.downcast_ref::<FolderError>()
            .is_some_and(FolderError::is_input_error)
        || c.downcast_ref::<StoreError>().is_some_and(is_input_store)
        || c.downcast_ref::<RunError>().is_some_and(|r| match r {
            RunError::ShardMismatch { .. } | RunError::Seed(_) => true,
            // `Store` is transparent: the store's error is not in the chain itself.
            RunError::Store(s) => is_input_store(s),
            _ => false,
        })
}

/// The store's refusals of a folder as given (rather than failures to read or write it).
fn is_input_store(e: &StoreError) -> bool {
    matches!(
        e,
        StoreError::FingerprintMismatch { .. }
            | StoreError::DataChanged { .. }
            | StoreError::BothPresent { .. }
            | StoreError::Invalid { .. }
            | StoreError::Corrupt { .. }
    )
}

/// The error and its causes joined by ": ", each cause left out when the message so far
/// already holds it: what `brdf-sls` prints after `error: ` and the Python package raises, so
/// that the two messages are equal. Many errors here say `"{path}: {source}"` and also return
/// the source as their cause, so the plain chain printed the operating system's message twice.
pub fn message(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.contains(&text) {
            continue;
        }
        // A cause that begins with what its parent ended with ("reading X" then "X: not
        // found") names the path once: the repeated head is dropped.
        let text = text
            .match_indices(": ")
            .map(|(i, _)| i)
            .find(|&i| i > 0 && out.ends_with(&text[..i]))
            .map_or(text.as_str(), |i| &text[i + 2..]);
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(text);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn store_invalid() -> StoreError {
        StoreError::Invalid {
            path: PathBuf::from("r/trials.jsonl"),
            line: 3,
            key: "k".into(),
            message: "`result.ended_at.cpu_seconds` is -1, expected at least 0".into(),
        }
    }

    /// The refusals of an edited results file are input however they are wrapped: directly
    /// (`stats`), through the run's error (`run` resuming) and under context.
    #[test]
    fn edited_results_are_input_however_wrapped() {
        use brdf_experiment::seed_check::{Mismatched, SeedMismatch};
        let seed = || SeedMismatch {
            path: PathBuf::from("r/trials.jsonl"),
            line: Some(3),
            key: "k".into(),
            what: Mismatched::Seed,
            stored: "1".into(),
            planned: "2".into(),
        };
        let cases = [
            anyhow::Error::new(seed()),
            anyhow::Error::new(RunError::Seed(seed())).context("running experiment x"),
            anyhow::Error::new(RunError::Store(store_invalid())).context("running experiment x"),
            anyhow::Error::new(store_invalid()).context("reading results in r"),
            anyhow::Error::new(FolderError::Seed(seed())),
        ];
        for e in &cases {
            assert!(is_input_error(e), "{e:#}");
        }
    }

    /// Failures while running stay failures: an I/O error, an interrupt, a lock held.
    #[test]
    fn failures_while_running_are_not_input() {
        let io = || StoreError::Io {
            path: PathBuf::from("r/trials.jsonl"),
            source: std::io::Error::other("disk on fire"),
        };
        let cases = [
            anyhow::Error::new(io()),
            anyhow::Error::new(RunError::Store(io())),
            anyhow::Error::new(RunError::Interrupted),
            anyhow::Error::new(StoreError::Locked {
                dir: PathBuf::from("r"),
                pid: None,
            }),
            anyhow::anyhow!("something else"),
        ];
        for e in &cases {
            assert!(!is_input_error(e), "{e:#}");
        }
    }
}
