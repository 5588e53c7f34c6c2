//! Descents on 25-row subsamples of the tuning instance (10,000 samples, noise 0.1, seed 1;
//! one anisotropic lobe) from the box's middle, a random pick, and each with n = 0, with the
//! searches' options and the default: code, f, evaluations and the scaled projected gradient
//! at the end, one line per subsample seed.
//!
//! `cargo run --release -p sls --example subsample_codes -- [SEEDS] [ROWS]`

use bounded_lm::{Options, Problem, Solver};
use brdf_model::{Layout, LobeKind, named_params, synthetic};
use sls::{BrdfObjective, BrdfWorkspace, Objective, Rows, SearchRng};
use std::sync::Arc;

struct Sub<'a> {
    obj: &'a BrdfObjective,
    ws: &'a mut BrdfWorkspace,
    m: usize,
}

impl Problem for Sub<'_> {
    fn residual_count(&self) -> usize {
        self.m
    }
    fn parameter_count(&self) -> usize {
        self.obj.dim()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        self.obj.residuals(self.ws, x, r)
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        self.obj.jacobian(self.ws, x, jac)
    }
}

/// `max_j |g_j| * max(|x_j|, 1)` over variables not held on a bound by the gradient's sign.
fn projected_gradient(p: &mut Sub, x: &[f64], lo: &[f64], hi: &[f64]) -> f64 {
    let (m, n) = (p.m, x.len());
    let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * n]);
    if !(p.residuals(x, &mut r) && p.jacobian(x, &mut jac)) {
        return f64::NAN;
    }
    let mut worst = 0.0f64;
    for j in 0..n {
        let g: f64 = (0..m).map(|i| jac[j * m + i] * r[i]).sum();
        let held = (x[j] <= lo[j] && g >= 0.0) || (x[j] >= hi[j] && g <= 0.0);
        if !held {
            worst = worst.max(g.abs() * x[j].abs().max(1.0));
        }
    }
    worst
}

fn main() {
    let seeds: u64 = std::env::args()
        .nth(1)
        .map_or(20, |s| s.parse().expect("seeds"));
    let rows: f64 = std::env::args()
        .nth(2)
        .map_or(25.0, |s| s.parse().expect("rows"));
    let data = Arc::new(synthetic(&named_params("tuning").unwrap(), 10000, 0.1, 1));
    let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
    let obj = BrdfObjective::new(data.clone(), layout);
    let (lo, hi) = (obj.lower().to_vec(), obj.upper().to_vec());
    let n_index = (0..obj.dim())
        .find(|&j| obj.layout().is_exponent(j))
        .unwrap();
    println!("| seed | start | options | code | f | evals | scaled projected gradient |");
    println!("|---|---|---|---|---|---|---|");
    for seed in 0..seeds {
        let mut rng = <SearchRng as rand::SeedableRng>::seed_from_u64(seed);
        let mut ws = obj.workspace();
        let m = obj.select(&mut ws, Rows::sized(rows, data.len()), &mut rng);
        let middle: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| 0.5 * (a + b)).collect();
        let mut at_n0 = middle.clone();
        at_n0[n_index] = lo[n_index];
        let mut picked = middle.clone();
        obj.random_pick(&mut rng, &mut picked);
        let mut picked_n0 = picked.clone();
        picked_n0[n_index] = lo[n_index];
        for (start_name, start) in [
            ("middle", &middle),
            ("n = 0", &at_n0),
            ("random", &picked),
            ("random, n = 0", &picked_n0),
        ] {
            let search = Options::search();
            let mut hold = search.clone();
            hold.safeguards.hold_dead_columns = true;
            let mut long_test = search.clone();
            long_test.safeguards.singular_radius_at_least_x = true;
            let mut min_norm = search.clone();
            min_norm.safeguards.stop_at_minimum_norm_step = true;
            let mut gauss_newton = search.clone();
            gauss_newton.model = bounded_lm::StepModel::GaussNewton;
            gauss_newton.scaling.secant = bounded_lm::SecantScaling::Off;
            for (name, options) in [
                ("search", search),
                ("search+hold", hold),
                ("search+long test", long_test),
                ("search+min-norm", min_norm),
                ("search GN no secant", gauss_newton),
                ("default", Options::default()),
                ("n2fb", Options::n2fb()),
            ] {
                let mut x = start.clone();
                let mut p = Sub {
                    obj: &obj,
                    ws: &mut ws,
                    m,
                };
                let rep = Solver::new().solve(&mut p, &mut x, &lo, &hi, &options);
                let pg = projected_gradient(&mut p, &x, &lo, &hi);
                match rep {
                    Ok(r) => println!(
                        "| {seed} | {start_name} | {name} | {:?} | {:.6} | {} | {pg:.3} |",
                        r.outcome, r.f, r.residual_evaluations
                    ),
                    Err(e) => println!("| {seed} | {start_name} | {name} | {e:?} | - | - | - |"),
                }
            }
        }
    }
}
