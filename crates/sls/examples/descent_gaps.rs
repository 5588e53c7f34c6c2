//! Diagnoses CPU-cutoff overshoot inside descents with many lobes: runs bounded-LM descents of
//! `L` anisotropic lobes on `k`-row subsamples of the tuning instance through a problem wrapper
//! that timestamps every call, and prints per descent the CPU time, the iterations, the calls,
//! the longest CPU gap between two consecutive calls (what no per-call clock check can cut),
//! and the wind-down: the CPU time from the first refused evaluation (the wrapper refuses
//! everything after `--refuse-ms`, reporting failed evaluations or, as the trial context does,
//! zero residuals) to the solver's return.
//!
//! ```text
//! cargo run --release -p sls --example descent_gaps -- [--lobes 8,16,50] [--rows 25,100]
//!     [--starts 5] [--refuse-ms 5]
//! ```

use bounded_lm::{Options, Problem, Solver};
use brdf_model::{Layout, LobeKind, named_params, synthetic};
use cpu_time::ThreadTime;
use sls::{BrdfObjective, BrdfWorkspace, Objective, Rows, SearchRng};
use std::sync::Arc;

struct Timed<'a> {
    obj: &'a BrdfObjective,
    ws: &'a mut BrdfWorkspace,
    m: usize,
    clock: ThreadTime,
    last: f64,
    max_gap: f64,
    calls: usize,
    refuse_after: f64,
    refused_at: Option<f64>,
    /// After refusing, report zero residuals (as the trial context does) instead of failures.
    zeros: bool,
}

impl Timed<'_> {
    fn tick(&mut self) -> bool {
        let t = self.clock.elapsed().as_secs_f64();
        self.max_gap = self.max_gap.max(t - self.last);
        self.last = t;
        self.calls += 1;
        if t >= self.refuse_after {
            self.refused_at.get_or_insert(t);
            return false;
        }
        true
    }
}

impl Problem for Timed<'_> {
    fn residual_count(&self) -> usize {
        self.m
    }
    fn parameter_count(&self) -> usize {
        self.obj.dim()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        if !self.tick() {
            r.fill(0.0);
            return self.zeros;
        }
        self.obj.residuals(self.ws, x, r)
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        self.tick() && self.obj.jacobian(self.ws, x, jac)
    }
    fn should_stop(&mut self) -> bool {
        !self.tick()
    }
}

fn main() {
    let mut lobes = vec![8usize, 16, 50];
    let mut rows = vec![25usize, 100];
    let mut starts = 5;
    let mut refuse_ms = 5.0;
    let args: Vec<String> = std::env::args().skip(1).collect();
    for pair in args.chunks(2) {
        let v = pair.get(1).cloned().unwrap_or_default();
        match pair[0].as_str() {
            "--lobes" => lobes = v.split(',').map(|s| s.parse().expect("lobes")).collect(),
            "--rows" => rows = v.split(',').map(|s| s.parse().expect("rows")).collect(),
            "--starts" => starts = v.parse().expect("starts"),
            "--refuse-ms" => refuse_ms = v.parse().expect("refuse-ms"),
            f => panic!("unknown flag {f}"),
        }
    }
    let data = Arc::new(synthetic(&named_params("tuning").unwrap(), 10000, 0.1, 1));
    println!(
        "| lobes | rows | mode | CPU ms | iterations | calls | max gap ms | wind-down ms | outcome |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for &l in &lobes {
        let layout = Layout::builder(&vec![LobeKind::Anisotropic; l])
            .build()
            .unwrap();
        let obj = BrdfObjective::new(data.clone(), layout);
        let p = obj.dim();
        let mut rng = <SearchRng as rand::SeedableRng>::seed_from_u64(7);
        for &k in &rows {
            let mut done = 0;
            let mut tries = 0;
            while done < starts && tries < 1000 {
                tries += 1;
                let mut ws = obj.workspace();
                let m = obj.select(&mut ws, Rows::sized(k as f64, data.len()), &mut rng);
                let mut x = vec![0.0; p];
                obj.random_pick(&mut rng, &mut x);
                let mut jac = vec![0.0; m * p];
                if !obj.jacobian(&mut ws, &x, &mut jac) {
                    continue; // unevaluable start
                }
                done += 1;
                for (mode, refuse, zeros) in [
                    ("free", f64::INFINITY, false),
                    ("refuse-fail", refuse_ms * 1e-3, false),
                    ("refuse-zero", refuse_ms * 1e-3, true),
                ] {
                    let mut y = x.clone();
                    let mut prob = Timed {
                        obj: &obj,
                        ws: &mut ws,
                        m,
                        clock: ThreadTime::now(),
                        last: 0.0,
                        max_gap: 0.0,
                        calls: 0,
                        refuse_after: refuse,
                        refused_at: None,
                        zeros,
                    };
                    let mut solver = Solver::new();
                    let res = solver.solve(
                        &mut prob,
                        &mut y,
                        obj.lower(),
                        obj.upper(),
                        &Options::default(),
                    );
                    let end = prob.clock.elapsed().as_secs_f64();
                    let wind = prob.refused_at.map(|t| (end - t) * 1e3);
                    let (it, out) = match &res {
                        Ok(r) => (r.iterations, format!("{:?}", r.outcome)),
                        Err(e) => (0, format!("{e:?}")),
                    };
                    println!(
                        "| {l} | {m} | {mode} | {:.1} | {it} | {} | {:.2} | {} | {out} |",
                        end * 1e3,
                        prob.calls,
                        prob.max_gap * 1e3,
                        wind.map_or("-".into(), |w| format!("{w:.1}"))
                    );
                }
            }
        }
    }
}
