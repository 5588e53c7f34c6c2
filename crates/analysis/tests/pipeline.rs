//! The run sequence as one library call (`brdf_analysis::pipeline::run`): results read once
//! and each instance built once, the same files as `brdf-sls run` (report.html included), a
//! failing algorithm's configuration reported after everything else is written, and a resumed
//! run that says when the program or a kind's settings schema changed.

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

use std::path::Path;

use brdf_analysis::pipeline::{ConfigurationsFailed, Finished, Request, run};
use brdf_experiment::instance::builds_on_this_thread;
use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::SlsExecutor;
use brdf_experiment::store::results_reads_on_this_thread;
use serde::{Deserialize, Serialize};
use sls::registry::Algorithm;
use sls::{ConfigError, Search, Stop};

/// Random picks until the budget, or a failure at once when `fail` is set.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct Picks {
    fail: bool,
    width: f64,
}

impl Algorithm for Picks {
    const KIND: &'static str = "pipeline-test-picks";
    fn validate(&self) -> Result<(), ConfigError> {
        Ok(())
    }
    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        if self.fail {
            let left = search.budget().evaluations_left();
            return Err(search.fail(format!("told to fail with {left:?} evaluations left")));
        }
        let mut x = vec![0.0; search.dim()];
        loop {
            search.random_pick(&mut x);
            search.evaluate(&x)?;
        }
    }
}

fn register() {
    let _ = sls::registry::register::<Picks>();
}

/// TINY with a configuration of [`Picks`] and `trials` trials.
fn spec_text(trials: u32, fail: bool) -> String {
    common::TINY
        .replace("trials = 4", &format!("trials = {trials}"))
        .replace(
            "[[algorithm]]\nkind = \"rpls\"",
            &format!(
                "[[algorithm]]\nlabel = \"PICKS\"\nkind = \"pipeline-test-picks\"\nfail = {fail}"
            ),
        )
}

fn run_in(text: &str, dir: &Path, plots: bool) -> anyhow::Result<Finished> {
    register();
    let spec = common::spec(text, dir);
    let mut request = Request::new(spec, dir.join("out"), 2);
    request.plots = plots;
    request.notes = false;
    request.options.progress = ProgressMode::Quiet;
    run(request, |spec, built, kernel| {
        Ok(SlsExecutor::from_built(spec, built, kernel)?)
    })
}

#[test]
fn one_read_one_build_per_instance_and_the_report_page() {
    let dir = tempfile::tempdir().unwrap();
    let (reads, builds) = (results_reads_on_this_thread(), builds_on_this_thread());
    let first = run_in(&spec_text(1, false), dir.path(), true).unwrap();
    assert_eq!(
        (
            results_reads_on_this_thread() - reads,
            builds_on_this_thread() - builds
        ),
        (0, 1),
        "a new folder: nothing to read, the instance built once"
    );
    assert_eq!(first.outcome.new_trials, 3);
    let out = dir.path().join("out");
    for f in [
        "trials.jsonl",
        "stats.csv",
        "table.txt",
        "summary.json",
        "report.html",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    assert!(first.report.files.contains(&out.join("report.html")));
    assert!(
        first.summary.ends_with("page: report.html)"),
        "{}",
        first.summary
    );
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("PICKS"));
    // Resumed with more trials: the results file read once, the instance built once.
    let (reads, builds) = (results_reads_on_this_thread(), builds_on_this_thread());
    let second = run_in(&spec_text(2, false), dir.path(), false).unwrap();
    assert_eq!(
        (
            results_reads_on_this_thread() - reads,
            builds_on_this_thread() - builds
        ),
        (1, 1)
    );
    assert_eq!((second.outcome.resumed, second.outcome.new_trials), (3, 3));
    // The same program resumed: nothing to say about it.
    assert!(
        !second.warnings.iter().any(|l| l.contains("written by")),
        "{:?}",
        second.warnings
    );
}

#[test]
fn a_failing_configuration_ends_the_run_after_the_statistics() {
    let dir = tempfile::tempdir().unwrap();
    let err = run_in(&spec_text(2, true), dir.path(), false).unwrap_err();
    let failed = err
        .downcast_ref::<ConfigurationsFailed>()
        .unwrap_or_else(|| panic!("{err:#}"));
    assert_eq!(failed.missing, 2);
    let text = err.to_string();
    assert!(
        text.starts_with(
            "running experiment `tiny`: configuration `PICKS` failed in trial tuning/PICKS/"
        ),
        "{text}"
    );
    // The budget the algorithm saw: the whole evaluation budget was left.
    assert!(
        text.contains("told to fail with Some(400000) evaluations left"),
        "{text}"
    );
    assert!(
        text.contains("trials missing: 2; the other configurations ran"),
        "{text}"
    );
    let out = dir.path().join("out");
    let table = std::fs::read_to_string(out.join("table.txt")).unwrap();
    assert!(table.contains("AED"), "{table}");
    let stored = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    assert!(
        !stored.contains("\"config\":\"PICKS\""),
        "no failed trial is stored"
    );
}

#[test]
fn a_resumed_run_says_that_the_program_or_a_schema_changed() {
    let dir = tempfile::tempdir().unwrap();
    let first = run_in(&spec_text(1, false), dir.path(), false).unwrap();
    let changed = |w: &[String]| w.iter().any(|l| l.contains("changed"));
    assert!(!changed(&first.warnings), "{:?}", first.warnings);
    let path = dir.path().join("out/trials.jsonl");
    let stored = std::fs::read_to_string(&path).unwrap();
    let schema = sls::registry::schema_hash("pipeline-test-picks").unwrap();
    assert!(stored.contains(&format!(
        "\"schemas\":{{\"pipeline-test-picks\":\"{schema}\"}}"
    )));
    // As if written by another version, with another schema of the kind.
    let older = stored
        .replace(&schema, "0123456789abcdef")
        .replace(brdf_experiment::PROGRAM_VERSION, "0.1.0 (git 000000000000)");
    std::fs::write(&path, older).unwrap();
    let second = run_in(&spec_text(1, false), dir.path(), false).unwrap();
    let notes = second.warnings.join("\n");
    assert!(
        notes.contains("the results so far were written by (brdf-sls 0.1.0 (git 000000000000))"),
        "{notes}"
    );
    assert!(
        notes.contains("the settings schema of kind `pipeline-test-picks` changed"),
        "{notes}"
    );
}
