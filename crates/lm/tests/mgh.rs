//! The Moré-Garbow-Hillstrom collection: analytic Jacobians against finite differences, and the
//! solver's results on it (unbounded and boxed, from x0 and 10 x0).

mod common;

use bounded_lm::problems::mgh::{self, Kind, Mgh};
use bounded_lm::{Options, Problem};
use common::mgh_run;

/// Central differences against the analytic Jacobian at x0 and at a perturbed point.
#[test]
fn jacobians_match_finite_differences() {
    let mut checked = 0;
    for mut prob in mgh::all() {
        let (m, n) = (prob.residual_count(), prob.parameter_count());
        let x0 = prob.start(1.0);
        let perturbed: Vec<f64> = x0
            .iter()
            .enumerate()
            .map(|(k, v)| v + 0.1 * (1.0 + v.abs()) * (0.3 + 0.17 * k as f64).sin())
            .collect();
        for x in [x0, perturbed] {
            let mut jac = vec![0.0; m * n];
            assert!(prob.jacobian(&x, &mut jac), "{}", prob.label());
            let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
            for k in 0..n {
                let h = 1e-6 * x[k].abs().max(1.0);
                let mut xp = x.clone();
                xp[k] += h;
                let mut xm = x.clone();
                xm[k] -= h;
                assert!(prob.residuals(&xp, &mut rp) && prob.residuals(&xm, &mut rm));
                for i in 0..m {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    let an = jac[k * m + i];
                    let scale = an.abs().max(fd.abs()).max(1.0);
                    // Round-off of the difference (Brown badly scaled has r ~ 1e6).
                    let noise = 1e3 * f64::EPSILON * rp[i].abs().max(rm[i].abs()) / h;
                    assert!(
                        (fd - an).abs() <= 1e-5 * scale + noise,
                        "{} at {x:?}: d r{i} / d x{k}: analytic {an}, differences {fd}",
                        prob.label()
                    );
                }
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 2 * mgh::all().len());
}

/// The residuals vanish (or equal the listed F) at minimisers MGH give in closed form.
#[test]
fn known_minimisers() {
    let cases: [(Kind, usize, usize, Vec<f64>); 6] = [
        (Kind::Rosenbrock, 2, 2, vec![1.0, 1.0]),
        (Kind::FreudensteinRoth, 2, 2, vec![5.0, 4.0]),
        (Kind::GulfResearch, 3, 10, vec![50.0, 25.0, 1.5]),
        (Kind::Box3d, 3, 10, vec![1.0, 10.0, 1.0]),
        (Kind::BiggsExp6, 6, 13, vec![1.0, 10.0, 1.0, 5.0, 4.0, 3.0]),
        (Kind::Wood, 4, 6, vec![1.0; 4]),
    ];
    for (kind, n, m, x) in cases {
        let mut p = Mgh::new(kind, n, m);
        let mut r = vec![0.0; m];
        assert!(p.residuals(&x, &mut r));
        let f = 0.5 * r.iter().map(|v| v * v).sum::<f64>();
        assert!(f < 1e-20, "{kind:?}: {f}");
        assert!(p.reaches_minimum(f));
    }
    // Meyer's minimiser (MGH: F = 87.9458 at about (0.0056096, 6181.35, 345.224)).
    let mut p = Mgh::new(Kind::Meyer, 3, 16);
    let mut r = vec![0.0; 16];
    p.residuals(&[0.005_609_636_471, 6_181.346_346, 345.223_635_2], &mut r);
    let big_f: f64 = r.iter().map(|v| v * v).sum();
    assert!((big_f - 87.9458).abs() < 1e-3, "{big_f}");
}

/// MGH, unbounded and boxed, from x0 and 10 x0, default options: never a success code on a
/// wrong answer, every boxed case solved or an honest failure code, and at least the measured
/// counts of unbounded runs that reach a listed minimum (71 of 78) and that reach it with a
/// success code (65 of 78: the other six end with code 7, singular convergence, which does
/// not claim a minimum).
#[test]
fn mgh_collection() {
    let runs = mgh_run::run_all(&Options::default());
    let summary = mgh_run::summary(&runs);
    let table = mgh_run::table(&runs);
    for r in &runs {
        assert!(
            !r.wrong_success(),
            "success code on a wrong answer: {r:?}\n{table}"
        );
    }
    let unbounded = || runs.iter().filter(|r| r.bound.is_none());
    let solved = unbounded().filter(|r| r.solved).count();
    let solved_with_success = unbounded().filter(|r| r.solved_with_success()).count();
    assert!(solved >= 71, "{summary}\n{table}");
    assert!(solved_with_success >= 65, "{summary}\n{table}");
}
