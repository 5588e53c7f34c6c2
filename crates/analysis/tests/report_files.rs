//! The statistics and plots written for a results folder after a run.

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunOptions, SlsExecutor, run_experiment};
use brdf_experiment::store::read_results;

use common::{TINY, spec};

fn options(threads: usize) -> RunOptions {
    RunOptions {
        threads,
        fresh: false,
        progress: ProgressMode::Quiet,
        limit: None,
    }
}

#[test]
fn report_writes_statistics_and_plots() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(TINY, dir.path());
    let (exec, _) = SlsExecutor::new(&s, brdf_model::Kernel::Auto).unwrap();
    let out = dir.path().join("r");
    let run = run_experiment(&s, &out, &options(2), &exec).unwrap();
    let c = read_results(&out).unwrap();
    let report =
        brdf_analysis::report::write_report(&s, &run.records, &c.sessions, &out, true).unwrap();
    // 3 configurations x 2 targets.
    assert_eq!(report.analysis.stats.configs.len(), 6);
    assert!(report.table.contains("AED phi=1.2"), "{}", report.table);
    for name in [
        "stats.json",
        "stats.csv",
        "tests.csv",
        "summary.json",
        "table.txt",
    ] {
        assert!(out.join(name).metadata().unwrap().len() > 0, "{name}");
    }
    let plots = out.join("plots");
    for base in [
        "tuning-rtd-cpu-q0.105",
        "tuning-rtd-evals-q0.12",
        "tuning-sweep-AED-phi",
        "tuning-trace",
        "tuning-scatter",
        "tuning-error-time",
        "tuning-ecdf-targets",
    ] {
        for ext in ["png", "svg"] {
            let p = plots.join(format!("{base}.{ext}"));
            let len = p.metadata().map(|m| m.len()).unwrap_or(0);
            assert!(len > 1000, "{} missing or tiny", p.display());
        }
    }
    let csv = std::fs::read_to_string(out.join("stats.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 6 * 2);
    let tests = std::fs::read_to_string(out.join("tests.csv")).unwrap();
    // 3 pairs x 2 targets x 2 measures.
    assert_eq!(tests.lines().count(), 1 + 12);
}
