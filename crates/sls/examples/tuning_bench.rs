//! Time-to-target of AED, AERS and RPLS on the paper's tuning instance (Table 2: one
//! anisotropic lobe, 10000 samples, sigma 0.1, target 0.11), in CPU time and sample-evaluations.
//!
//! ```text
//! cargo run --release -p sls --example tuning_bench -- [--seeds 100] [--cutoff 10]
//!     [--algorithms aed,aers,rpls] [--k 10] [--instance-seed 1] [--target 0.11] [--verbose]
//!     [--raw-exponent] [--overshoot] [--instance tuning] [--sigma 0.1] [--no-early-exit]
//!     [--gauss-newton] [--adaptive-delay 2] [--no-secant-scaling] [--secant-delay 2]
//!     [--hold-dead-columns] [--singular-radius-at-least-x] [--stop-at-minimum-norm-step]
//!     [--scale-tiny-rotations]
//!     [--second-order-correction] [--scaling-decay 0.6]
//! ```
//! The descents use bounded-lm's default model, NL2SOL's adaptive choice switching only after
//! `--adaptive-delay K` secant updates per parameter (`bounded_lm::StepModel::Adaptive`,
//! default 2; 0 is N2FB's rule); `--gauss-newton` never uses the augmented model (the default
//! before 2026-12-02); `--no-secant-scaling` leaves the secant term out of the scaling and
//! `--secant-delay K` sets after how many secant updates per parameter it enters
//! (`bounded_lm::SecantScaling`; 0 is N2FB's rule).
//! `--hold-dead-columns` holds numerically dead variables in the descents, as the library's
//! default does (`bounded_lm::Safeguards::hold_dead_columns`; the searches leave them free).
//! `--singular-radius-at-least-x` makes the singular-convergence test step at least `||D x||`
//! long, as the library's default does (`bounded_lm::Safeguards::singular_radius_at_least_x`; the
//! searches use N2FB's LMAXS alone). `--stop-at-minimum-norm-step` ends the search for the
//! Levenberg parameter at a singular model's minimum-norm step, as the library's default does
//! (`bounded_lm::Safeguards::stop_at_minimum_norm_step`; the searches keep searching).
//! `--scale-tiny-rotations` scales a Givens rotation's tiny entries before squaring them, as the
//! library's default does (`bounded_lm::Safeguards::scale_tiny_rotations`; the searches keep
//! the plain rotation).
//! `--second-order-correction` corrects a rejected descent step once for the residuals'
//! curvature, as the library's default does (`bounded_lm::Safeguards::second_order_correction`;
//! the searches do not).
//! `--scaling-decay F` sets how fast the descents' scaling may fall
//! (`bounded_lm::Scaling::decay`; N2FB's 0.6 by default, 1 is MINPACK's rule).
//! `--no-early-exit` computes every full-data RMSE in full (the
//! trials' decisions are the same; only the computed rows and the CPU time differ).
//! `--k 3,5,10,20` sweeps the per-call iteration limit of AED and AERS, `--stall 0,25` their
//! stall limit (0: off, as in the paper). The annealing kinds `sa`, `sals`, `avg`, `asa` run with
//! their defaults, `asa-paper` with the paper's tuned ASA values, and `sa-opt`, `sals-opt`,
//! `avg-opt` with SA perturbations in the optimiser's coordinates. Trials run one after the
//! other on one thread (trial seeds 1..=seeds). Censored trials (cutoff reached) count as +inf in
//! the percentiles.

use brdf_model::{ExponentCoord, Layout, LobeKind, named_params, synthetic};
use sls::{
    AedConfig, AersConfig, AlgorithmConfig, AvgConfig, BrdfObjective, Budget, DescentLimits,
    DsConfig, Rows, RplsConfig, SaConfig, SalsConfig, Search, TrialContext, run_trial,
};
use std::sync::Arc;

struct Args {
    seeds: u64,
    cutoff: f64,
    algorithms: Vec<String>,
    ks: Vec<usize>,
    stalls: Vec<usize>,
    instance_seed: u64,
    target: f64,
    verbose: bool,
    overshoot: bool,
    raw_exponent: bool,
    instance: String,
    sigma: f64,
    early_exit: bool,
    gauss_newton: bool,
    secant_scaling: bool,
    secant_delay: usize,
    adaptive_delay: usize,
    hold_dead_columns: bool,
    singular_radius_at_least_x: bool,
    stop_at_minimum_norm_step: bool,
    scale_tiny_rotations: bool,
    second_order_correction: bool,
    scaling_decay: f64,
}

