//! Trials of the simulated-annealing algorithms on small BRDF instances: the standalone SA
//! (not in brdf_trials.rs's list because its paper defaults cannot reach the target), the
//! paper-tuned ASA, and the SA options.

use brdf_model::named_params;
use sls::{
    AlgorithmConfig, AsaConfig, Budget, Perturbation, SaConfig, SalsConfig, Search, Stop,
    StopReason, TrialContext, run_trial,
};
mod common;

use common::{assert_reproducible_within_budget, cpu, tuning};

/// A cool SA in the optimiser's coordinates, which can fit the easy instance.
fn cool_sa() -> AlgorithmConfig {
    AlgorithmConfig::new(SaConfig {
        t_start: 0.1,
        t_stop: 0.001,
        perturbation: Perturbation::Optimiser,
        ..SaConfig::default()
    })
}

fn variants() -> Vec<AlgorithmConfig> {
    vec![
        AlgorithmConfig::new(SaConfig::default()),
        cool_sa(),
        AlgorithmConfig::new(SaConfig {
            constant_acceptance: Some(0.1),
            ..SaConfig::default()
        }),
        AlgorithmConfig::new(AsaConfig::paper_tuned()),
        AlgorithmConfig::new(SalsConfig {
            descent_sample_size: 50,
            ..SalsConfig::default()
        }),
        AlgorithmConfig::new(SaConfig {
            sample_size: 100,
            ..SaConfig::default()
        }),
    ]
}

#[test]
fn subsample_rmse_is_charged_and_leaves_the_best_alone() {
    let objective = tuning(400, 0.0, 3);
    let truth = objective.layout().encode(named_params("tuning").unwrap());
    let mut ctx = TrialContext::new(&objective, 1, Budget::default(), 0.5);
    let mut off = truth.clone();
    off[0] += 0.05; // kd off by 0.05
    let a = ctx.evaluate_subsample(&off, 100).unwrap();
    let b = ctx.evaluate_subsample(&off, 100).unwrap();
    assert!(a > 0.0 && b > 0.0 && a != b, "{a} {b}"); // fresh draws
    // Exact at the (noiseless) truth, yet no target: subsample RMSEs never touch the best.
    assert!(ctx.evaluate_subsample(&truth, 100).unwrap() < 1e-9);
    assert_eq!(ctx.counts().rmse_rows, 300);
    assert!(ctx.best_rmse().is_infinite());
    // A subsample as large as the data set is the full-data evaluation.
    assert_eq!(ctx.evaluate_subsample(&truth, 400), Err(Stop::Target));
    assert_eq!(ctx.counts().rmse_rows, 700);
}

#[test]
fn asa_paper_tuned_and_subsampled_sals_reach_an_easy_target() {
    let objective = tuning(300, 0.0, 1);
    for config in [&variants()[3], &variants()[4]] {
        for seed in 1..=2 {
            let r = run_trial(&objective, config, seed, cpu(20.0), 0.01);
            assert_eq!(r.stop, StopReason::Target, "{config:?} seed {seed}: {r:?}");
        }
    }
}

#[test]
fn cool_sa_in_optimiser_coordinates_reaches_an_easy_target() {
    let objective = tuning(300, 0.0, 1);
    let r = run_trial(&objective, &cool_sa(), 2, cpu(20.0), 0.01);
    assert_eq!(r.stop, StopReason::Target, "{r:?}");
    // Every SA evaluation is a full-data RMSE.
    let c = r.ended_at.evaluations;
    assert_eq!(c.residual_rows + c.jacobian_rows, 0);
    assert_eq!(c.rmse_rows % 300, 0);
}

#[test]
fn variants_are_reproducible_respect_budgets_and_trace_monotonically() {
    let objective = tuning(500, 0.1, 2);
    for config in variants() {
        let a = assert_reproducible_within_budget(&objective, &config);
        assert!(a.trace.windows(2).all(|w| w[1].rmse < w[0].rmse));
        assert_eq!(a.trace.last().map(|p| p.rmse), Some(a.best_rmse));
        let cutoff = 0.05;
        let r = run_trial(&objective, &config, 1, cpu(cutoff), 0.0);
        assert_eq!(r.stop, StopReason::CpuBudget);
        let overshoot = r.ended_at.cpu_seconds - cutoff;
        assert!((0.0..0.01).contains(&overshoot), "{config:?}: {overshoot}");
    }
}

#[test]
fn nested_configurations_deserialise_and_validate() {
    let c: AlgorithmConfig = serde_json::from_str(
        r#"{"kind": "sals", "later": {"t_start": 0.02, "t_stop": 0.01, "perturbation": "optimiser"},
            "descent_sample_size": 100}"#,
    )
    .unwrap();
    let Some(s) = c.downcast_ref::<SalsConfig>() else {
        panic!("{c:?}")
    };
    assert_eq!(s.later.t_start, 0.02);
    assert_eq!(s.later.perturbation, Perturbation::Optimiser);
    // A schedule table given in a config replaces the whole schedule: its missing fields take
    // SaConfig's defaults, not SALS's default schedule.
    assert_eq!(s.later.temperatures, SaConfig::default().temperatures);
    assert_eq!(s.first, SalsConfig::default().first);
    assert!(c.validate().is_ok());
    // ... so a lone cool t_start is below the default t_stop (0.3) and is rejected.
    let bad: AlgorithmConfig =
        serde_json::from_str(r#"{"kind": "sals", "later": {"t_start": 0.001}}"#).unwrap();
    let e = bad.validate().unwrap_err();
    assert_eq!((e.algorithm, e.field), ("sals.later", "t_stop"));
    assert!(
        serde_json::from_str::<AlgorithmConfig>(r#"{"kind": "sa", "perturbation": "raw"}"#)
            .is_err()
    );
    assert!(serde_json::from_str::<AlgorithmConfig>(r#"{"kind": "asa", "quench": true}"#).is_err());
    for config in variants() {
        let json = serde_json::to_string(&config).unwrap();
        assert_eq!(
            serde_json::from_str::<AlgorithmConfig>(&json).unwrap(),
            config
        );
        assert!(config.validate().is_ok());
    }
    assert_eq!(
        AlgorithmConfig::default_for("sa"),
        Some(AlgorithmConfig::new(SaConfig::default()))
    );
}
