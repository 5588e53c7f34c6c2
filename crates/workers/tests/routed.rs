//! Trials in worker processes give the results of trials in this process (times aside), keep
//! the data hashes checked, and turn a worker that breaks off into a failed configuration.

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

use std::ffi::OsString;

use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunOptions, SlsExecutor, run_experiment};
use brdf_experiment::store::TrialRecord;
use brdf_workers::pool::{PoolError, Routed, RoutedError, WorkerCommand};

fn worker() -> WorkerCommand {
    WorkerCommand {
        program: OsString::from(env!("CARGO_BIN_EXE_brdf-worker")),
        args: Vec::new(),
        env: Vec::new(),
    }
}

fn options() -> RunOptions {
    RunOptions {
        threads: 2,
        progress: ProgressMode::Quiet,
        ..RunOptions::default()
    }
}

fn without_clocks(records: &[TrialRecord]) -> Vec<(String, sls::TrialResult)> {
    let mut v: Vec<_> = records
        .iter()
        .map(|r| (r.key.clone(), r.result.clone().without_clock()))
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

#[test]
fn workers_give_the_results_of_this_process() {
    let dir = tempfile::tempdir().unwrap();
    let text = common::TINY.replace("trials = 4", "trials = 2");
    let spec = common::spec(&text, dir.path());
    let built = brdf_experiment::instance::build_all(&spec).unwrap();
    let kernel = brdf_model::Kernel::Auto;
    let here = SlsExecutor::from_built(&spec, &built, kernel).unwrap();
    let a = run_experiment(&spec, &dir.path().join("here"), &options(), &here).unwrap();
    // Every configuration but the first in workers.
    let routed = Routed::new(
        &spec,
        &built,
        kernel,
        |c| c.label != spec.configurations[0].label,
        worker,
        "tiny.toml",
    )
    .unwrap();
    let b = run_experiment(&spec, &dir.path().join("workers"), &options(), &routed).unwrap();
    assert_eq!(a.records.len(), 6);
    assert_eq!(without_clocks(&a.records), without_clocks(&b.records));
    // Each trial in a worker was timed there.
    assert!(
        b.records
            .iter()
            .all(|r| r.result.ended_at.cpu_seconds > 0.0)
    );
}

#[test]
fn a_spec_the_worker_refuses_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let spec = common::spec(common::TINY, dir.path());
    let built = brdf_experiment::instance::build_all(&spec).unwrap();
    let mut spec_changed = spec.clone();
    // The worker parses the text it is sent: a text with an unknown kind is refused there.
    spec_changed.text = spec.text.replace("kind = \"rpls\"", "kind = \"nope\"");
    let err = Routed::new(
        &spec_changed,
        &built,
        brdf_model::Kernel::Auto,
        |_| true,
        worker,
        "tiny.toml",
    )
    .err()
    .unwrap();
    match err {
        RoutedError::Pool(PoolError::Refused(m)) => {
            assert!(m.starts_with("tiny.toml:") && m.contains("`nope`"), "{m}")
        }
        e => panic!("{e}"),
    }
}

#[test]
fn a_worker_that_cannot_start_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let spec = common::spec(common::TINY, dir.path());
    let built = brdf_experiment::instance::build_all(&spec).unwrap();
    let missing = || WorkerCommand {
        program: OsString::from("/no/such/worker"),
        args: Vec::new(),
        env: Vec::new(),
    };
    let err = Routed::new(
        &spec,
        &built,
        brdf_model::Kernel::Auto,
        |_| true,
        missing,
        "tiny.toml",
    )
    .err()
    .unwrap();
    let text = err.to_string();
    assert!(
        text.contains("/no/such/worker") && text.contains("cannot start it"),
        "{text}"
    );
}
