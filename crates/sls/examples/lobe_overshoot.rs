//! CPU-cutoff overshoot with many lobes: fits the tuning BRDF (10000 samples) with a model of
//! `L` anisotropic lobes under a tiny CPU cutoff and an unreachable target, and prints the
//! trials' CPU time as a multiple of the cutoff.
//!
//! ```text
//! cargo run --release -p sls --example lobe_overshoot -- [--lobes 8,16,50] [--cutoff 0.05]
//!     [--seeds 5] [--algorithms aed,rpls]
//! ```

use brdf_model::{Layout, LobeKind, named_params, synthetic};
use sls::{AlgorithmConfig, BrdfObjective, Budget, run_trial};
use std::sync::Arc;

fn main() {
    let mut lobes = vec![8usize, 16, 50];
    let mut cutoff = 0.05;
    let mut seeds = 5u64;
    let mut algorithms = vec!["aed".to_string(), "rpls".to_string()];
    let args: Vec<String> = std::env::args().skip(1).collect();
    for pair in args.chunks(2) {
        let v = pair.get(1).cloned().unwrap_or_default();
        match pair[0].as_str() {
            "--lobes" => lobes = v.split(',').map(|s| s.parse().expect("lobes")).collect(),
            "--cutoff" => cutoff = v.parse().expect("cutoff"),
            "--seeds" => seeds = v.parse().expect("seeds"),
            "--algorithms" => algorithms = v.split(',').map(String::from).collect(),
            f => panic!("unknown flag {f}"),
        }
    }
    let data = Arc::new(synthetic(&named_params("tuning").unwrap(), 10000, 0.1, 1));
    let budget = Budget {
        cpu_seconds: Some(cutoff),
        sample_evaluations: None,
    };
    println!("| algorithm | lobes | trials | cutoff s | median CPU / cutoff | max CPU / cutoff |");
    println!("|---|---|---|---|---|---|");
    for name in &algorithms {
        let config = AlgorithmConfig::default_for(name).expect("known algorithm");
        for &l in &lobes {
            let layout = Layout::builder(&vec![LobeKind::Anisotropic; l])
                .build()
                .unwrap();
            let objective = BrdfObjective::new(data.clone(), layout);
            let mut ratio: Vec<f64> = (1..=seeds)
                .map(|seed| {
                    run_trial(&objective, &config, seed, budget, 0.0)
                        .ended_at
                        .cpu_seconds
                        / cutoff
                })
                .collect();
            ratio.sort_by(f64::total_cmp);
            println!(
                "| {name} | {l} | {seeds} | {cutoff} | {:.2} | {:.2} |",
                ratio[ratio.len() / 2],
                ratio[ratio.len() - 1]
            );
        }
    }
}
