//! The one step before a run: nothing reads the results file before the folder's lock is held,
//! a run reads that file once, and each instance is built once for both the best-known RMSE
//! and the runner (counted with the library's per-thread diagnostics).

// The experiment crate's test helpers (a tiny spec and its parsing), shared rather than copied.
#[path = "../../experiment/tests/common/mod.rs"]
mod common;

use brdf_best_known::prepare::{PrepareError, prepare};
use brdf_experiment::instance::builds_on_this_thread;
use brdf_experiment::run::{RunOptions, SlsExecutor, run_locked};
use brdf_experiment::store::{DirLock, StoreError, results_reads_on_this_thread};

/// Two instances, one with a relative target (so its best-known RMSE must be computed), a
/// short evaluation budget.
fn two_instances() -> String {
    let second = "[[instance]]\nname = \"cross\"\ntargets = [{ relative = 0.05 }]\n\
                  [instance.synthetic]\nparams = \"cross\"\nsamples = 300\nsigma = 0.05\n\n";
    common::TINY
        .replace("trials = 4", "trials = 1")
        .replace("evaluations = 400000", "evaluations = 20000")
        .replace(
            "[[algorithm]]\nlabel",
            &format!("{second}[[algorithm]]\nlabel"),
        )
}

/// Reads and builds counted on this thread while `f` runs.
fn counted<T>(f: impl FnOnce() -> T) -> (T, usize, usize) {
    let (reads, builds) = (results_reads_on_this_thread(), builds_on_this_thread());
    let out = f();
    (
        out,
        results_reads_on_this_thread() - reads,
        builds_on_this_thread() - builds,
    )
}

/// Prepares and runs `spec` into `dir` the way `brdf-sls run` does.
fn prepare_and_run(text: &str, dir: &std::path::Path) -> brdf_experiment::run::RunOutcome {
    let spec = common::spec(text, dir);
    let p = prepare(spec, dir).unwrap();
    let exec = SlsExecutor::from_built(&p.spec, &p.built, brdf_model::Kernel::Auto).unwrap();
    let options = RunOptions {
        threads: 1,
        progress: brdf_experiment::progress::ProgressMode::Quiet,
        ..RunOptions::default()
    };
    run_locked(&p.spec, None, p.folder, &options, &exec).unwrap()
}

#[test]
fn a_run_reads_its_results_once_and_builds_each_instance_once() {
    let dir = tempfile::tempdir().unwrap();
    let text = two_instances();
    // First run: no results file to read; both instances built once, though the relative
    // target needs a best-known RMSE computed from one of them.
    let (first, reads, builds) = counted(|| prepare_and_run(&text, dir.path()));
    assert_eq!((reads, builds), (0, 2));
    assert_eq!(first.new_trials, 6);
    assert_eq!(first.sessions.len(), 1);
    // Resumed with more trials: one read of the file, each instance built once, and the
    // recorded best-known RMSEs used as they are.
    let more = text.replace("trials = 1", "trials = 2");
    let (second, reads, builds) = counted(|| prepare_and_run(&more, dir.path()));
    assert_eq!((reads, builds), (1, 2));
    assert_eq!((second.resumed, second.new_trials), (6, 6));
    // The outcome's sessions are the file's: reading it back gives the same.
    let back = brdf_experiment::store::read_results(dir.path()).unwrap();
    assert_eq!(back.sessions, second.sessions);
    assert_eq!(back.records.len(), 12);
}

#[test]
fn nothing_is_read_or_built_before_the_lock_is_held() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join(brdf_experiment::store::TRIALS_FILE),
        "not read\n",
    )
    .unwrap();
    let held = DirLock::acquire(dir.path()).unwrap();
    let spec = common::spec(&two_instances(), dir.path());
    let (result, reads, builds) = counted(|| prepare(spec, dir.path()));
    match result {
        Err(PrepareError::Store(StoreError::Locked { .. })) => {}
        other => panic!("expected the lock to be refused, got {other:?}"),
    }
    assert_eq!((reads, builds), (0, 0));
    drop(held);
}
