//! Instances, budgets and checks shared by the integration tests.

use brdf_model::{Layout, LobeKind, named_params, synthetic};
use sls::{AlgorithmConfig, BrdfObjective, Budget, StopReason, TrialResult, run_trial};
use std::sync::Arc;

/// The tuning BRDF (Table 2) sampled `n` times with noise `sigma`.
pub fn tuning(n: usize, sigma: f64, seed: u64) -> BrdfObjective {
    let data = synthetic(&named_params("tuning").unwrap(), n, sigma, seed);
    let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
    BrdfObjective::new(Arc::new(data), layout)
}

/// A CPU-time budget.
pub fn cpu(seconds: f64) -> Budget {
    Budget {
        cpu_seconds: Some(seconds),
        sample_evaluations: None,
    }
}

/// The same seed gives the same trial bit for bit (clocks aside), another seed a different
/// trace, and an evaluation budget of 300,000 is never overshot. Returns the seed-3 trial.
pub fn assert_reproducible_within_budget(
    objective: &BrdfObjective,
    config: &AlgorithmConfig,
) -> TrialResult {
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(300_000),
    };
    let run = |seed| run_trial(objective, config, seed, budget, 0.0).without_clock();
    let (a, b, c) = (run(3), run(3), run(4));
    assert_eq!(a, b, "{config:?}");
    assert_ne!(a.trace, c.trace, "{config:?}");
    assert_eq!(a.stop, StopReason::EvaluationBudget, "{config:?}");
    assert!(a.ended_at.evaluations.total() <= 300_000, "{config:?}");
    a
}