fn parse() -> Result<Args, String> {
    let search = sls::DescentModel::default().options();
    let secant_delay = match search.scaling.secant {
        bounded_lm::SecantScaling::After { delay } => Some(delay),
        bounded_lm::SecantScaling::Off => None,
    };
    let adaptive_delay = match search.model {
        bounded_lm::StepModel::Adaptive { delay } => delay,
        bounded_lm::StepModel::GaussNewton => 0,
    };
    let mut a = Args {
        seeds: 100,
        cutoff: 10.0,
        algorithms: vec!["aed".into(), "aers".into(), "rpls".into()],
        ks: vec![sls::algorithms::aed::DEFAULT_DESCENT_ITERATIONS],
        stalls: vec![sls::algorithms::aed::DEFAULT_STALL_LIMIT],
        instance_seed: 1,
        target: 0.11,
        verbose: false,
        overshoot: false,
        raw_exponent: false,
        instance: "tuning".into(),
        sigma: 0.1,
        early_exit: true,
        gauss_newton: false,
        secant_scaling: secant_delay.is_some(),
        secant_delay: secant_delay.unwrap_or(0),
        adaptive_delay,
        hold_dead_columns: search.safeguards.hold_dead_columns,
        singular_radius_at_least_x: search.safeguards.singular_radius_at_least_x,
        stop_at_minimum_norm_step: search.safeguards.stop_at_minimum_norm_step,
        scale_tiny_rotations: search.safeguards.scale_tiny_rotations,
        second_order_correction: search.safeguards.second_order_correction,
        scaling_decay: search.scaling.decay,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        // Switches take no value: each sets one field.
        let switch = match flag.as_str() {
            "--raw-exponent" => Some((&mut a.raw_exponent, true)),
            "--overshoot" => Some((&mut a.overshoot, true)),
            "--gauss-newton" => Some((&mut a.gauss_newton, true)),
            "--hold-dead-columns" => Some((&mut a.hold_dead_columns, true)),
            "--singular-radius-at-least-x" => Some((&mut a.singular_radius_at_least_x, true)),
            "--stop-at-minimum-norm-step" => Some((&mut a.stop_at_minimum_norm_step, true)),
            "--scale-tiny-rotations" => Some((&mut a.scale_tiny_rotations, true)),
            "--second-order-correction" => Some((&mut a.second_order_correction, true)),
            "--no-secant-scaling" => Some((&mut a.secant_scaling, false)),
            "--no-early-exit" => Some((&mut a.early_exit, false)),
            "--verbose" => Some((&mut a.verbose, true)),
            _ => None,
        };
        if let Some((field, value)) = switch {
            *field = value;
            continue;
        }
        let value = it.next().ok_or(format!("{flag} needs a value"))?;
        let bad = |e: &dyn std::fmt::Display| format!("{flag} {value}: {e}");
        match flag.as_str() {
            "--seeds" => a.seeds = value.parse().map_err(|e| bad(&e))?,
            "--secant-delay" => a.secant_delay = value.parse().map_err(|e| bad(&e))?,
            "--adaptive-delay" => a.adaptive_delay = value.parse().map_err(|e| bad(&e))?,
            "--scaling-decay" => a.scaling_decay = value.parse().map_err(|e| bad(&e))?,
            "--cutoff" => a.cutoff = value.parse().map_err(|e| bad(&e))?,
            "--instance-seed" => a.instance_seed = value.parse().map_err(|e| bad(&e))?,
            "--target" => a.target = value.parse().map_err(|e| bad(&e))?,
            "--sigma" => a.sigma = value.parse().map_err(|e| bad(&e))?,
            "--instance" => a.instance = value.clone(),
            "--algorithms" => a.algorithms = value.split(',').map(String::from).collect(),
            "--k" => {
                a.ks = value
                    .split(',')
                    .map(|s| s.parse().map_err(|e| bad(&e)))
                    .collect::<Result<_, _>>()?
            }
            "--stall" => {
                a.stalls = value
                    .split(',')
                    .map(|s| s.parse().map_err(|e| bad(&e)))
                    .collect::<Result<_, _>>()?
            }
            _ => return Err(format!("unknown flag {flag}")),
        }
    }
    Ok(a)
}

