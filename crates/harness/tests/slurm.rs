//! A real Slurm job array: `brdf-sls slurm --submit` runs a small experiment as 4 shards plus
//! the merge job, and the merged per-trial outcomes equal a single-process run's.
//!
//! Needs a Slurm cluster that can run jobs from this machine (scripts/slurm-local.sh starts
//! one) and runs only when BRDF_SLS_SLURM=1; otherwise it says why it is skipped and passes.
//! scripts/ci-slurm.sh does both.

use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunOptions, SlsExecutor, run_experiment};
use brdf_experiment::spec::Spec;
use brdf_experiment::store::{TrialRecord, read_results};

/// An evaluation budget only (no CPU time), so every trial's outcome, censored or not, is a
/// function of its seed; the portable kernel, so any node computes the same bits.
const SPEC: &str = r#"
name = "slurm-check"
seed = 21
trials = 8
kernel = "portable"

[budget]
evaluations = 1000000

[[instance]]
name = "tuning"
targets = [0.105, 0.12]
[instance.synthetic]
params = "tuning"
samples = 1000
sigma = 0.1
seed = 3

[[algorithm]]
kind = "aed"

[[algorithm]]
kind = "aers"

[[algorithm]]
kind = "rpls"

[stats]
bootstrap = 100
"#;

/// How long the jobs may take (queueing included) before the test fails.
const TIMEOUT: Duration = Duration::from_secs(240);

/// Writes past the test harness's output capture, so a skip shows in `cargo test` output.
fn say(text: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

/// (seed, reached the target, evaluations at the end, best RMSE bits) per trial key.
fn outcomes(records: &[TrialRecord]) -> BTreeMap<String, (u64, bool, u64, u64)> {
    records
        .iter()
        .map(|r| {
            (
                r.key.clone(),
                (
                    r.seed,
                    r.result.reached(),
                    r.result.ended_at.evaluations.total(),
                    r.result.best_rmse.to_bits(),
                ),
            )
        })
        .collect()
}

fn job_state(id: &str) -> String {
    let out = Command::new("scontrol")
        .args(["show", "job", id])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    out.split_whitespace()
        .find_map(|w| w.strip_prefix("JobState="))
        .unwrap_or("unknown")
        .to_string()
}

fn log_tail(dir: &Path) -> String {
    let mut s = String::new();
    if let Ok(entries) = std::fs::read_dir(dir.join("slurm/logs")) {
        for e in entries.flatten() {
            let text = std::fs::read_to_string(e.path()).unwrap_or_default();
            let tail: Vec<&str> = text.lines().rev().take(8).collect();
            s.push_str(&format!("--- {}\n", e.path().display()));
            for l in tail.into_iter().rev() {
                s.push_str(l);
                s.push('\n');
            }
        }
    }
    s
}

#[test]
fn slurm_array_of_four_shards_merges_to_the_single_run() {
    if std::env::var("BRDF_SLS_SLURM").as_deref() != Ok("1") {
        say(
            "SKIPPED slurm_array_of_four_shards_merges_to_the_single_run: set BRDF_SLS_SLURM=1 \
             with a Slurm cluster running (scripts/ci-slurm.sh starts one and runs this test)",
        );
        return;
    }
    let started = Instant::now();
    // Slurm runs the jobs as this user on this node: a folder both can reach.
    let dir = tempfile::tempdir_in(std::env::temp_dir()).unwrap();
    let d = dir.path();
    std::fs::write(d.join("check.toml"), SPEC).unwrap();
    let out = d.join("results");
    let o = Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args([
            "slurm",
            "check.toml",
            "--shards",
            "4",
            "--cpus-per-task",
            "1",
        ])
        .arg("--out")
        .arg(&out)
        .arg("--submit")
        .current_dir(d)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "brdf-sls slurm --submit failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    say(&stdout);
    let id = |name: &str| {
        stdout
            .lines()
            .find_map(|l| l.strip_prefix(name))
            .unwrap_or_else(|| panic!("no {name} line in:\n{stdout}"))
            .trim()
            .to_string()
    };
    let (array, merge) = (id("array_job="), id("merge_job="));

    // Wait until neither job is queued or running.
    let jobs = format!("{array},{merge}");
    loop {
        let q = Command::new("squeue")
            .args(["-h", "-j", &jobs, "-o", "%i %T"])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&q.stdout).into_owned();
        if q.status.success() && text.trim().is_empty() {
            break;
        }
        assert!(
            started.elapsed() < TIMEOUT,
            "jobs {jobs} not done after {TIMEOUT:?}:\n{text}\n{}",
            log_tail(&out)
        );
        std::thread::sleep(Duration::from_secs(1));
    }
    let slurm_seconds = started.elapsed().as_secs_f64();
    let state = job_state(&merge);
    assert!(
        state == "COMPLETED" || state == "unknown",
        "merge job {merge}: {state}\n{}",
        log_tail(&out)
    );
    let merged = read_results(&out)
        .unwrap_or_else(|e| panic!("no merged results ({e}):\n{}", log_tail(&out)));
    assert_eq!(merged.header.shard, None);
    assert!(out.join("stats.csv").exists(), "{}", log_tail(&out));
    for k in 1..=4 {
        let shard = read_results(&out.join(format!("shard-{k}-of-4"))).unwrap();
        assert_eq!(shard.header.shard.map(|s| (s.index, s.count)), Some((k, 4)));
        assert_eq!(shard.header.fingerprint, merged.header.fingerprint);
    }

    // The same spec in this process.
    let spec = Spec::parse(SPEC, "check.toml", "check", d).unwrap();
    let (exec, _) = SlsExecutor::new(&spec, spec.kernel).unwrap();
    let options = RunOptions {
        threads: 2,
        fresh: false,
        progress: ProgressMode::Quiet,
        limit: None,
    };
    let single = run_experiment(&spec, &d.join("single"), &options, &exec).unwrap();
    assert_eq!(single.records.len(), 24);
    assert_eq!(outcomes(&merged.records), outcomes(&single.records));
    let reached = single.records.iter().filter(|r| r.result.reached()).count();
    say(&format!(
        "slurm: 4-shard array + merge of 24 trials took {slurm_seconds:.1} s wall (submit to \
         done); merged outcomes equal the single run ({reached} of 24 reached the target)"
    ));
}
