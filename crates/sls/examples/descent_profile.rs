//! Where the CPU time of a descent goes with many lobes: times one residual evaluation, one
//! Jacobian and one-iteration descents (the solver's linear algebra included) for `L`
//! anisotropic lobes on `k` rows of the tuning instance.
//!
//! ```text
//! cargo run --release -p sls --example descent_profile -- [--lobes 8,16,50] [--rows 25,500,10000]
//! ```

use brdf_model::{Layout, LobeKind, named_params, synthetic};
use cpu_time::ThreadTime;
use sls::{BrdfObjective, Budget, DescentLimits, Objective, Rows, Search, SearchRng, TrialContext};
use std::sync::Arc;

fn main() {
    let mut lobes = vec![8usize, 16, 50];
    let mut rows = vec![25usize, 500, 2000, 10000];
    let args: Vec<String> = std::env::args().skip(1).collect();
    for pair in args.chunks(2) {
        let v = pair.get(1).cloned().unwrap_or_default();
        match pair[0].as_str() {
            "--lobes" => lobes = v.split(',').map(|s| s.parse().expect("lobes")).collect(),
            "--rows" => rows = v.split(',').map(|s| s.parse().expect("rows")).collect(),
            f => panic!("unknown flag {f}"),
        }
    }
    let data = Arc::new(synthetic(&named_params("tuning").unwrap(), 10000, 0.1, 1));
    println!(
        "| lobes | params | rows | residuals ms | jacobian ms | 1-iteration descent ms | 5-iteration descent ms |"
    );
    println!("|---|---|---|---|---|---|---|");
    for &l in &lobes {
        let layout = Layout::builder(&vec![LobeKind::Anisotropic; l])
            .build()
            .unwrap();
        let objective = BrdfObjective::new(data.clone(), layout);
        let p = objective.dim();
        for &k in &rows {
            let mut ws = objective.workspace();
            let mut rng = <SearchRng as rand::SeedableRng>::seed_from_u64(1);
            let m = objective.select(&mut ws, Rows::Subsample(k), &mut rng);
            let mut x = vec![0.0; p];
            objective.random_pick(&mut rng, &mut x);
            let mut r = vec![0.0; m];
            let mut jac = vec![0.0; m * p];
            let t = ThreadTime::now();
            objective.residuals(&mut ws, &x, &mut r);
            let tr = t.elapsed().as_secs_f64() * 1e3;
            let t = ThreadTime::now();
            objective.jacobian(&mut ws, &x, &mut jac);
            let tj = t.elapsed().as_secs_f64() * 1e3;
            let mut times = [0.0; 2];
            for (slot, iters) in [1usize, 5].into_iter().enumerate() {
                let mut ctx = TrialContext::new(&objective, 1, Budget::default(), 0.0);
                let mut y = x.clone();
                let t = ThreadTime::now();
                let _ = ctx.descend(
                    &mut y,
                    Rows::sized(k as f64, data.len()),
                    DescentLimits {
                        iterations: iters,
                        evaluations: 200,
                    },
                );
                times[slot] = t.elapsed().as_secs_f64() * 1e3;
            }
            println!(
                "| {l} | {p} | {m} | {tr:.3} | {tj:.3} | {:.1} | {:.1} |",
                times[0], times[1]
            );
        }
    }
}
