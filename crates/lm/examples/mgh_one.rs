//! Diagnostic: traces one MGH solve (every residual and Jacobian evaluation) with a chosen
//! configuration.
//! `cargo run -p bounded-lm --release --example mgh_one -- BrownDennis 1
//! [adaptive|classic|no-secant|no-correction|n2fb]`

use bounded_lm::problems::mgh;
use bounded_lm::{Options, Problem, RadiusUpdate, SecantScaling, Solver, StepModel};

struct Trace<'a>(&'a mut mgh::Mgh, usize);
impl Problem for Trace<'_> {
    fn residual_count(&self) -> usize {
        self.0.residual_count()
    }
    fn parameter_count(&self) -> usize {
        self.0.parameter_count()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        let ok = self.0.residuals(x, r);
        let f = 0.5 * r.iter().map(|v| v * v).sum::<f64>();
        println!("  f {f:.10e} at {x:.4?}");
        ok
    }
    fn jacobian(&mut self, x: &[f64], j: &mut [f64]) -> bool {
        self.1 += 1;
        println!("J{}", self.1);
        self.0.jacobian(x, j)
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let factor: f64 = args.get(2).map_or(1.0, |s| s.parse().unwrap());
    let mut options = Options::default();
    for a in args.iter().skip(3) {
        match a.as_str() {
            "adaptive" => options.model = StepModel::Adaptive { delay: 2 },
            "classic" => options.radius.update = RadiusUpdate::Classic,
            "no-secant" => options.scaling.secant = SecantScaling::Off,
            "no-correction" => options.safeguards.second_order_correction = false,
            "n2fb" => options = Options::n2fb(),
            other => {
                panic!("unknown option {other} (adaptive, classic, no-secant, no-correction, n2fb)")
            }
        }
    }
    for mut prob in mgh::all() {
        if !prob.label().contains(&args[1]) {
            continue;
        }
        let n = prob.parameter_count();
        let mut x = prob.start(factor);
        let rep = Solver::new()
            .solve(
                &mut Trace(&mut prob, 0),
                &mut x,
                &vec![f64::NEG_INFINITY; n],
                &vec![f64::INFINITY; n],
                &options,
            )
            .unwrap();
        println!("{} {rep:?}\nx = {x:?}", prob.label());
    }
}
