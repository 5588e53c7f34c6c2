//! An algorithm registered from outside sls runs through the harness like a built-in one: its
//! spec entry is read and validated, its trials are budgeted, counted, traced, stored,
//! fingerprinted and resumed, and the statistics name it.

use std::sync::Once;

use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunOptions, SlsExecutor, run_experiment};
use brdf_experiment::spec::Spec;
use serde::{Deserialize, Serialize};
use sls::registry::{self, Algorithm};
use sls::{ConfigError, Search, Stop, StopReason};

/// Evaluates `batch` random picks per round and counts the rounds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct RandomPicks {
    batch: usize,
}

impl Default for RandomPicks {
    fn default() -> Self {
        Self { batch: 1 }
    }
}

impl Algorithm for RandomPicks {
    const KIND: &'static str = "test-random-picks";

    fn validate(&self) -> Result<(), ConfigError> {
        if self.batch == 0 {
            return Err(ConfigError::new(
                Self::KIND,
                "batch",
                "must be at least 1, found 0",
            ));
        }
        Ok(())
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        let mut x = vec![0.0; search.dim()];
        loop {
            for _ in 0..self.batch {
                search.random_pick(&mut x);
                search.evaluate(&x)?;
            }
            search.count("round");
        }
    }
}

fn register_once() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| registry::register::<RandomPicks>().unwrap());
}

/// 400 samples, an evaluation budget of 100 full-data RMSEs, a target no pick reaches.
const SPEC: &str = r#"
name = "custom"
seed = 2
trials = 3

[budget]
evaluations = 40000

[[instance]]
name = "tuning"
targets = [0.01]
[instance.synthetic]
params = "tuning"
samples = 400
sigma = 0.1
seed = 3

[[algorithm]]
kind = "rpls"

[[algorithm]]
label = "PICKS"
kind = "test-random-picks"
batch = 4

[stats]
bootstrap = 50
"#;

fn parse(text: &str, dir: &std::path::Path) -> Result<Spec, brdf_experiment::spec::SpecError> {
    Spec::parse(text, "custom.toml", "custom", dir)
}

fn options() -> RunOptions {
    RunOptions {
        threads: 2,
        fresh: false,
        progress: ProgressMode::Quiet,
        limit: None,
    }
}

#[test]
fn a_registered_algorithm_runs_stores_and_resumes_like_a_built_in() {
    register_once();
    let dir = tempfile::tempdir().unwrap();
    let spec = parse(SPEC, dir.path()).unwrap();
    let canonical = spec.canonical().to_string();
    assert!(
        canonical.contains(r#"{"batch":4,"kind":"test-random-picks"}"#),
        "{canonical}"
    );
    let (exec, _) = SlsExecutor::new(&spec, brdf_model::Kernel::Auto).unwrap();
    let out = dir.path().join("out");
    let first = run_experiment(&spec, &out, &options(), &exec).unwrap();
    assert_eq!((first.new_trials, first.resumed), (6, 0));
    let picks: Vec<_> = first
        .records
        .iter()
        .filter(|r| r.config == "PICKS")
        .collect();
    assert_eq!(picks.len(), 3);
    for r in &picks {
        let result = &r.result;
        // 100 full-data RMSEs of 400 samples fit the budget exactly; the 101st is refused.
        assert_eq!(result.stop, StopReason::EvaluationBudget);
        assert_eq!(result.ended_at.evaluations.rmse_rows, 40_000);
        assert_eq!(result.ended_at.evaluations.total(), 40_000);
        assert_eq!(result.counters, vec![("round".to_string(), 25)]);
        assert!(!result.trace.is_empty());
        assert!(result.trace.windows(2).all(|w| w[1].rmse < w[0].rmse));
        assert_eq!(result.trace.last().unwrap().rmse, result.best_rmse);
    }
    let again = run_experiment(&spec, &out, &options(), &exec).unwrap();
    assert_eq!((again.new_trials, again.resumed), (0, 6));
    assert_eq!(again.records, first.records);

    let stored = brdf_experiment::store::read_results(&out).unwrap();
    assert_eq!(stored.header.fingerprint, spec.fingerprint());
    let report =
        brdf_analysis::report::write_report(&spec, &stored.records, &stored.sessions, &out, false)
            .unwrap();
    assert!(report.table.contains("PICKS"), "{}", report.table);
    let csv = std::fs::read_to_string(out.join("stats.csv")).unwrap();
    assert!(csv.contains("PICKS"), "{csv}");
}

#[test]
fn a_registered_algorithms_errors_name_its_keys() {
    register_once();
    let dir = tempfile::tempdir().unwrap();
    let zero = parse(&SPEC.replace("batch = 4", "batch = 0"), dir.path()).unwrap_err();
    let message = zero.to_string();
    assert!(message.contains("`batch` must be at least 1"), "{message}");
    let typo = parse(&SPEC.replace("batch = 4", "bach = 4"), dir.path()).unwrap_err();
    assert!(typo.to_string().contains("unknown field `bach`"), "{typo}");
    let unknown = parse(&SPEC.replace("test-random-picks", "nope"), dir.path()).unwrap_err();
    let message = unknown.to_string();
    assert!(message.contains("unknown `kind` `nope`"), "{message}");
    assert!(
        message.contains("aed, aers") && message.contains("test-random-picks"),
        "{message}"
    );
}
