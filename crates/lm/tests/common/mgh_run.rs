//! Runs the MGH collection (unbounded and boxed, from x0 and 10 x0) and formats the table.
//! Shared by tests/mgh.rs and examples/mgh_table.rs.

#![allow(dead_code, clippy::needless_range_loop)]

use bounded_lm::problems::mgh::{self, Mgh};
use bounded_lm::{Options, Outcome, Problem, Report, Solver};

/// One solve.
#[derive(Clone, Debug)]
pub struct MghRun {
    pub label: String,
    pub factor: f64,
    /// `None` unbounded, else the bound's description.
    pub bound: Option<String>,
    pub report: Report,
    pub f_star: Option<f64>,
    /// Unbounded: reached a listed minimum. Boxed: the projected gradient is small (KKT).
    pub solved: bool,
    /// The bound is active at the end (boxed runs).
    pub bound_active: bool,
}

impl MghRun {
    /// A success code on an answer that is not a minimum.
    pub fn wrong_success(&self) -> bool {
        self.report.outcome.is_success() && !self.solved
    }

    /// The right answer reported with a success code (3 to 6); a right answer with code 7
    /// (singular convergence) does not say that it converged to a minimum.
    pub fn solved_with_success(&self) -> bool {
        self.solved && self.report.outcome.is_success()
    }
}

fn gradient(prob: &mut Mgh, x: &[f64]) -> Vec<f64> {
    let (m, n) = (prob.residual_count(), prob.parameter_count());
    let mut r = vec![0.0; m];
    let mut j = vec![0.0; m * n];
    prob.residuals(x, &mut r);
    prob.jacobian(x, &mut j);
    (0..n)
        .map(|k| (0..m).map(|i| j[k * m + i] * r[i]).sum())
        .collect()
}

/// Projected gradient norm (components pushing out of the box at an active bound dropped).
fn projected_gradient_norm(prob: &mut Mgh, x: &[f64], lo: &[f64], hi: &[f64]) -> f64 {
    let g = gradient(prob, x);
    let mut s = 0.0;
    for k in 0..x.len() {
        let held = (x[k] <= lo[k] && g[k] > 0.0) || (x[k] >= hi[k] && g[k] < 0.0);
        if !held {
            s += g[k] * g[k];
        }
    }
    s.sqrt()
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Runs every problem of [`mgh::all`] from `x0` and `10 x0`, unbounded and in the box from
/// [`Mgh::cutting_box`] around the minimiser reached from `x0` with a budget of 5000.
pub fn run_all(options: &Options) -> Vec<MghRun> {
    let mut solver = Solver::new();
    let mut out = Vec::new();
    for mut prob in mgh::all() {
        let n = prob.parameter_count();
        let free = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
        // The minimiser that defines the box.
        let big = mgh::box_reference_options();
        let mut x_star = prob.start(1.0);
        let _ = solver.solve(&mut prob, &mut x_star, &free.0, &free.1, &big);
        let bounds = prob.cutting_box(&x_star);
        let f_star = prob.f_minima().first().copied();
        for factor in [1.0, 10.0] {
            let mut x = prob.start(factor);
            let report = solver
                .solve(&mut prob, &mut x, &free.0, &free.1, options)
                .expect("solve");
            out.push(MghRun {
                label: prob.label(),
                factor,
                bound: None,
                report,
                f_star,
                solved: prob.reaches_minimum(report.f),
                bound_active: false,
            });
            let mut x = prob.start(factor);
            let x0 = x.clone();
            let g0 = {
                let mut xp = x0.clone();
                for k in 0..n {
                    xp[k] = xp[k].clamp(bounds.lower[k], bounds.upper[k]);
                }
                projected_gradient_norm(&mut prob, &xp, &bounds.lower, &bounds.upper)
                    .max(norm(&gradient(&mut prob, &xp)))
            };
            let report = solver
                .solve(&mut prob, &mut x, &bounds.lower, &bounds.upper, options)
                .expect("solve");
            let pg = projected_gradient_norm(&mut prob, &x, &bounds.lower, &bounds.upper);
            let j = bounds.index;
            out.push(MghRun {
                label: prob.label(),
                factor,
                bound: Some(bounds.describe()),
                report,
                f_star: None,
                solved: pg <= 1e-6 * g0.max(1e-300) || pg <= 1e-10,
                bound_active: x[j] == bounds.value,
            });
        }
    }
    out
}

/// The markdown table.
pub fn table(runs: &[MghRun]) -> String {
    let mut s = String::from(
        "| problem | start | bounds | outcome (code) | iterations | residual evals | final f | f* | solved |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in runs {
        s.push_str(&format!(
            "| {} | {}x0 | {} | {:?} ({}) | {} | {} | {:.6e} | {} | {} |\n",
            r.label,
            r.factor,
            match &r.bound {
                None => "none".to_string(),
                Some(b) => format!(
                    "{b}{}",
                    if r.bound_active {
                        " (active)"
                    } else {
                        " (inactive)"
                    }
                ),
            },
            r.report.outcome,
            r.report.outcome.code(),
            r.report.iterations,
            r.report.residual_evaluations,
            r.report.f,
            r.f_star.map_or("-".to_string(), |v| format!("{v:.6e}")),
            if r.solved { "yes" } else { "no" },
        ));
    }
    s
}

/// (solved, total) over the unbounded runs, the boxed runs, and success codes on wrong answers.
pub fn summary(runs: &[MghRun]) -> String {
    let unb: Vec<&MghRun> = runs.iter().filter(|r| r.bound.is_none()).collect();
    let bnd: Vec<&MghRun> = runs.iter().filter(|r| r.bound.is_some()).collect();
    let solved = |v: &[&MghRun]| v.iter().filter(|r| r.solved).count();
    let solved_success = |v: &[&MghRun]| v.iter().filter(|r| r.solved_with_success()).count();
    let honest = |v: &[&MghRun]| {
        v.iter()
            .filter(|r| r.solved || !r.report.outcome.is_success())
            .count()
    };
    let its = |v: &[&MghRun]| v.iter().map(|r| r.report.iterations).sum::<usize>();
    let fev = |v: &[&MghRun]| {
        v.iter()
            .map(|r| r.report.residual_evaluations)
            .sum::<usize>()
    };
    format!(
        "unbounded: {}/{} solved to a listed minimum ({}/{} with a success code), {} success codes on a wrong answer, {} iterations, {} residual evals\n\
         boxed: {}/{} solved (KKT), {}/{} solved or an honest failure code, bound active in {}, {} iterations, {} residual evals\n",
        solved(&unb),
        unb.len(),
        solved_success(&unb),
        unb.len(),
        unb.len() - honest(&unb),
        its(&unb),
        fev(&unb),
        solved(&bnd),
        bnd.len(),
        honest(&bnd),
        bnd.len(),
        bnd.iter().filter(|r| r.bound_active).count(),
        its(&bnd),
        fev(&bnd),
    )
}

pub fn outcome_of(runs: &[MghRun], label_prefix: &str, factor: f64) -> Option<(Outcome, Report)> {
    runs.iter()
        .find(|r| r.bound.is_none() && r.label.starts_with(label_prefix) && r.factor == factor)
        .map(|r| (r.report.outcome, r.report))
}