/// The q-quantile (nearest rank) of sorted values.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let i = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1;
    sorted[i]
}

fn fmt_evals(v: f64) -> String {
    if v.is_finite() {
        format!("{:.0}", v)
    } else {
        "censored".into()
    }
}

fn fmt_ms(v: f64) -> String {
    if v.is_finite() {
        format!("{:.2}", v * 1e3)
    } else {
        "censored".into()
    }
}

fn main() {
    let args = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let Some(truth) = named_params(&args.instance) else {
        eprintln!("unknown BRDF {}", args.instance);
        std::process::exit(2);
    };
    let data = Arc::new(synthetic(&truth, 10000, args.sigma, args.instance_seed));
    let kinds = vec![LobeKind::Anisotropic; truth.lobes.len()];
    let coord = if args.raw_exponent {
        ExponentCoord::Raw
    } else {
        ExponentCoord::Log1p
    };
    let layout = Layout::builder(&kinds)
        .exponent_coord(coord)
        .build()
        .expect("default layout");
    let objective = BrdfObjective::new(data, layout);

    // The instance's optimum, as far as a descent from the true parameters finds it.
    let x_true = objective.layout().encode(&truth);
    let mut ctx = TrialContext::new(&objective, 0, Budget::default(), 0.0);
    let rmse_true = ctx.evaluate(&x_true).unwrap_or(f64::NAN);
    let mut x = x_true.clone();
    let descent = ctx.descend(&mut x, Rows::Full, DescentLimits::default());
    let rmse_opt = ctx.evaluate(&x).unwrap_or(f64::NAN);
    println!(
        "instance: {}, 10000 samples, sigma {}, instance seed {}, exponent coordinate \
         {coord:?}; RMSE at the true parameters {rmse_true:.6}; after a full-data descent from \
         them {rmse_opt:.6} ({:?}); target {}",
        args.instance,
        args.sigma,
        args.instance_seed,
        descent.map(|d| d.end),
        args.target
    );
    println!("fitted: {:?}", objective.layout().decode(&x));

    if args.overshoot {
        measure_overshoot(&objective, &args);
        return;
    }

    let budget = Budget {
        cpu_seconds: Some(args.cutoff),
        sample_evaluations: None,
    };
    println!(
        "| algorithm | K | stall limit | reached | median evals | p90 evals | median CPU ms | p90 CPU ms | mean CPU ms/trial (all) | computed/paper evals | ns per computed sample-evaluation (all) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for name in &args.algorithms {
        let variants: Vec<Option<(usize, usize)>> = if name != "aed" && name != "aers" {
            vec![None]
        } else {
            args.ks
                .iter()
                .flat_map(|&k| args.stalls.iter().map(move |&st| Some((k, st))))
                .collect()
        };
        for variant in variants {
            let config = match (name.as_str(), variant) {
                ("aed", Some((k, stall))) => AlgorithmConfig::new(AedConfig {
                    descent_iterations: k,
                    stall_limit: stall,
                    ..AedConfig::default()
                }),
                ("aers", Some((k, stall))) => AlgorithmConfig::new(AersConfig {
                    descent_iterations: k,
                    stall_limit: stall,
                    ..AersConfig::default()
                }),
                ("rpls", _) => AlgorithmConfig::new(RplsConfig::default()),
                ("ds", _) => AlgorithmConfig::new(DsConfig::default()),
                // The annealing kinds with their defaults; `asa-paper`: the paper's tuned ASA;
                // `*-opt`: SA perturbations scaled in the optimiser's coordinates.
                ("asa-paper", _) => AlgorithmConfig::new(sls::AsaConfig::paper_tuned()),
                (kind, _) if kind.ends_with("-opt") => match kind.trim_end_matches("-opt") {
                    "sa" => AlgorithmConfig::new(opt(SaConfig::default())),
                    "avg" => {
                        let mut c = AvgConfig::default();
                        c.sa = opt(c.sa);
                        AlgorithmConfig::new(c)
                    }
                    "sals" => {
                        let mut c = SalsConfig::default();
                        c.first = opt(c.first);
                        c.later = opt(c.later);
                        AlgorithmConfig::new(c)
                    }
                    _ => {
                        eprintln!("unknown algorithm {name}");
                        std::process::exit(2);
                    }
                },
                (kind @ ("sa" | "sals" | "avg" | "asa"), _) => {
                    AlgorithmConfig::default_for(kind).expect("annealing kinds have defaults")
                }
                _ => {
                    eprintln!("unknown algorithm {name}");
                    std::process::exit(2);
                }
            };
            let mut evals = Vec::new();
            let mut cpu = Vec::new();
            let mut cpu_all = 0.0;
            let (mut computed, mut paper) = (0.0, 0.0);
            let mut reached = 0;
            for seed in 1..=args.seeds {
                let mut ctx = TrialContext::new(&objective, seed, budget, args.target);
                ctx.set_early_exit(args.early_exit);
                if args.gauss_newton {
                    ctx.set_step_model(bounded_lm::StepModel::GaussNewton);
                }
                ctx.set_secant_scaling(args.secant_scaling, args.secant_delay);
                ctx.set_adaptive_delay(args.adaptive_delay);
                ctx.set_hold_dead_columns(args.hold_dead_columns);
                ctx.set_singular_radius_at_least_x(args.singular_radius_at_least_x);
                ctx.set_stop_at_minimum_norm_step(args.stop_at_minimum_norm_step);
                ctx.set_scale_tiny_rotations(args.scale_tiny_rotations);
                ctx.set_second_order_correction(args.second_order_correction);
                ctx.set_scaling_decay(args.scaling_decay);
                let end = config.run(&mut ctx);
                let r = ctx.finish(end);
                cpu_all += r.ended_at.cpu_seconds;
                computed += r.ended_at.evaluations.total_computed() as f64;
                paper += r.ended_at.evaluations.total() as f64;
                match r.reached_at {
                    Some(at) => {
                        reached += 1;
                        evals.push(at.evaluations.total() as f64);
                        cpu.push(at.cpu_seconds);
                    }
                    None => {
                        if args.verbose {
                            eprintln!(
                                "censored: {name} seed {seed} best {:.5} at {:?} counters {:?}",
                                r.best_rmse,
                                objective.layout().decode(&r.best_x),
                                r.counters
                            );
                        }
                        evals.push(f64::INFINITY);
                        cpu.push(f64::INFINITY);
                    }
                }
            }
            evals.sort_by(f64::total_cmp);
            cpu.sort_by(f64::total_cmp);
            println!(
                "| {name} | {} | {} | {reached}/{} | {} | {} | {} | {} | {:.2} | {:.3} | {:.2} |",
                variant.map_or("-".to_string(), |(k, _)| k.to_string()),
                variant.map_or("-".to_string(), |(_, s)| s.to_string()),
                args.seeds,
                fmt_evals(quantile(&evals, 0.5)),
                fmt_evals(quantile(&evals, 0.9)),
                fmt_ms(quantile(&cpu, 0.5)),
                fmt_ms(quantile(&cpu, 0.9)),
                cpu_all * 1e3 / args.seeds as f64,
                computed / paper,
                cpu_all * 1e9 / computed,
            );
        }
    }
}

