//! Golden tests: the default experiment's plan, fingerprint and a few seeded trial outcomes are
//! pinned to fixed values, so an accidental change of random streams, of the fingerprint
//! formula or of a search's path fails here instead of silently invalidating stored results.
//! The statistics table and one SVG of fixed records are pinned to files under tests/golden/.
//!
//! The seeded outcomes were recorded from this version (see the constants for how they relate
//! to the committed results/default).

use std::path::Path;
use std::sync::Arc;

use brdf_experiment::spec::Spec;
use brdf_model::Kernel;
use sls::{Budget, EvalCounts};

/// Fingerprint of experiments/default.toml (as stored in results/default/trials.jsonl.gz).
const DEFAULT_FINGERPRINT: &str = "251a3ecf19bddec7";

#[test]
fn default_plan_and_fingerprint() {
    let spec = Spec::default_experiment();
    assert_eq!(spec.fingerprint(), DEFAULT_FINGERPRINT);
    let plan = spec.trials_plan();
    assert_eq!(plan.len(), 750);
    let first: Vec<(&str, u64)> = plan[..4].iter().map(|t| (t.key.as_str(), t.seed)).collect();
    assert_eq!(
        first,
        vec![
            ("tuning/AED/0", 16712816481137707360),
            ("tuning/AERS/0", 8821328397174705835),
            ("tuning/RPLS/0", 666174647954552605),
            ("tuning/AED/1", 2644763349156984446),
        ]
    );
}

#[test]
fn default_data_hash() {
    // The generated data themselves: a change of the generator's random stream or of the
    // model changes this, and a resume on such data is refused.
    let spec = Spec::default_experiment();
    let built = brdf_experiment::instance::build(&spec.instances[0]).unwrap();
    assert_eq!(
        brdf_experiment::seed::data_hash(&built.data),
        DEFAULT_DATA_HASH
    );
}

/// [`brdf_experiment::seed::data_hash`] of the default experiment's instance.
const DEFAULT_DATA_HASH: &str = "76fb9762eed8b52a";

/// Evaluation counts (residual, Jacobian, RMSE rows; the paper's count) when the target was
/// reached, for `(configuration, trial)` of the default experiment under `kernel`.
fn reached(kernel: Kernel, config: &str, trial: u32) -> (u64, u64, u64) {
    let spec = Spec::default_experiment();
    let built = brdf_experiment::instance::build(&spec.instances[0]).unwrap();
    let objective =
        sls::BrdfObjective::with_kernel(Arc::clone(&built.data), built.layout.clone(), kernel)
            .unwrap();
    let ci = spec
        .configurations
        .iter()
        .position(|c| c.label == config)
        .unwrap();
    let t = spec
        .trials_plan()
        .into_iter()
        .find(|t| t.config == ci && t.trial == trial)
        .unwrap();
    // An evaluation budget instead of the spec's CPU cutoff keeps the outcome independent of
    // the machine's speed; these trials reach the target long before either limit.
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(2_000_000_000),
    };
    let r = sls::run_trial(
        &objective,
        &spec.configurations[ci].algorithm,
        t.seed,
        budget,
        spec.instances[0].run_target(),
    );
    let EvalCounts {
        residual_rows,
        jacobian_rows,
        rmse_rows,
        ..
    } = r.reached_at.expect("the target is reached").evaluations;
    (residual_rows, jacobian_rows, rmse_rows)
}

/// The trials pinned for the SIMD kernels: (configuration, trial) of the default experiment.
const PINNED: [(&str, u32); 4] = [("AED", 0), ("AED", 1), ("AED", 2), ("RPLS", 1)];

/// [`reached`] for each of `trials` under `kernel`, or `None` (saying so) when this CPU cannot
/// run the kernel; the other kernels' tests still run.
fn pinned_outcomes(kernel: Kernel, trials: &[(&str, u32)]) -> Option<Vec<(u64, u64, u64)>> {
    if kernel.resolve().is_err() {
        eprintln!("skipped: this CPU cannot run the {kernel} kernel");
        return None;
    }
    Some(trials.iter().map(|&(c, t)| reached(kernel, c, t)).collect())
}

#[test]
fn seeded_trials_avx2() {
    if let Some(got) = pinned_outcomes(Kernel::Avx2, &PINNED) {
        assert_eq!(got, AVX2);
    }
}

/// Outcomes with the AVX2 kernel. Before the descent changes of 2026-12-01 these trials took
/// (9240, 7180, 90000), (4993, 2990, 60000), (9653, 7140, 90000) and (230000, 160000, 0);
/// from then until the searches' descents left numerically dead columns free again
/// (2026-12-02), trial 0 took (22913, 19545, 120000) and trial 2 (7877, 5596, 90000).
const AVX2: [(u64, u64, u64); 4] = [
    (9315, 7155, 90000),
    (4993, 2990, 60000),
    (8024, 5596, 90000),
    (230000, 160000, 0),
];

