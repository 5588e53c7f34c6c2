//! Running experiments end to end: seeding invariance across thread counts, resume after an
//! interruption, refusal of a different spec, failing trials and configurations. The statistics
//! and plots written after a run are tested in crates/analysis/tests/report_files.rs.

mod common;

use std::io::Write;

use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunError, RunOptions, SlsExecutor, run_experiment};
use brdf_experiment::store::{StoreError, TRIALS_FILE, read_results};

use common::{TINY, deterministic_view, spec};

fn options(threads: usize) -> RunOptions {
    RunOptions {
        threads,
        fresh: false,
        progress: ProgressMode::Quiet,
        limit: None,
    }
}

#[test]
fn results_identical_for_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(TINY, dir.path());
    let (exec, built) = SlsExecutor::new(&s, brdf_model::Kernel::Auto).unwrap();
    assert_eq!(built[0].data.len(), 400);
    let one = run_experiment(&s, &dir.path().join("one"), &options(1), &exec).unwrap();
    let two = run_experiment(&s, &dir.path().join("two"), &options(2), &exec).unwrap();
    assert_eq!(one.records.len(), 12);
    assert_eq!(one.new_trials, 12);
    let a: Vec<String> = one.records.iter().map(deterministic_view).collect();
    let b: Vec<String> = two.records.iter().map(deterministic_view).collect();
    assert_eq!(a, b);
    // Seeds differ between trials and configurations.
    let mut seeds: Vec<u64> = one.records.iter().map(|r| r.seed).collect();
    seeds.sort();
    seeds.dedup();
    assert_eq!(seeds.len(), 12);
    // The stored file reads back to the same records (plan order is restored on read).
    let stored = read_results(&dir.path().join("two")).unwrap();
    let mut c: Vec<String> = stored.records.iter().map(deterministic_view).collect();
    let mut a_sorted = a.clone();
    c.sort();
    a_sorted.sort();
    assert_eq!(c, a_sorted);
    assert_eq!(stored.header.machine.threads, 2);
}

#[test]
fn resume_after_interruption_matches_uninterrupted_run() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(TINY, dir.path());
    let (exec, _) = SlsExecutor::new(&s, brdf_model::Kernel::Auto).unwrap();
    let full = run_experiment(&s, &dir.path().join("full"), &options(2), &exec).unwrap();

    // Interrupted run: 5 trials, then a kill in the middle of writing the 6th line.
    let out = dir.path().join("interrupted");
    let mut opts = options(2);
    opts.limit = Some(5);
    let part = run_experiment(&s, &out, &opts, &exec).unwrap();
    assert_eq!(part.new_trials, 5);
    assert_eq!(part.missing, 7);
    let path = out.join(TRIALS_FILE);
    let text = std::fs::read_to_string(&path).unwrap();
    let last = text.lines().last().unwrap().to_string();
    let mut f = std::fs::OpenOptions::new()
        .append(true)
        .open(&path)
        .unwrap();
    f.write_all(&last.as_bytes()[..last.len() / 2]).unwrap();
    drop(f);

    let resumed = run_experiment(&s, &out, &options(1), &exec).unwrap();
    assert_eq!(resumed.resumed, 5);
    assert_eq!(resumed.new_trials, 7);
    assert!(
        resumed.notes.iter().any(|n| n.contains("torn")),
        "{:?}",
        resumed.notes
    );
    let a: Vec<String> = full.records.iter().map(deterministic_view).collect();
    let b: Vec<String> = resumed.records.iter().map(deterministic_view).collect();
    assert_eq!(a, b);
    // The file itself is clean again: 12 trials, no torn tail, two sessions (interrupted + resumed).
    let c = read_results(&out).unwrap();
    assert_eq!(c.records.len(), 12);
    assert!(c.torn.is_none());
    assert_eq!(c.sessions.len(), 2);
    // A run with nothing left to do adds nothing.
    let again = run_experiment(&s, &out, &options(2), &exec).unwrap();
    assert_eq!(again.new_trials, 0);
    assert_eq!(again.records.len(), 12);
}