/// CPU-cutoff overshoot of trials that cannot reach their target.
fn measure_overshoot(objective: &BrdfObjective, args: &Args) {
    let budget = Budget {
        cpu_seconds: Some(args.cutoff),
        sample_evaluations: None,
    };
    println!("| algorithm | trials | cutoff s | median overshoot us | max overshoot us |");
    println!("|---|---|---|---|---|");
    for kind in ["aed", "aers", "rpls", "ds"] {
        let config = AlgorithmConfig::default_for(kind).expect("known kind");
        let mut over: Vec<f64> = (1..=args.seeds)
            .map(|seed| {
                let r = run_trial(objective, &config, seed, budget, 0.0);
                r.ended_at.cpu_seconds - args.cutoff
            })
            .collect();
        over.sort_by(f64::total_cmp);
        println!(
            "| {kind} | {} | {} | {:.1} | {:.1} |",
            args.seeds,
            args.cutoff,
            quantile(&over, 0.5) * 1e6,
            over[over.len() - 1] * 1e6
        );
    }
}

/// An SA schedule with the perturbation scaled in the optimiser's coordinates.
fn opt(c: sls::SaConfig) -> sls::SaConfig {
    sls::SaConfig {
        perturbation: sls::Perturbation::Optimiser,
        ..c
    }
}