#[test]
fn seeded_trials_avx512() {
    if let Some(got) = pinned_outcomes(Kernel::Avx512, &PINNED) {
        assert_eq!(got, AVX512);
    }
}

/// Outcomes with the AVX-512 kernel, the `auto` choice on CPUs with AVX-512F. Its exponential
/// rounds `x log2(e)` to an integer with `roundscale` instead of the fused magic-number sum and
/// scales with `scalef`, so a value can differ from the AVX2 and portable kernels' in the last
/// bit and a path from theirs (here AED trial 2's does); the outcomes are the
/// same on every AVX-512F CPU, whose instructions are exactly specified. Recorded on an AMD
/// Zen 4 machine, with the kernel's degree-11 exponential and fdlibm logarithm (since
/// 2026-12-02). The committed results/default (rewritten on 2026-12-02 with this kernel)
/// holds exactly these outcomes for these trials.
const AVX512: [(u64, u64, u64); 4] = [
    (9265, 7130, 90000),
    (4993, 2990, 60000),
    (14067, 9815, 100000),
    (230000, 160000, 0),
];

#[test]
fn seeded_trials_portable() {
    let trials = [("AED", 0), ("AED", 1), ("RPLS", 1)];
    let got = pinned_outcomes(Kernel::Portable, &trials).expect("every CPU runs it");
    assert_eq!(got, PORTABLE);
}

/// Outcomes with the portable kernel (any x86-64 CPU). Until its exponential's polynomial
/// went to Estrin's form (2026-12-03, a last-bit difference in some values) trial 0 took
/// (9340, 7180, 90000).
const PORTABLE: [(u64, u64, u64); 3] = [
    (9315, 7155, 90000),
    (4993, 2990, 60000),
    (230000, 160000, 0),
];

fn golden_file(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(name)
}

/// Compares `text` with tests/golden/NAME; `BRDF_SLS_BLESS=1` rewrites the file instead.
fn assert_golden(name: &str, text: &str) {
    let path = golden_file(name);
    if std::env::var_os("BRDF_SLS_BLESS").is_some() {
        std::fs::write(&path, text).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (BRDF_SLS_BLESS=1 writes it)", path.display()));
    assert!(
        want == text,
        "{} changed; if intended, rerun with BRDF_SLS_BLESS=1 and review the diff",
        path.display()
    );
}

/// Fixed records of the default plan: a deterministic function of each trial's seed.
fn fixed_records(spec: &Spec) -> Vec<brdf_experiment::store::TrialRecord> {
    spec.trials_plan()
        .into_iter()
        .filter(|t| t.trial < 20)
        .map(|t| {
            let inst = &spec.instances[t.instance];
            let secs = 1e-4 * (1 + t.seed % 997) as f64 * (1 + t.config) as f64;
            let evaluations = EvalCounts {
                residual_rows: t.seed % 100_003,
                jacobian_rows: t.seed % 50_021,
                rmse_rows: 10_000 * (t.seed % 17),
                ..EvalCounts::default()
            };
            let at = sls::Stamp {
                cpu_seconds: secs,
                wall_seconds: secs,
                evaluations,
            };
            let reached = t.seed % 5 != 0;
            let rmse = if reached { 0.101 } else { 0.115 };
            brdf_experiment::store::TrialRecord {
                key: t.key.clone(),
                instance: inst.name.clone(),
                config: spec.configurations[t.config].label.clone(),
                trial: t.trial,
                seed: t.seed,
                target: inst.run_target(),
                budget: spec.budget,
                result: sls::TrialResult {
                    stop: if reached {
                        sls::StopReason::Target
                    } else {
                        sls::StopReason::CpuBudget
                    },
                    reached_at: reached.then_some(at),
                    ended_at: at,
                    best_rmse: rmse,
                    best_x: vec![0.1; 6],
                    trace: vec![sls::TracePoint { at, rmse }],
                    counters: Vec::new(),
                    failure: None,
                },
            }
        })
        .collect()
}

#[test]
fn stats_table_of_fixed_records() {
    let mut spec = Spec::default_experiment();
    spec.trials = 20;
    let records = fixed_records(&spec);
    let stats = brdf_analysis::report::compute_stats(&spec, &records);
    assert_golden("table.txt", &brdf_analysis::stats::table(&stats));
}

#[test]
fn rtd_svg_of_fixed_records() {
    let mut spec = Spec::default_experiment();
    spec.trials = 20;
    spec.plots.draw = vec![brdf_experiment::spec::PlotKind::Rtd];
    spec.plots.formats = vec![brdf_experiment::spec::PlotFormat::Svg];
    let records = fixed_records(&spec);
    let dir = tempfile::tempdir().unwrap();
    brdf_analysis::report::write_report(&spec, &records, &[], dir.path(), true).unwrap();
    let svg = std::fs::read_to_string(dir.path().join("plots/tuning-rtd-cpu-q0.11.svg")).unwrap();
    assert_golden("tuning-rtd-cpu-q0.11.svg", &svg);
}
