//! Trials of the simulated-annealing algorithms (SA, SALS, AVG, ASA) on small BRDF instances.

use brdf_model::{Layout, LobeKind, named_params, synthetic};
use sls::{
    AlgorithmConfig, AsaConfig, AvgConfig, BrdfObjective, Budget, Perturbation, SaConfig,
    SalsConfig, StopReason, run_trial,
};
use std::sync::Arc;

/// The tuning BRDF (Table 2) sampled `n` times with noise `sigma`.
fn tuning(n: usize, sigma: f64, seed: u64) -> BrdfObjective {
    let data = synthetic(&named_params("tuning").unwrap(), n, sigma, seed);
    let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
    BrdfObjective::new(Arc::new(data), layout)
}

fn cpu(seconds: f64) -> Budget {
    Budget {
        cpu_seconds: Some(seconds),
        sample_evaluations: None,
    }
}

#[test]
fn probe() {
    let objective = tuning(300, 0.0, 1);
    let configs = vec![
        AlgorithmConfig::Sals(SalsConfig::default()),
        AlgorithmConfig::Avg(AvgConfig::default()),
        AlgorithmConfig::Asa(AsaConfig::default()),
        AlgorithmConfig::Asa(AsaConfig::paper_tuned()),
        AlgorithmConfig::Sa(SaConfig::default()),
        AlgorithmConfig::Sa(SaConfig { perturbation: Perturbation::Optimiser, t_start: 0.1, t_stop: 0.001, ..SaConfig::default() }),
    ];
    for config in configs {
        for seed in 1..=3 {
            let r = run_trial(&objective, &config, seed, cpu(5.0), 0.01);
            eprintln!("{} seed {seed}: {:?} best {:.4} cpu {:.3} evals {} counters {:?}", config.kind_name(), r.stop, r.best_rmse, r.ended_at.cpu_seconds, r.ended_at.evaluations.total(), r.counters);
        }
    }
    let _ = StopReason::Target;
}
