//! Criterion benchmarks: the whole NIST StRD suite (54 solves per iteration) and a synthetic
//! three-exponential fit (6 parameters) with 10000 rows and with 25 rows.
//!
//! `cargo bench -p bounded-lm --bench solve -- --warm-up-time 1 --measurement-time 3`

#[path = "../tests/common/expsum.rs"]
mod expsum;
#[path = "../tests/common/nist.rs"]
mod nist;

use bounded_lm::{Options, Solver, StepModel};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

fn bench_nist(c: &mut Criterion) {
    let data: Vec<nist::NistData> = nist::NAMES.iter().map(|n| nist::load(n)).collect();
    for model in [StepModel::GaussNewton, StepModel::Adaptive { delay: 2 }] {
        let options = Options {
            model,
            ..Options::default()
        };
        let mut solver = Solver::new();
        let (mut fev, mut jev) = (0, 0);
        for d in &data {
            for s in 0..2 {
                let r = nist::run(&mut solver, d, s, &options);
                fev += r.report.residual_evaluations;
                jev += r.report.jacobian_evaluations;
            }
        }
        println!(
            "NIST {model:?}: {:.1} residual and {:.1} Jacobian evaluations per solve",
            fev as f64 / 54.0,
            jev as f64 / 54.0
        );
        c.bench_function(&format!("nist_suite_54_solves_{model:?}"), |b| {
            b.iter(|| {
                for d in &data {
                    for s in 0..2 {
                        black_box(nist::run(&mut solver, d, s, &options));
                    }
                }
            })
        });
    }
}

fn bench_expsum(c: &mut Criterion) {
    let lower = [0.0; 6];
    let upper = [20.0; 6];
    let start = [1.0, 0.3, 1.0, 1.5, 1.0, 4.0];
    for m in [10_000usize, 25] {
        let mut prob = expsum::ExpSum::new(m, 6);
        let mut solver = Solver::new();
        let options = Options::default();
        let mut x = start;
        let rep = solver
            .solve(&mut prob, &mut x, &lower, &upper, &options)
            .unwrap();
        println!(
            "expsum m={m}: {:?}, {} iterations, {} residual / {} Jacobian evaluations",
            rep.outcome, rep.iterations, rep.residual_evaluations, rep.jacobian_evaluations
        );
        c.bench_function(&format!("expsum_m{m}_p6"), |b| {
            b.iter(|| {
                let mut x = start;
                black_box(
                    solver
                        .solve(&mut prob, &mut x, &lower, &upper, &options)
                        .unwrap(),
                )
            })
        });
    }
}

criterion_group!(benches, bench_nist, bench_expsum);
criterion_main!(benches);