#[test]
fn different_spec_is_refused_and_fresh_moves_it_aside() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(TINY, dir.path());
    let (exec, _) = SlsExecutor::new(&s, brdf_model::Kernel::Auto).unwrap();
    let out = dir.path().join("r");
    let mut opts = options(2);
    opts.limit = Some(2);
    run_experiment(&s, &out, &opts, &exec).unwrap();

    let other = spec(&TINY.replace("seed = 11", "seed = 12"), dir.path());
    let err = run_experiment(&other, &out, &opts, &exec).unwrap_err();
    assert!(
        matches!(err, RunError::Store(StoreError::FingerprintMismatch { .. })),
        "{err}"
    );
    let msg = err.to_string();
    assert!(msg.contains("--out") && msg.contains("--fresh"), "{msg}");

    // More trials (a spec change outside the fingerprint) resumes instead.
    let more = spec(&TINY.replace("trials = 4", "trials = 5"), dir.path());
    let r = run_experiment(&more, &out, &opts, &exec).unwrap();
    assert_eq!(r.resumed, 2);

    let mut fresh = opts.clone();
    fresh.fresh = true;
    let r = run_experiment(&other, &out, &fresh, &exec).unwrap();
    assert_eq!(r.resumed, 0);
    let aside = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with("trials.jsonl.old-")
        })
        .count();
    assert_eq!(aside, 1);
}

/// A fake executor: deterministic results from the seed; panics on one trial index if asked.
struct Fake {
    panic_on: Option<u32>,
}

impl brdf_experiment::run::Executor for Fake {
    fn run(
        &self,
        t: &brdf_experiment::spec::PlannedTrial,
        target: f64,
        _budget: sls::Budget,
    ) -> sls::TrialResult {
        if self.panic_on == Some(t.trial) {
            panic!("boom in trial {}", t.trial);
        }
        let secs = (t.seed % 1000) as f64 / 1000.0;
        let at = sls::Stamp {
            cpu_seconds: secs,
            wall_seconds: secs,
            evaluations: sls::EvalCounts {
                residual_rows: t.seed % 977,
                jacobian_rows: 0,
                rmse_rows: 100,
                ..sls::EvalCounts::default()
            },
        };
        sls::TrialResult {
            stop: sls::StopReason::Target,
            reached_at: Some(at),
            ended_at: at,
            best_rmse: target,
            best_x: vec![secs],
            trace: vec![sls::TracePoint { at, rmse: target }],
            counters: Vec::new(),
            failure: None,
        }
    }
}

#[test]
fn a_panicking_trial_stops_the_run_and_keeps_finished_trials() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(TINY, dir.path());
    let out = dir.path().join("r");
    let err = run_experiment(&s, &out, &options(1), &Fake { panic_on: Some(2) }).unwrap_err();
    let msg = err.to_string();
    assert!(
        matches!(err, RunError::TrialPanicked { .. }) && msg.contains("boom in trial 2"),
        "{msg}"
    );
    // With one thread the plan order is followed: trials 0 and 1 of every configuration finished.
    let kept = read_results(&out).unwrap().records.len();
    assert_eq!(kept, 6);
    let r = run_experiment(&s, &out, &options(2), &Fake { panic_on: None }).unwrap();
    assert_eq!((r.resumed, r.new_trials), (6, 6));
}

/// [`Fake`] whose configuration 1 fails at every trial ([`sls::StopReason::Failed`], as an
/// algorithm that calls `Search::fail`): the runner skips it from the first failure on.
struct FailingConfig;

impl brdf_experiment::run::Executor for FailingConfig {
    fn run(
        &self,
        t: &brdf_experiment::spec::PlannedTrial,
        target: f64,
        b: sls::Budget,
    ) -> sls::TrialResult {
        let mut result = Fake { panic_on: None }.run(t, target, b);
        if t.config == 1 {
            result.stop = sls::StopReason::Failed;
            result.failure = Some(format!("bad luck in {}", t.key));
        }
        result
    }
}

#[test]
fn a_failed_configuration_is_skipped_while_the_others_run() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(TINY, dir.path());
    let out = dir.path().join("r");
    let r = run_experiment(&s, &out, &options(2), &FailingConfig).unwrap();
    // Every trial of the other two configurations ran and was stored; none of configuration 1.
    assert_eq!((r.new_trials, r.missing), (8, 4));
    let label = &s.configurations[1].label;
    assert!(r.records.iter().all(|rec| &rec.config != label));
    // One failure for the configuration, naming it, its trial, seed and message.
    assert_eq!(r.failures.len(), 1, "{:?}", r.failures);
    let f = &r.failures[0];
    assert_eq!(f.config, 1);
    let want = format!("configuration `{label}` failed in trial ");
    assert!(f.message.starts_with(&want), "{}", f.message);
    assert!(
        f.message.contains("(seed ") && f.message.contains("bad luck in"),
        "{}",
        f.message
    );
    assert_eq!(read_results(&out).unwrap().records.len(), 8);
    // Fixed, the run resumes with the skipped configuration only.
    let r = run_experiment(&s, &out, &options(2), &Fake { panic_on: None }).unwrap();
    assert_eq!((r.resumed, r.new_trials, r.missing), (8, 4, 0));
}
