//! The results store across processes: a second run on a folder in use is refused at once,
//! and runs killed (SIGKILL) at several points resume to exactly the per-trial outcomes of an
//! uninterrupted run.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use brdf_experiment::store::read_results;

/// Trials that each spend a fixed evaluation budget (the target 0 is never reached), so every
/// trial's outcome is a function of its seed alone.
const SPEC: &str = r#"
name = "kill"
seed = 5
trials = 12
kernel = "portable"

[budget]
evaluations = 3000000

[[instance]]
name = "tuning"
targets = [0.0]
[instance.synthetic]
params = "tuning"
samples = 1000
sigma = 0.1

[[algorithm]]
kind = "aed"

[[algorithm]]
kind = "rpls"
"#;

fn command(dir: &Path, out: &str) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_brdf-sls"));
    c.args([
        "run",
        "kill.toml",
        "--out",
        out,
        "--threads",
        "2",
        "--no-plots",
        "--progress",
        "quiet",
    ])
    .current_dir(dir)
    .stdout(Stdio::null())
    .stderr(Stdio::piped());
    c
}

/// (stop, best RMSE bits, paper's evaluation count) per trial key.
fn outcomes(dir: &Path) -> BTreeMap<String, (String, u64, u64)> {
    read_results(dir)
        .unwrap()
        .records
        .into_iter()
        .map(|r| {
            (
                r.key,
                (
                    format!("{:?}", r.result.stop),
                    r.result.best_rmse.to_bits(),
                    r.result.ended_at.evaluations.total(),
                ),
            )
        })
        .collect()
}

/// Runs the spec in `dir` into `dir/out` to its end (resuming what is there) and returns the
/// per-trial outcomes.
fn run_to_end(dir: &Path, out: &str) -> BTreeMap<String, (String, u64, u64)> {
    let o = command(dir, out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    outcomes(&dir.join(out))
}

/// A temporary folder holding the spec and its uninterrupted run in `whole/`, with that run's
/// per-trial outcomes: the reference a broken run must resume to.
fn spec_and_whole_run() -> (tempfile::TempDir, BTreeMap<String, (String, u64, u64)>) {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("kill.toml"), SPEC).unwrap();
    let whole = run_to_end(tmp.path(), "whole");
    (tmp, whole)
}

fn trial_lines(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("trials.jsonl"))
        .map(|t| t.matches("\"type\":\"trial\"").count())
        .unwrap_or(0)
}

#[test]
fn killed_runs_resume_to_the_uninterrupted_outcomes() {
    let (tmp, whole) = spec_and_whole_run();
    let dir = tmp.path();
    assert_eq!(whole.len(), 24);

    // Kill after 1, 3, 6 and 10 finished trials (and whatever was in flight), then finish.
    let broken = dir.join("broken");
    for after in [1, 3, 6, 10] {
        let mut child = command(dir, "broken").spawn().unwrap();
        let started = Instant::now();
        while trial_lines(&broken) < after && started.elapsed() < Duration::from_secs(60) {
            if child.try_wait().unwrap().is_some() {
                break;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        let _ = child.kill();
        let _ = child.wait();
    }
    let resumed = run_to_end(dir, "broken");
    assert_eq!(
        resumed, whole,
        "resumed outcomes differ from the uninterrupted run"
    );
    let c = read_results(&broken).unwrap();
    assert!(
        c.duplicates.is_empty(),
        "duplicate trials: {:?}",
        c.duplicates
    );
    assert!(
        c.sessions.len() >= 2,
        "the kills should have left several sessions"
    );
}

#[test]
fn a_second_run_on_a_folder_in_use_fails_at_once_naming_the_holder() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("kill.toml"),
        SPEC.replace("trials = 12", "trials = 40"),
    )
    .unwrap();
    let mut first = command(dir, "shared").spawn().unwrap();
    let lock = dir.join("shared/.lock");
    let results = dir.join("shared").join(brdf_experiment::store::TRIALS_FILE);
    let started = Instant::now();
    // The lock is taken before the instances are built; wait for the results file too, so the
    // first run is writing trials when the second starts.
    while (std::fs::read_to_string(&lock).map_or(true, |t| t.trim().is_empty())
        || !results.exists())
        && started.elapsed() < Duration::from_secs(60)
    {
        std::thread::sleep(Duration::from_millis(2));
    }
    let t0 = Instant::now();
    let second = command(dir, "shared").output().unwrap();
    let waited = t0.elapsed();
    let first_still_running = first.try_wait().unwrap().is_none();
    let _ = first.kill();
    let _ = first.wait();
    assert!(
        first_still_running,
        "the first run ended too soon to test the lock"
    );
    let err = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(1), "{err}");
    assert!(
        err.contains("in use") && err.contains(&format!("PID {}", first.id())),
        "{err}"
    );
    assert!(
        waited < Duration::from_secs(10),
        "the second run waited {waited:?}"
    );
    // The folder is intact: every line parses.
    read_results(&dir.join("shared")).unwrap();
}

/// A write that fails part-way (here: the file-size limit, `EFBIG`; a full disk fails the same
/// way) ends the run with status 1 and a message saying what happened, and leaves the results
/// file cut back to its last complete line, so the next run resumes to the outcomes of an
/// uninterrupted one. `prelude` runs in bash before the binary is exec'ed under
/// `ulimit -f 12` (bash counts KiB).
fn a_failed_write_is_cut_back_and_resumes(prelude: &str) {
    let (tmp, whole) = spec_and_whole_run();
    let dir = tmp.path();

    let limited = command(dir, "limited");
    let mut args: Vec<String> = vec![limited.get_program().to_string_lossy().into_owned()];
    args.extend(limited.get_args().map(|a| a.to_string_lossy().into_owned()));
    let o = Command::new("bash")
        .arg("-c")
        .arg(format!("{prelude} ulimit -f 12; exec \"$@\""))
        .arg("bash")
        .args(&args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{:?}: {err}", o.status);
    assert!(err.contains("cut back to its last complete line"), "{err}");
    assert_eq!(err.matches("File too large").count(), 1, "{err}");

    let text = std::fs::read(dir.join("limited/trials.jsonl")).unwrap();
    assert!(text.len() <= 12 * 1024 && text.ends_with(b"\n"));
    let kept = read_results(&dir.join("limited")).unwrap();
    assert!(kept.torn.is_none());
    assert!(kept.records.len() < whole.len());

    assert_eq!(run_to_end(dir, "limited"), whole);
}

/// With SIGXFSZ ignored by the caller (kept across exec), the write fails with `EFBIG`.
#[cfg(target_os = "linux")]
#[test]
fn a_failed_write_leaves_no_torn_line_and_the_run_resumes() {
    a_failed_write_is_cut_back_and_resumes("trap '' XFSZ;");
}

/// With the signal's default action (which kills a process): the binary ignores SIGXFSZ
/// itself, so the same cut-back path runs.
#[cfg(target_os = "linux")]
#[test]
fn the_file_size_signal_does_not_kill_the_run() {
    a_failed_write_is_cut_back_and_resumes("");
}
