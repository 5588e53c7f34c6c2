//! NIST StRD with larger budgets (`cargo run -p bounded-lm --release --example nist_budget -- 5000`):
//! prints the number correct for both step models, the failures and the runs needing more than
//! 100 iterations.

#[path = "../tests/common/nist.rs"]
mod nist;

use bounded_lm::{Options, StepModel};

fn main() {
    let budget: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5000);
    for model in [StepModel::GaussNewton, StepModel::Adaptive { delay: 2 }] {
        let mut options = Options::default().with_limits(budget, budget);
        options.model = model;
        let runs = nist::run_all(&options);
        let correct = runs.iter().filter(|r| r.correct()).count();
        println!("{model:?} budget {budget}: {correct}/54");
        for r in runs
            .iter()
            .filter(|r| !r.correct() || r.report.iterations > 100)
        {
            println!(
                "  {} start {}: LRE {:.1} {:?} it {} fev {}",
                r.name,
                r.start,
                r.min_lre,
                r.report.outcome,
                r.report.iterations,
                r.report.residual_evaluations
            );
        }
    }
}
