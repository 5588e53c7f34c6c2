//! Golden tests: pin the solver's exact behaviour (outcome code, iteration, residual and
//! Jacobian evaluation counts, final f to 1e-12 relative) on the NIST StRD suite with every
//! configuration, on box-constrained variants of it, and with forward differences, so a
//! refactoring that is meant to change nothing can prove it.
//!
//! The expected values live in `tests/data/golden.txt`. After a deliberate change of behaviour,
//! regenerate them with `GOLDEN_BLESS=1 cargo test -p bounded-lm --release --test golden` and
//! say in the commit why the numbers moved.

mod common;

use bounded_lm::{
    ForwardDifference, Options, RadiusUpdate, Report, ResidualsOnly, SecantScaling, Solver,
    StepModel,
};
use common::nist::{NAMES, NistData, NistProblem, load};
use std::fmt::Write as _;

/// Residuals only (for the forward-difference adapter).
struct Fd<'a>(NistProblem<'a>);
impl ResidualsOnly for Fd<'_> {
    fn residual_count(&self) -> usize {
        bounded_lm::Problem::residual_count(&self.0)
    }
    fn parameter_count(&self) -> usize {
        bounded_lm::Problem::parameter_count(&self.0)
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        bounded_lm::Problem::residuals(&mut self.0, x, r)
    }
}

/// A box that cuts the path from start 1 to the certified values: parameter 0 is bounded
/// halfway between its start and its certified value (so the bound is active at the
/// solution), every other parameter within a factor 10 around the certified value.
fn cutting_box(d: &NistData) -> (Vec<f64>, Vec<f64>) {
    let p = d.certified.len();
    let mut lo = vec![f64::NEG_INFINITY; p];
    let mut hi = vec![f64::INFINITY; p];
    let (s, c) = (d.starts[0][0], d.certified[0]);
    if s < c {
        hi[0] = 0.5 * (s + c);
    } else {
        lo[0] = 0.5 * (s + c);
    }
    for j in 1..p {
        let (a, b) = (d.certified[j] / 10.0, d.certified[j] * 10.0);
        let (a, b) = (a.min(b), a.max(b));
        lo[j] = a.min(d.starts[0][j]);
        hi[j] = b.max(d.starts[0][j]);
    }
    (lo, hi)
}

fn line(out: &mut String, label: &str, r: &Report) {
    let _ = writeln!(
        out,
        "{label} {} {} {} {} {:.17e}",
        r.outcome.code(),
        r.iterations,
        r.residual_evaluations,
        r.jacobian_evaluations,
        r.f
    );
}

fn current() -> String {
    let mut out = String::new();
    let mut solver = Solver::new();
    let adaptive = Options {
        model: StepModel::N2FB,
        ..Options::default()
    };
    let mut classic = Options::gauss_newton();
    classic.radius.update = RadiusUpdate::Classic;
    let mut gn_nosecant = Options::gauss_newton();
    gn_nosecant.scaling.secant = SecantScaling::Off;
    // The default without the second-order correction: its lines are those of the solver
    // without that rule, so the option off is that solver bit for bit.
    let mut no_correction = Options::default();
    no_correction.safeguards.second_order_correction = false;
    let configs = [
        ("gn", Options::gauss_newton()),
        ("adaptive", adaptive),
        ("classic", classic),
        ("gn-nosecant", gn_nosecant),
        ("n2fb", Options::n2fb()),
        ("default", Options::default()),
        ("no-correction", no_correction),
    ];
    let data: Vec<NistData> = NAMES.iter().map(|n| load(n)).collect();
    for (tag, options) in configs {
        for d in &data {
            let p = d.certified.len();
            for s in 0..2 {
                let mut x = d.starts[s].clone();
                let r = solver
                    .solve(
                        &mut NistProblem::new(d),
                        &mut x,
                        &vec![f64::NEG_INFINITY; p],
                        &vec![f64::INFINITY; p],
                        &options,
                    )
                    .unwrap();
                line(&mut out, &format!("{tag} {} start{}", d.name, s + 1), &r);
            }
            let (lo, hi) = cutting_box(d);
            let mut x = d.starts[0].clone();
            let r = solver
                .solve(&mut NistProblem::new(d), &mut x, &lo, &hi, &options)
                .unwrap();
            line(&mut out, &format!("{tag} {} boxed", d.name), &r);
        }
    }
    // Forward differences (the sls path) on the easier problems, unbounded and boxed.
    let options = Options::default();
    for d in data.iter().take(12) {
        let p = d.certified.len();
        let mut x = d.starts[1].clone();
        let mut fd = ForwardDifference::new(Fd(NistProblem::new(d)));
        let r = solver
            .solve(
                &mut fd,
                &mut x,
                &vec![f64::NEG_INFINITY; p],
                &vec![f64::INFINITY; p],
                &options,
            )
            .unwrap();
        line(&mut out, &format!("fd {} start2", d.name), &r);
        let (lo, hi) = cutting_box(d);
        let mut x = d.starts[0].clone();
        let mut fd = ForwardDifference::new(Fd(NistProblem::new(d))).with_bounds(&lo, &hi);
        let r = solver.solve(&mut fd, &mut x, &lo, &hi, &options).unwrap();
        line(&mut out, &format!("fd {} boxed", d.name), &r);
    }
    out
}

#[test]
fn behaviour_matches_golden_file() {
    let path = format!("{}/tests/data/golden.txt", env!("CARGO_MANIFEST_DIR"));
    let now = current();
    if std::env::var_os("GOLDEN_BLESS").is_some() {
        std::fs::write(&path, &now).unwrap();
        return;
    }
    let expected = std::fs::read_to_string(&path).expect("tests/data/golden.txt");
    let mut diffs = Vec::new();
    let (a, b): (Vec<&str>, Vec<&str>) = (expected.lines().collect(), now.lines().collect());
    assert_eq!(a.len(), b.len(), "number of golden lines");
    for (e, n) in a.iter().zip(&b) {
        let (ew, nw): (Vec<&str>, Vec<&str>) = (
            e.split_whitespace().collect(),
            n.split_whitespace().collect(),
        );
        let k = ew.len() - 1;
        let (fe, fnow): (f64, f64) = (ew[k].parse().unwrap(), nw[k].parse().unwrap());
        let same_counts = ew[..k] == nw[..k];
        let same_f = (fe - fnow).abs() <= 1e-12 * fe.abs().max(1e-300) || fe == fnow;
        if !(same_counts && same_f) {
            diffs.push(format!("expected {e}\n     got {n}"));
        }
    }
    assert!(
        diffs.is_empty(),
        "{} of {} runs changed:\n{}",
        diffs.len(),
        a.len(),
        diffs.join("\n")
    );
}
