//! Sharded runs and merging, without a cluster: the shards of a plan partition it, shards run
//! in-process or as `brdf-sls run --shard K/N` subprocesses merge to exactly a single run's
//! per-trial outcomes, duplicates are removed, missing trials fail the merge unless
//! `--allow-partial`, merging is idempotent, and shards of a different spec are refused.

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunOptions, SlsExecutor, run_experiment, run_shard};
use brdf_experiment::shard::Shard;
use brdf_experiment::store::{TRIALS_FILE, read_results};

use common::{TINY, deterministic_view, spec};

fn options() -> RunOptions {
    RunOptions {
        threads: 2,
        fresh: false,
        progress: ProgressMode::Quiet,
        limit: None,
    }
}

fn bin(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn views(dir: &Path) -> Vec<String> {
    read_results(dir)
        .unwrap()
        .records
        .iter()
        .map(deterministic_view)
        .collect()
}

/// Writes tiny.toml into `dir` and runs the `n` shards of it as subprocesses; returns the
/// shard folders.
fn run_shards(dir: &Path, n: u32) -> Vec<PathBuf> {
    std::fs::write(dir.join("tiny.toml"), TINY).unwrap();
    (1..=n)
        .map(|k| {
            let shard = format!("{k}/{n}");
            let o = bin(
                dir,
                &[
                    "run",
                    "tiny.toml",
                    "--shard",
                    &shard,
                    "--threads",
                    "1",
                    "--no-plots",
                    "--progress",
                    "quiet",
                ],
            );
            assert!(o.status.success(), "shard {shard}: {}", stderr(&o));
            let out = dir.join(format!("runs/tiny/shard-{k}-of-{n}"));
            assert!(out.join(TRIALS_FILE).exists(), "{}", out.display());
            out
        })
        .collect()
}

fn merge(dir: &Path, out: &str, inputs: &[PathBuf], extra: &[&str]) -> Output {
    let mut args = vec!["merge".to_string(), out.to_string()];
    args.extend(inputs.iter().map(|p| p.to_string_lossy().into_owned()));
    args.extend(["--no-plots".to_string()]);
    args.extend(extra.iter().map(|s| s.to_string()));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    bin(dir, &args)
}

/// The single-process reference run of tiny.toml in `dir/single`.
fn single_run(dir: &Path) -> Vec<String> {
    let s = spec(TINY, dir);
    let (exec, _) = SlsExecutor::new(&s, brdf_model::Kernel::Auto).unwrap();
    let single = run_experiment(&s, &dir.join("single"), &options(), &exec).unwrap();
    assert_eq!(single.records.len(), 12);
    single.records.iter().map(deterministic_view).collect()
}

#[test]
fn shards_partition_the_plan_and_keep_seeds() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = spec(TINY, dir.path());
    s.trials = 10;
    let plan = s.trials_plan();
    for n in 1..=7 {
        let mut union = Vec::new();
        for shard in Shard::all(n).unwrap() {
            let part = shard.select(plan.clone());
            // Every configuration gets a fair share of each shard: 10 trials each.
            for c in 0..s.configurations.len() {
                let k = part.iter().filter(|t| t.config == c).count() as u32;
                assert!(
                    k == 10 / n || k == 10_u32.div_ceil(n),
                    "{shard}: config {c}: {k}"
                );
            }
            union.extend(part);
        }
        union.sort_by_key(|t| plan.iter().position(|p| p.key == t.key).unwrap());
        assert_eq!(union, plan, "{n} shards");
    }
}

#[test]
fn in_process_shards_merge_to_the_single_run() {
    let dir = tempfile::tempdir().unwrap();
    let reference = single_run(dir.path());
    let s = spec(TINY, dir.path());
    let (exec, _) = SlsExecutor::new(&s, brdf_model::Kernel::Auto).unwrap();
    let mut inputs = Vec::new();
    for shard in Shard::all(3).unwrap() {
        let out = dir.path().join(shard.dir_name());
        let o = run_shard(&s, Some(shard), &out, &options(), &exec).unwrap();
        assert_eq!(o.records.len(), 4, "{shard}");
        assert_eq!(read_results(&out).unwrap().header.shard, Some(shard));
        inputs.push(out);
    }
    let merged = brdf_merge::merge(&dir.path().join("merged"), &inputs, false).unwrap();
    assert!(merged.missing.is_empty() && merged.duplicates.is_empty());
    assert!(merged.written.is_some());
    assert_eq!(
        merged
            .records
            .iter()
            .map(deterministic_view)
            .collect::<Vec<_>>(),
        reference
    );
    assert_eq!(views(&dir.path().join("merged")), reference);
    let header = read_results(&dir.path().join("merged")).unwrap().header;
    assert_eq!(header.shard, None);
    assert!(!header.kernel.is_empty());
    assert_eq!(header.program_version, brdf_experiment::PROGRAM_VERSION);
}

