//! Runs the NIST StRD suite with both step models (and the Gauss-Newton model with the classic
//! radius rule, without the secant term in the scaling, with MINPACK's non-decreasing scaling,
//! without the second-order correction, and N2FB's configuration, which has none) and writes
//! the per-problem table to `results/lm/nist.md` (workspace root). Regenerate with
//! `cargo run -p bounded-lm --release --example nist_table [-- OUT.md]`.

#[path = "../tests/common/nist.rs"]
mod nist;

use bounded_lm::{Options, RadiusUpdate, SecantScaling, StepModel};
use std::fmt::Write as _;

fn main() {
    let mut out = String::new();
    let mut totals = Vec::new();
    let defaults = Options::default();
    let mut tables = String::new();
    // The adaptive rows switch models from the first secant update (N2FB's rule); the default
    // (first row) only after its delay.
    let with = |model, update, secant| {
        let mut options = Options {
            model,
            ..Options::default()
        };
        options.radius.update = update;
        options.scaling.secant = secant;
        options
    };
    let mut no_correction = Options::default();
    no_correction.safeguards.second_order_correction = false;
    let mut minpack = Options::default();
    minpack.scaling.decay = 1.0;
    let (gn, adaptive) = (StepModel::GaussNewton, StepModel::N2FB);
    let (nl2sol, secant) = (defaults.radius.update, defaults.scaling.secant);
    let configs = [
        Options::default(),
        no_correction,
        minpack,
        with(gn, nl2sol, secant),
        with(adaptive, nl2sol, secant),
        with(gn, RadiusUpdate::Classic, secant),
        with(gn, nl2sol, SecantScaling::Off),
        with(adaptive, nl2sol, SecantScaling::Off),
        Options::n2fb(),
    ];
    for options in configs {
        let radius_update = options.radius.update;
        let (model, switch) = match options.model {
            StepModel::GaussNewton => ("GaussNewton", String::new()),
            StepModel::Adaptive { delay: 0 } => ("Adaptive", String::new()),
            StepModel::Adaptive { delay } => {
                ("Adaptive", format!(" from {delay} updates per parameter"))
            }
        };
        let decay = if options.scaling.decay == defaults.scaling.decay {
            String::new()
        } else {
            format!(", scaling decay {} (MINPACK's)", options.scaling.decay)
        };
        let correction = if options.safeguards.second_order_correction {
            ""
        } else {
            ", no second-order correction"
        };
        let label = format!(
            "{model}{switch}, {radius_update:?} radius{decay}{correction}, {}",
            match options.scaling.secant {
                SecantScaling::Off => "no secant scaling".to_string(),
                SecantScaling::After { delay: 0 } => "secant scaling at once (N2FB)".to_string(),
                SecantScaling::After { delay } => {
                    format!("secant scaling after {delay} updates per parameter")
                }
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
