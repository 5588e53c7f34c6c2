//! Runs the NIST StRD suite with both step models (and the Gauss-Newton model with the classic
//! radius rule, without the secant term in the scaling, with MINPACK's non-decreasing scaling,
//! without the second-order correction, and N2FB's configuration, which has none) and writes
//! the per-problem table to `results/lm/nist.md` (workspace root). Regenerate with
//! `cargo run -p bounded-lm --release --example nist_table [-- OUT.md]`.

#[path = "../tests/common/nist.rs"]
mod nist;

use bounded_lm::{Options, RadiusUpdate, StepModel};
use std::fmt::Write as _;

fn main() {
    let mut out = String::new();
    let mut totals = Vec::new();
    let defaults = Options::default();
    let mut tables = String::new();
    // The adaptive rows switch models from the first secant update (N2FB's rule); the default
    // (first row) only after `adaptive_delay` updates per parameter.
    let with = |model, radius_update, secant_scaling| Options {
        model,
        radius_update,
        secant_scaling,
        adaptive_delay: 0,
        ..Options::default()
    };
    let configs = [
        Options::default(),
        Options {
            second_order_correction: false,
            ..Options::default()
        },
        Options {
            scaling_decay: 1.0,
            ..Options::default()
        },
        with(StepModel::GaussNewton, defaults.radius_update, true),
        with(StepModel::Adaptive, defaults.radius_update, true),
        with(StepModel::GaussNewton, RadiusUpdate::Classic, true),
        with(StepModel::GaussNewton, defaults.radius_update, false),
        with(StepModel::Adaptive, defaults.radius_update, false),
        Options::n2fb(),
    ];
    for options in configs {
        let (model, radius_update, secant_scaling) =
            (options.model, options.radius_update, options.secant_scaling);
        let switch = if model == StepModel::Adaptive && options.adaptive_delay > 0 {
            format!(" from {} updates per parameter", options.adaptive_delay)
        } else {
            String::new()
        };
        let decay = if options.scaling_decay == defaults.scaling_decay {
            String::new()
        } else {
            format!(", scaling decay {} (MINPACK's)", options.scaling_decay)
        };
        let correction = if options.second_order_correction {
            ""
        } else {
            ", no second-order correction"
        };
        let label = format!(
            "{model:?}{switch}, {radius_update:?} radius{decay}{correction}, {}",
            if !secant_scaling {
                "no secant scaling".to_string()
            } else if options.secant_scaling_delay == 0 {
                "secant scaling at once (N2FB)".to_string()
            } else {
                format!(
                    "secant scaling after {} updates per parameter",
                    options.secant_scaling_delay
                )
            }
        );
        let runs = nist::run_all(&options);
        let correct = runs.iter().filter(|r| r.correct()).count();
        let wrong_success = runs
            .iter()
            .filter(|r| r.report.outcome.is_success() && !r.correct())
            .count();
        let fev: usize = runs.iter().map(|r| r.report.residual_evaluations).sum();
        let jev: usize = runs.iter().map(|r| r.report.jacobian_evaluations).sum();
        let its: usize = runs.iter().map(|r| r.report.iterations).sum();
        let fev_ok: usize = runs
            .iter()
            .filter(|r| r.correct())
            .map(|r| r.report.residual_evaluations)
            .sum();
        totals.push((label.clone(), correct, wrong_success, fev, jev, its, fev_ok));
        let _ = writeln!(
            tables,
            "\n## {label}{}\n",
            if options == defaults {
                " (default)"
            } else {
                ""
            }
        );
        let _ = writeln!(
            tables,
            "| problem | start | min LRE | RSS LRE | outcome (code) | iterations | residual evals | Jacobian evals |"
        );
        let _ = writeln!(tables, "|---|---|---|---|---|---|---|---|");
        for r in &runs {
            let _ = writeln!(
                tables,
                "| {} | {} | {:.1} | {:.1} | {:?} ({}) | {} | {} | {} |",
                r.name,
                r.start,
                r.min_lre,
                r.rss_lre,
                r.report.outcome,
                r.report.outcome.code(),
                r.report.iterations,
                r.report.residual_evaluations,
                r.report.jacobian_evaluations
            );
        }
    }
    let _ = writeln!(
        out,
        "# bounded-lm on NIST StRD nonlinear regression (27 problems x 2 starts)\n"
    );
    let _ = writeln!(
        out,
        "Default budgets (150 iterations, 200 residual evaluations), analytic Jacobians, no bounds."
    );
    let _ = writeln!(
        out,
        "Correct = LRE >= 4 in every parameter (LRE capped at 11; the exchangeable terms of MGH17,\n\
         Lanczos, Gauss and ENSO may come in any order). Generated by"
    );
    let _ = writeln!(
        out,
        "`cargo run -p bounded-lm --release --example nist_table`. PORT N2FB reference: 46/54.\n"
    );
    let _ = writeln!(
        out,
        "| configuration | correct | success code on a wrong answer | iterations | residual evals | Jacobian evals | residual evals (correct runs) |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|");
    for (model, correct, wrong, fev, jev, its, fev_ok) in &totals {
        let _ = writeln!(
            out,
            "| {model} | {correct}/54 | {wrong} | {its} | {fev} | {jev} | {fev_ok} |"
        );
        println!(
            "{model}: {correct}/54 correct, {wrong} success codes on wrong answers, {its} iterations, {fev} residual evals, {jev} Jacobian evals"
        );
    }
    out.push_str(&tables);
    // An optional argument writes the table elsewhere.
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| format!("{}/../../results/lm/nist.md", env!("CARGO_MANIFEST_DIR")));
    if let Some(dir) = std::path::Path::new(&path).parent() {
        std::fs::create_dir_all(dir).expect("results dir");
    }
    std::fs::write(&path, out).expect("write results/lm/nist.md");
    println!("wrote {path}");
}
