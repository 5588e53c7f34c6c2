//! The SA perturbation options measured against each other on the paper's tuning instance
//! (Table 2: one anisotropic lobe, 10000 samples, sigma 0.1, target 0.11): reached count,
//! time-to-target and the final (best) RMSE at a short CPU cutoff.
//!
//! ```text
//! cargo run --release -p sls --example anneal_bench -- [--seeds 10] [--cutoff 3] [--target 0.11]
//! ```
//! Trials run one after the other on one thread (trial seeds 1..=seeds); censored trials count
//! as +inf in the time percentiles.

use brdf_model::{Layout, LobeKind, named_params, synthetic};
use sls::{
    AlgorithmConfig, AsaConfig, AvgConfig, BrdfObjective, Budget, Perturbation, SaConfig,
    SalsConfig, run_trial,
};
use std::sync::Arc;

fn quantile(sorted: &[f64], q: f64) -> f64 {
    let i = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1;
    sorted[i]
}

fn with(c: &SaConfig, p: Perturbation) -> SaConfig {
    SaConfig {
        perturbation: p,
        ..c.clone()
    }
}

fn configs() -> Vec<(String, AlgorithmConfig)> {
    let mut out = Vec::new();
    let cool = SaConfig {
        t_start: 0.1,
        t_stop: 0.001,
        ..SaConfig::default()
    };
    for p in [Perturbation::Paper, Perturbation::Optimiser] {
        let tag = format!("{p:?}").to_lowercase();
        out.push((
            format!("sa default (1 -> 0.3), {tag}"),
            AlgorithmConfig::new(with(&SaConfig::default(), p)),
        ));
        out.push((
            format!("sa cool (0.1 -> 0.001), {tag}"),
            AlgorithmConfig::new(with(&cool, p)),
        ));
        let sals = SalsConfig::default();
        out.push((
            format!("sals default, {tag}"),
            AlgorithmConfig::new(SalsConfig {
                first: with(&sals.first, p),
                later: with(&sals.later, p),
                ..sals
            }),
        ));
        let avg = AvgConfig::default();
        out.push((
            format!("avg default, {tag}"),
            AlgorithmConfig::new(AvgConfig {
                sa: with(&avg.sa, p),
                ..avg
            }),
        ));
    }
    // SA steps judged on 500-sample subsample RMSEs (optimiser perturbation).
    let sub = |c: &SaConfig| SaConfig {
        sample_size: 500,
        perturbation: Perturbation::Optimiser,
        ..c.clone()
    };
    out.push((
        "sa cool (0.1 -> 0.001), optimiser, sub500".into(),
        AlgorithmConfig::new(sub(&cool)),
    ));
    let sals = SalsConfig::default();
    out.push((
        "sals default, optimiser, sub500".into(),
        AlgorithmConfig::new(SalsConfig {
            first: sub(&sals.first),
            later: sub(&sals.later),
            ..sals
        }),
    ));
    out.push((
        "asa default".into(),
        AlgorithmConfig::new(AsaConfig::default()),
    ));
    out.push((
        "asa paper-tuned".into(),
        AlgorithmConfig::new(AsaConfig::paper_tuned()),
    ));
    out
}

fn main() {
    let (mut seeds, mut cutoff, mut target) = (10u64, 3.0f64, 0.11f64);
    let mut only: Option<String> = None;
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().unwrap_or_default();
        let ok = match flag.as_str() {
            "--seeds" => value.parse().map(|v| seeds = v).is_ok(),
            "--cutoff" => value.parse().map(|v| cutoff = v).is_ok(),
            "--target" => value.parse().map(|v| target = v).is_ok(),
            "--only" => {
                only = Some(value.clone());
                true
            }
            _ => false,
        };
        if !ok {
            eprintln!("bad flag {flag} {value}");
            std::process::exit(2);
        }
    }
    let truth = named_params("tuning").expect("tuning is a named BRDF");
    let data = Arc::new(synthetic(&truth, 10000, 0.1, 1));
    let layout = Layout::builder(&[LobeKind::Anisotropic])
        .build()
        .expect("default layout");
    let objective = BrdfObjective::new(data, layout);
    let budget = Budget {
        cpu_seconds: Some(cutoff),
        sample_evaluations: None,
    };
    println!("cutoff {cutoff} CPU s, target {target}, seeds 1..={seeds}");
    println!(
        "| configuration | reached | median CPU s to target | median final RMSE | min final RMSE | max final RMSE |"
    );
    println!("|---|---|---|---|---|---|");
    for (name, config) in configs() {
        if only.as_ref().is_some_and(|o| !name.contains(o.as_str())) {
            continue;
        }
        let mut times = Vec::new();
        let mut finals = Vec::new();
        for seed in 1..=seeds {
            let r = run_trial(&objective, &config, seed, budget, target);
            times.push(r.reached_at.map_or(f64::INFINITY, |a| a.cpu_seconds));
            finals.push(r.best_rmse);
        }
        times.sort_by(f64::total_cmp);
        finals.sort_by(f64::total_cmp);
        let reached = times.iter().filter(|t| t.is_finite()).count();
        let median_time = quantile(&times, 0.5);
        println!(
            "| {name} | {reached}/{seeds} | {} | {:.4} | {:.4} | {:.4} |",
            if median_time.is_finite() {
                format!("{median_time:.3}")
            } else {
                "censored".into()
            },
            quantile(&finals, 0.5),
            finals[0],
            finals[finals.len() - 1],
        );
    }
}