#[test]
fn a_folder_of_another_shard_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tiny.toml"), TINY).unwrap();
    let run = |shard: &str| {
        bin(
            dir.path(),
            &[
                "run",
                "tiny.toml",
                "--shard",
                shard,
                "--out",
                "x",
                "--limit",
                "1",
                "--no-plots",
                "--progress",
                "quiet",
            ],
        )
    };
    assert!(run("1/2").status.success());
    let o = run("2/2");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("shard 1/2"), "{}", stderr(&o));
    let o = bin(dir.path(), &["run", "tiny.toml", "--shard", "3/2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("3/2"), "{}", stderr(&o));
}

#[test]
fn subprocess_shards_merge_dedupe_and_remerge_identically() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let reference = single_run(d);
    let shards = run_shards(d, 4);

    // Merge equals the single run.
    let o = merge(d, "merged", &shards, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(views(&d.join("merged")), reference);
    assert!(d.join("merged/stats.csv").exists());
    let bytes = std::fs::read(d.join("merged").join(TRIALS_FILE)).unwrap();

    // Merging again into the same folder, and merging the merged folder elsewhere, write the
    // same bytes.
    let o = merge(d, "merged", &shards, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("12 trials were already in"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read(d.join("merged").join(TRIALS_FILE)).unwrap(),
        bytes
    );
    let o = merge(d, "again", &[d.join("merged")], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.join("again").join(TRIALS_FILE)).unwrap(),
        bytes
    );

    // A copy of a shard: its trials are duplicates, removed and reported.
    let copy = d.join("copy");
    std::fs::create_dir_all(&copy).unwrap();
    std::fs::copy(shards[1].join(TRIALS_FILE), copy.join(TRIALS_FILE)).unwrap();
    let mut with_copy = shards.clone();
    with_copy.push(copy);
    let o = merge(d, "deduped", &with_copy, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let n = read_results(&shards[1]).unwrap().records.len();
    assert!(
        stderr(&o).contains(&format!("removed {n} duplicate")),
        "{}",
        stderr(&o)
    );
    assert_eq!(views(&d.join("deduped")), reference);

    // A missing shard: exit 1, the missing trials listed with their shard, nothing written.
    let o = merge(d, "partial", &shards[..3], &[]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let missing = 12
        - shards[..3]
            .iter()
            .map(|s| read_results(s).unwrap().records.len())
            .sum::<usize>();
    assert!(missing > 0);
    assert!(
        stderr(&o).contains(&format!("missing {missing} of 12 trials")),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains("shard 4/4"), "{}", stderr(&o));
    assert!(!d.join("partial").join(TRIALS_FILE).exists());
    // ... unless --allow-partial.
    let o = merge(d, "partial", &shards[..3], &["--allow-partial"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        read_results(&d.join("partial")).unwrap().records.len(),
        12 - missing
    );
    // Completing it later gives the single run.
    let o = merge(d, "partial", &shards[3..], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(views(&d.join("partial")), reference);
}

#[test]
fn shards_of_a_different_spec_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("tiny.toml"), TINY).unwrap();
    std::fs::write(d.join("other.toml"), TINY.replace("seed = 11", "seed = 12")).unwrap();
    for spec in ["tiny.toml", "other.toml"] {
        let o = bin(
            d,
            &[
                "run",
                spec,
                "--shard",
                "1/2",
                "--limit",
                "1",
                "--no-plots",
                "--progress",
                "quiet",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let inputs = [
        d.join("runs/tiny/shard-1-of-2"),
        d.join("runs/other/shard-1-of-2"),
    ];
    let o = merge(d, "m", &inputs, &["--allow-partial"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("different spec"), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("runs/other/shard-1-of-2"),
        "{}",
        stderr(&o)
    );
    assert!(!d.join("m").join(TRIALS_FILE).exists());
    // A folder that does not exist is named.
    let o = merge(d, "m", &[d.join("nope")], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("nope"), "{}", stderr(&o));
}
