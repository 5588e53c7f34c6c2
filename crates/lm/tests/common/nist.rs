//! NIST StRD helpers for tests, benches and examples: the problems themselves are
//! `bounded_lm::problems::nist`; this adds LRE scoring and suite runs.

#![allow(dead_code, clippy::needless_range_loop)]

pub use bounded_lm::problems::nist::{NAMES, NistData, NistProblem, load, lre, min_lre};
use bounded_lm::{Options, Outcome, Report, Solver};

/// One solve of one problem from one start.
#[derive(Clone, Debug)]
pub struct NistRun {
    pub name: String,
    pub start: usize,
    pub min_lre: f64,
    pub rss_lre: f64,
    pub report: Report,
}

impl NistRun {
    pub fn correct(&self) -> bool {
        self.min_lre >= 4.0
    }
    pub fn outcome(&self) -> Outcome {
        self.report.outcome
    }
}

/// Solves `data` from start `start` (0 or 1).
pub fn run(solver: &mut Solver, data: &NistData, start: usize, options: &Options) -> NistRun {
    let mut x = data.starts[start].clone();
    let p = x.len();
    let lower = vec![f64::NEG_INFINITY; p];
    let upper = vec![f64::INFINITY; p];
    let mut prob = NistProblem::new(data);
    let report = solver
        .solve(&mut prob, &mut x, &lower, &upper, options)
        .unwrap_or_else(|e| panic!("{} start {}: {e}", data.name, start + 1));
    let min_lre = min_lre(&data.name, &x, &data.certified);
    let rss_lre = lre(2.0 * report.f, data.certified_rss);
    NistRun {
        name: data.name.clone(),
        start: start + 1,
        min_lre,
        rss_lre,
        report,
    }
}

/// All 54 runs.
pub fn run_all(options: &Options) -> Vec<NistRun> {
    let mut solver = Solver::new();
    let mut out = Vec::new();
    for name in NAMES {
        let data = load(name);
        for start in 0..2 {
            out.push(run(&mut solver, &data, start, options));
        }
    }
    out
}
