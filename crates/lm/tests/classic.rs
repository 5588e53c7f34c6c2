//! More-Garbow-Hillstrom classics with and without bounds, and the failure-mode outcomes.

use bounded_lm::{ForwardDifference, Options, Outcome, Problem, ResidualsOnly, SolveError, Solver};

/// A problem from closures: residuals and an analytic Jacobian (column-major).
struct Fun<R, J> {
    m: usize,
    p: usize,
    r: R,
    j: J,
}

impl<R, J> Problem for Fun<R, J>
where
    R: FnMut(&[f64], &mut [f64]) -> bool,
    J: FnMut(&[f64], &mut [f64]) -> bool,
{
    fn residual_count(&self) -> usize {
        self.m
    }
    fn parameter_count(&self) -> usize {
        self.p
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        (self.r)(x, r)
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        (self.j)(x, jac)
    }
}

fn rosenbrock() -> impl Problem {
    Fun {
        m: 2,
        p: 2,
        r: |x: &[f64], r: &mut [f64]| {
            r[0] = 10.0 * (x[1] - x[0] * x[0]);
            r[1] = 1.0 - x[0];
            true
        },
        j: |x: &[f64], j: &mut [f64]| {
            j.copy_from_slice(&[-20.0 * x[0], -1.0, 10.0, 0.0]);
            true
        },
    }
}

const INF: f64 = f64::INFINITY;

fn solve(prob: &mut impl Problem, x: &mut [f64], lo: &[f64], hi: &[f64]) -> bounded_lm::Report {
    Solver::new()
        .solve(prob, x, lo, hi, &Options::default())
        .expect("solve")
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= tol * (1.0 + y.abs()))
}

#[test]
fn rosenbrock_unbounded() {
    let mut x = [-1.2, 1.0];
    let rep = solve(&mut rosenbrock(), &mut x, &[-INF; 2], &[INF; 2]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(close(&x, &[1.0, 1.0], 1e-8), "{x:?}");
}

#[test]
fn rosenbrock_optimum_on_bound() {
    // x0 <= 0.5: the constrained optimum is (0.5, 0.25) with x0 on its bound.
    let mut x = [-1.2, 1.0];
    let rep = solve(&mut rosenbrock(), &mut x, &[-INF; 2], &[0.5, INF]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert_eq!(x[0], 0.5);
    assert!(close(&x, &[0.5, 0.25], 1e-8), "{x:?}");
    assert!((rep.f - 0.125).abs() < 1e-12);
}

#[test]
fn rosenbrock_start_on_bound() {
    let mut x = [-1.2, 1.0];
    let rep = solve(&mut rosenbrock(), &mut x, &[-1.2, -INF], &[INF; 2]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(close(&x, &[1.0, 1.0], 1e-8), "{x:?}");
    // Start on the bound with the optimum on the same bound (x1 >= 1): the constrained problem
    // has a local minimum near (-0.995, 1) on the bound, which is a correct answer too.
    let mut x = [-1.2, 1.0];
    let rep = solve(&mut rosenbrock(), &mut x, &[-INF, 1.0], &[INF; 2]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert_eq!(x[1], 1.0);
    assert!(
        close(&x, &[1.0, 1.0], 1e-8) || (x[0] + 0.995).abs() < 1e-2,
        "{x:?}"
    );
}

#[test]
fn rosenbrock_bound_cuts_the_valley() {
    // The curved valley x1 = x0^2 passes below x1 = 0.3 near x0 = 0, so the bound blocks the
    // path from (-1.2, 1) to the interior optimum (1, 1) and creates a constrained local minimum
    // on the bound near x0 = -0.53. Either is a correct answer: check the KKT conditions.
    let mut x = [-1.2, 1.0];
    let rep = solve(&mut rosenbrock(), &mut x, &[-INF, 0.3], &[INF; 2]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    let g0 = -200.0 * x[0] * (x[1] - x[0] * x[0]) - (1.0 - x[0]);
    let g1 = 100.0 * (x[1] - x[0] * x[0]);
    assert!(g0.abs() < 1e-4, "{x:?} {g0}");
    assert!(g1.abs() < 1e-6 || (x[1] == 0.3 && g1 > 0.0), "{x:?} {g1}");
    assert!(x[1] >= 0.3);
}

#[test]
fn start_outside_box_is_projected() {
    let mut x = [-5.0, 9.0];
    let rep = solve(&mut rosenbrock(), &mut x, &[-2.0, -2.0], &[2.0, 2.0]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(close(&x, &[1.0, 1.0], 1e-8), "{x:?}");
}

fn freudenstein_roth() -> impl Problem {
    Fun {
        m: 2,
        p: 2,
        r: |x: &[f64], r: &mut [f64]| {
            r[0] = -13.0 + x[0] + ((5.0 - x[1]) * x[1] - 2.0) * x[1];
            r[1] = -29.0 + x[0] + ((x[1] + 1.0) * x[1] - 14.0) * x[1];
            true
        },
        j: |x: &[f64], j: &mut [f64]| {
            j[0] = 1.0;
            j[1] = 1.0;
            j[2] = 10.0 * x[1] - 3.0 * x[1] * x[1] - 2.0;
            j[3] = 3.0 * x[1] * x[1] + 2.0 * x[1] - 14.0;
            true
        },
    }
}

#[test]
fn freudenstein_roth_local_minimum_and_bounded_global() {
    // From the standard start LM methods reach the local minimum f = 0.5 * 48.9842.
    let mut x = [0.5, -2.0];
    let rep = solve(&mut freudenstein_roth(), &mut x, &[-INF; 2], &[INF; 2]);
    // J is singular at that local minimum (both columns parallel), so the iterates stall there
    // without a success code: singular or false convergence, never a budget stop.
    assert!(
        rep.outcome.is_success()
            || matches!(
                rep.outcome,
                Outcome::SingularConvergence | Outcome::FalseConvergence
            ),
        "{rep:?}"
    );
    assert!(
        (rep.f - 0.5 * 48.984_253_679_240_3).abs() < 1e-6 || rep.f < 1e-12,
        "{rep:?} {x:?}"
    );
    // x1 >= 2 keeps the iterates away from the local minimum (x1 = -0.8968): global (5, 4).
    let mut x = [0.5, 2.0];
    let rep = solve(&mut freudenstein_roth(), &mut x, &[-INF, 2.0], &[INF; 2]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(close(&x, &[5.0, 4.0], 1e-7), "{x:?}");
}

fn powell_singular() -> impl Problem {
    let s5 = 5f64.sqrt();
    let s10 = 10f64.sqrt();
    Fun {
        m: 4,
        p: 4,
        r: move |x: &[f64], r: &mut [f64]| {
            r[0] = x[0] + 10.0 * x[1];
            r[1] = s5 * (x[2] - x[3]);
            r[2] = (x[1] - 2.0 * x[2]).powi(2);
            r[3] = s10 * (x[0] - x[3]).powi(2);
            true
        },
        j: move |x: &[f64], j: &mut [f64]| {
            j.fill(0.0);
            let (a, b) = (x[1] - 2.0 * x[2], x[0] - x[3]);
            j[0] = 1.0;
            j[3] = 2.0 * s10 * b;
            j[4] = 10.0;
            j[4 + 2] = 2.0 * a;
            j[8 + 1] = s5;
            j[8 + 2] = -4.0 * a;
            j[12 + 1] = -s5;
            j[12 + 3] = -2.0 * s10 * b;
            true
        },
    }
}

#[test]
fn powell_singular_reaches_zero() {
    let mut x = [3.0, -1.0, 0.0, 1.0];
    let rep = solve(&mut powell_singular(), &mut x, &[-INF; 4], &[INF; 4]);
    assert!(rep.f < 1e-12, "{rep:?}");
    assert!(x.iter().all(|v| v.abs() < 1e-3), "{x:?}");
    // The Jacobian is singular at the solution: success (f tiny) or singular convergence, never
    // a budget stop.
    assert!(
        rep.outcome.is_success() || rep.outcome == Outcome::SingularConvergence,
        "{rep:?}"
    );
}

fn box3d() -> impl Problem {
    Fun {
        m: 10,
        p: 3,
        r: |x: &[f64], r: &mut [f64]| {
            for (i, ri) in r.iter_mut().enumerate() {
                let t = 0.1 * (i + 1) as f64;
                *ri =
                    (-t * x[0]).exp() - (-t * x[1]).exp() - x[2] * ((-t).exp() - (-10.0 * t).exp());
            }
            true
        },
        j: |x: &[f64], j: &mut [f64]| {
            for i in 0..10 {
                let t = 0.1 * (i + 1) as f64;
                j[i] = -t * (-t * x[0]).exp();
                j[10 + i] = t * (-t * x[1]).exp();
                j[20 + i] = -((-t).exp() - (-10.0 * t).exp());
            }
            true
        },
    }
}

#[test]
fn box3d_unbounded_and_with_optimum_on_bound() {
    let mut x = [0.0, 10.0, 20.0];
    let rep = solve(&mut box3d(), &mut x, &[-INF; 3], &[INF; 3]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(
        rep.f < 1e-20 || close(&x, &[1.0, 10.0, 1.0], 1e-6),
        "{rep:?} {x:?}"
    );
    // x2 <= 0.9 excludes the zero-residual solutions: the optimum has x2 on its bound.
    let mut x = [0.0, 10.0, 0.5];
    let rep = solve(&mut box3d(), &mut x, &[-INF; 3], &[INF, INF, 0.9]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert_eq!(x[2], 0.9, "{x:?}");
    assert!(rep.f > 0.0);
}

fn beale() -> impl Problem {
    const Y: [f64; 3] = [1.5, 2.25, 2.625];
    Fun {
        m: 3,
        p: 2,
        r: |x: &[f64], r: &mut [f64]| {
            for i in 0..3 {
                r[i] = Y[i] - x[0] * (1.0 - x[1].powi(i as i32 + 1));
            }
            true
        },
        j: |x: &[f64], j: &mut [f64]| {
            for i in 0..3 {
                let k = i as i32 + 1;
                j[i] = -(1.0 - x[1].powi(k));
                j[3 + i] = x[0] * k as f64 * x[1].powi(k - 1);
            }
            true
        },
    }
}

#[test]
fn beale_unbounded_and_bounded() {
    let mut x = [1.0, 1.0];
    let rep = solve(&mut beale(), &mut x, &[-INF; 2], &[INF; 2]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(close(&x, &[3.0, 0.5], 1e-7), "{x:?}");
    // x0 <= 2.5 puts the optimum on the bound.
    let mut x = [1.0, 1.0];
    let rep = solve(&mut beale(), &mut x, &[-INF; 2], &[2.5, INF]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert_eq!(x[0], 2.5);
}

fn jennrich_sampson() -> impl Problem {
    Fun {
        m: 10,
        p: 2,
        r: |x: &[f64], r: &mut [f64]| {
            for (i, ri) in r.iter_mut().enumerate() {
                let k = (i + 1) as f64;
                *ri = 2.0 + 2.0 * k - ((k * x[0]).exp() + (k * x[1]).exp());
            }
            r.iter().all(|v| v.is_finite())
        },
        j: |x: &[f64], j: &mut [f64]| {
            for i in 0..10 {
                let k = (i + 1) as f64;
                j[i] = -k * (k * x[0]).exp();
                j[10 + i] = -k * (k * x[1]).exp();
            }
            true
        },
    }
}

#[test]
fn jennrich_sampson_large_residual() {
    let mut x = [0.3, 0.4];
    let rep = solve(&mut jennrich_sampson(), &mut x, &[-INF; 2], &[INF; 2]);
    // The optimum has x0 = x1, where the two Jacobian columns coincide, so the Gauss-Newton model
    // cannot certify it: the iterates reach it and stall with singular or false convergence
    // (which of the two depends on round-off), or a success code; never a budget stop.
    assert!(
        rep.outcome.is_success()
            || matches!(
                rep.outcome,
                Outcome::SingularConvergence | Outcome::FalseConvergence
            ),
        "{rep:?}"
    );
    assert!((2.0 * rep.f - 124.362_182_355_8).abs() < 1e-6, "{rep:?}");
    assert!(close(&x, &[0.257_824_8, 0.257_824_8], 1e-5), "{x:?}");
}

/// y = a * b * x: only the product is identifiable.
struct Product;
impl Problem for Product {
    fn residual_count(&self) -> usize {
        5
    }
    fn parameter_count(&self) -> usize {
        3
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        for (i, ri) in r.iter_mut().enumerate() {
            let t = i as f64 + 1.0;
            // noise-like data so the optimum has a nonzero residual
            *ri = x[0] * x[1] * t - (2.0 * t + [0.1, -0.2, 0.05, 0.3, -0.1][i]);
        }
        true
    }
    fn jacobian(&mut self, x: &[f64], j: &mut [f64]) -> bool {
        for i in 0..5 {
            let t = i as f64 + 1.0;
            j[i] = x[1] * t;
            j[5 + i] = x[0] * t;
            // third parameter: unused (a zero Jacobian column)
            j[10 + i] = 0.0;
        }
        true
    }
}

#[test]
fn rank_deficient_gives_singular_convergence() {
    let mut x = [1.0, 1.0, 3.0];
    let rep = solve(&mut Product, &mut x, &[-INF; 3], &[INF; 3]);
    assert_eq!(rep.outcome, Outcome::SingularConvergence, "{rep:?} {x:?}");
    assert!((x[0] * x[1] - 2.0).abs() < 0.1, "{x:?}");
}

/// Exponential decay with a deterministic pseudo-random perturbation of size `noise` that
/// changes with every bit of x (a non-smooth f, like a noisy simulation).
struct Noisy {
    noise: f64,
}
impl ResidualsOnly for Noisy {
    fn residual_count(&self) -> usize {
        20
    }
    fn parameter_count(&self) -> usize {
        2
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        let mut h = x[0].to_bits() ^ x[1].to_bits().rotate_left(17);
        for (i, ri) in r.iter_mut().enumerate() {
            h = h
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407 + i as u64);
            let u = (h >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let t = i as f64 * 0.25;
            *ri = x[0] * (-x[1] * t).exp() - 3.0 * (-0.7 * t).exp() + self.noise * u;
        }
        true
    }
}

#[test]
fn noisy_residuals_with_differences_do_not_claim_convergence() {
    let mut prob = ForwardDifference::new(Noisy { noise: 1e-4 });
    let mut x = [1.0, 0.2];
    let rep = solve(&mut prob, &mut x, &[-INF; 2], &[INF; 2]);
    assert!(prob.difference_evaluations() > 0);
    assert_eq!(rep.outcome, Outcome::FalseConvergence, "{rep:?} {x:?}");
    // The difference Jacobian is dominated by noise/h ~ 1e4, so no real progress is possible;
    // the solver must not have made f worse.
    let mut r = [0.0; 20];
    Noisy { noise: 1e-4 }.residuals(&[1.0, 0.2], &mut r);
    assert!(rep.f <= 0.5 * r.iter().map(|v| v * v).sum::<f64>());
}

#[test]
fn forward_difference_on_smooth_problem_converges() {
    let mut prob =
        ForwardDifference::new(Noisy { noise: 0.0 }).with_bounds(&[0.0, 0.0], &[10.0, 0.7]);
    let mut x = [1.0, 0.2];
    let rep = solve(&mut prob, &mut x, &[0.0, 0.0], &[10.0, 0.7]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(close(&x, &[3.0, 0.7], 1e-6), "{x:?}");
}

/// ln-based residuals: undefined for x <= 0, optimum at 0.01 close to that region.
fn log_problem() -> impl Problem {
    Fun {
        m: 1,
        p: 1,
        r: |x: &[f64], r: &mut [f64]| {
            if x[0] <= 0.0 {
                return false;
            }
            r[0] = x[0].ln() - 0.01f64.ln();
            true
        },
        j: |x: &[f64], j: &mut [f64]| {
            j[0] = 1.0 / x[0];
            true
        },
    }
}

#[test]
fn failed_evaluations_are_survived() {
    let mut x = [1.0];
    let rep = solve(&mut log_problem(), &mut x, &[-INF], &[INF]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!((x[0] - 0.01).abs() < 1e-8, "{x:?}");
}

#[test]
fn nan_region_is_survived() {
    // Residuals turn NaN (not reported as failure) for x0 > 2; optimum at 1.9.
    let mut prob = Fun {
        m: 2,
        p: 1,
        r: |x: &[f64], r: &mut [f64]| {
            r[0] = if x[0] > 2.0 { f64::NAN } else { x[0] - 1.9 };
            r[1] = 0.0;
            true
        },
        j: |_x: &[f64], j: &mut [f64]| {
            j[0] = 1.0;
            j[1] = 0.0;
            true
        },
    };
    let mut x = [-30.0];
    let rep = solve(&mut prob, &mut x, &[-INF], &[INF]);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!((x[0] - 1.9).abs() < 1e-10);
}

#[test]
fn start_not_evaluable_is_an_error() {
    let mut x = [-1.0];
    let err = Solver::new()
        .solve(
            &mut log_problem(),
            &mut x,
            &[-INF],
            &[INF],
            &Options::default(),
        )
        .unwrap_err();
    assert_eq!(err, SolveError::StartNotEvaluable);
}

#[test]
fn input_errors() {
    let mut x = [0.0, 0.0];
    let err = Solver::new()
        .solve(
            &mut rosenbrock(),
            &mut x,
            &[1.0, 0.0],
            &[0.0, 1.0],
            &Options::default(),
        )
        .unwrap_err();
    assert!(
        matches!(err, SolveError::InconsistentBounds { index: 0, .. }),
        "{err}"
    );
    let err = Solver::new()
        .solve(
            &mut rosenbrock(),
            &mut x,
            &[0.0],
            &[1.0, 1.0],
            &Options::default(),
        )
        .unwrap_err();
    assert!(
        matches!(err, SolveError::DimensionMismatch { what: "lower", .. }),
        "{err}"
    );
    let mut bad = Options::default();
    bad.tolerances.relative_function = -1.0;
    let err = Solver::new()
        .solve(&mut rosenbrock(), &mut x, &[-INF; 2], &[INF; 2], &bad)
        .unwrap_err();
    assert!(
        matches!(&err, SolveError::InvalidOptions(e) if e.field == "tolerances.relative_function"),
        "{err}"
    );
}

#[test]
fn budgets_give_limit_codes() {
    let mut x = [-1.2, 1.0];
    let o = Options::default().with_limits(3, 200);
    let rep = Solver::new()
        .solve(&mut rosenbrock(), &mut x, &[-INF; 2], &[INF; 2], &o)
        .unwrap();
    assert_eq!(rep.outcome, Outcome::IterationLimit);
    assert_eq!(rep.iterations, 3);
    let mut x = [-1.2, 1.0];
    let o = Options::default().with_limits(150, 4);
    let rep = Solver::new()
        .solve(&mut rosenbrock(), &mut x, &[-INF; 2], &[INF; 2], &o)
        .unwrap();
    assert_eq!(rep.outcome, Outcome::EvaluationLimit);
    assert_eq!(rep.residual_evaluations, 4);
}

#[test]
fn outcome_codes() {
    let all = [
        Outcome::XConvergence,
        Outcome::RelativeFunctionConvergence,
        Outcome::BothConvergence,
        Outcome::AbsoluteFunctionConvergence,
        Outcome::SingularConvergence,
        Outcome::FalseConvergence,
        Outcome::EvaluationLimit,
        Outcome::IterationLimit,
    ];
    for (i, o) in all.iter().enumerate() {
        assert_eq!(o.code() as usize, i + 3);
        assert_eq!(o.is_success(), i < 4);
    }
}

#[test]
fn failed_jacobian_returns_to_previous_point() {
    // The Jacobian cannot be computed for x0 > 0.5 (the residuals can): every step there is
    // undone, so the solver must end at a point with x0 <= 0.5 without claiming convergence to
    // the unconstrained optimum (1, 1).
    let mut prob = Fun {
        m: 2,
        p: 2,
        r: |x: &[f64], r: &mut [f64]| {
            r[0] = 10.0 * (x[1] - x[0] * x[0]);
            r[1] = 1.0 - x[0];
            true
        },
        j: |x: &[f64], j: &mut [f64]| {
            j.copy_from_slice(&[-20.0 * x[0], -1.0, 10.0, 0.0]);
            x[0] <= 0.5
        },
    };
    let mut x = [-1.2, 1.0];
    let rep = solve(&mut prob, &mut x, &[-INF; 2], &[INF; 2]);
    assert!(x[0] <= 0.5, "{x:?} {rep:?}");
    assert!(!rep.outcome.is_success(), "{rep:?}");
    assert!(rep.jacobian_evaluations > rep.iterations, "{rep:?}");
}

#[test]
fn every_evaluation_is_feasible() {
    // Box 3-D from a start outside the box, with bounds that cut the path: every residual and
    // Jacobian evaluation must happen inside the box.
    let lo = [0.5, 2.0, 0.2];
    let hi = [2.0, 9.0, 0.9];
    let inside = move |x: &[f64]| {
        x.iter()
            .zip(&lo)
            .zip(&hi)
            .all(|((v, l), h)| v >= l && v <= h)
    };
    let mut inner = box3d();
    let mut outside = 0usize;
    let mut prob = Fun {
        m: 10,
        p: 3,
        r: |x: &[f64], r: &mut [f64]| {
            if !inside(x) {
                outside += 1;
            }
            inner.residuals(x, r)
        },
        j: |x: &[f64], j: &mut [f64]| {
            assert!(inside(x), "Jacobian outside the box at {x:?}");
            box3d().jacobian(x, j)
        },
    };
    let mut x = [0.0, 10.0, 20.0];
    let rep = solve(&mut prob, &mut x, &lo, &hi);
    assert_eq!(outside, 0);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(inside(&x));
}

/// `y = x0 (1 + x0) + x1 t + x2 sin(3 t)` on 25 points, fitted to data with intercept -0.5:
/// with `x0 >= 0` the optimum lies on the bound and the data pull hard into it (`g0 > 0`). On
/// the face `x0 = 0` the residuals are linear in the free variables.
fn pulled_into_bound() -> impl Problem {
    let t: Vec<f64> = (0..25).map(|i| i as f64 / 24.0).collect();
    let y: Vec<f64> = t
        .iter()
        .map(|&t| -0.5 + 2.0 * t + 0.3 * (3.0 * t).sin())
        .collect();
    let t2 = t.clone();
    Fun {
        m: 25,
        p: 3,
        r: move |x: &[f64], r: &mut [f64]| {
            for i in 0..25 {
                r[i] = x[0] * (1.0 + x[0]) + x[1] * t[i] + x[2] * (3.0 * t[i]).sin() - y[i];
            }
            true
        },
        j: move |x: &[f64], j: &mut [f64]| {
            for i in 0..25 {
                j[i] = 1.0 + 2.0 * x[0];
                j[25 + i] = t2[i];
                j[50 + i] = (3.0 * t2[i]).sin();
            }
            true
        },
    }
}

/// The free variables of `pulled_into_bound` on the face `x0 = 0` (least squares by the normal
/// equations of the 2-column problem).
fn pulled_into_bound_face_optimum() -> [f64; 2] {
    let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..25 {
        let t = i as f64 / 24.0;
        let (c1, c2) = (t, (3.0 * t).sin());
        let y = -0.5 + 2.0 * t + 0.3 * (3.0 * t).sin();
        a11 += c1 * c1;
        a12 += c1 * c2;
        a22 += c2 * c2;
        b1 += c1 * y;
        b2 += c2 * y;
    }
    let det = a11 * a22 - a12 * a12;
    [(b1 * a22 - b2 * a12) / det, (a11 * b2 - a12 * b1) / det]
}

#[test]
fn optimum_on_bound_with_strong_pull_converges_within_a_few_iterations() {
    // AED calls the solver with 10 iterations: a descent that reaches the face of the box must
    // report convergence there, not creep into the iteration limit.
    let options = Options::default().with_limits(10, 200);
    let face = pulled_into_bound_face_optimum();
    for start in [[0.3, 1.0, 0.0], [0.0, 1.0, 0.0], [1.0, -3.0, 2.0]] {
        let mut x = start;
        let rep = Solver::new()
            .solve(
                &mut pulled_into_bound(),
                &mut x,
                &[0.0, -10.0, -10.0],
                &[1.0, 10.0, 10.0],
                &options,
            )
            .expect("solve");
        assert!(rep.outcome.is_success(), "{start:?}: {rep:?}");
        assert!(rep.iterations <= 6, "{start:?}: {rep:?}");
        assert_eq!(x[0], 0.0, "{start:?}");
        assert!(close(&x[1..], &face, 1e-7), "{x:?} {face:?}");
    }
}

#[test]
fn step_cut_at_a_bound_does_not_prevent_convergence() {
    // Start a hair inside the box with the free variables already optimal on the face: the
    // Gauss-Newton step crosses the bound, is cut there and the rest (nothing) is re-solved as
    // a Newton step. As in N2FB (whose x-convergence test asks for STPPAR = 0, the Marquardt
    // parameter of the last sub-step), that step is a Newton step, so the first iteration
    // already reports x-convergence. (When any cut step counted as non-Newton, this start ended
    // in singular convergence, code 7, which AED reads as a failed descent.)
    let face = pulled_into_bound_face_optimum();
    let mut x = [1e-12, face[0], face[1]];
    let rep = solve(
        &mut pulled_into_bound(),
        &mut x,
        &[0.0, -10.0, -10.0],
        &[1.0, 10.0, 10.0],
    );
    assert!(
        matches!(
            rep.outcome,
            Outcome::XConvergence | Outcome::BothConvergence
        ),
        "{rep:?}"
    );
    assert_eq!(rep.iterations, 1, "{rep:?}");
    assert_eq!(x[0], 0.0);
}

#[test]
fn linear_convergence_on_a_bound_face_is_not_a_stall() {
    // y = kd + s exp(-n t) with data from kd = -0.3: kd is held on its bound 0, and the face
    // problem in (s, n) has nonzero residuals, so Gauss-Newton converges only linearly there
    // (each step shrinks by ~0.27; 10 iterations, AED's limit, are not enough for N2FB's tests).
    // It must still end with a convergence code on the face, not a stall.
    let t: Vec<f64> = (0..25).map(|i| i as f64 / 24.0).collect();
    let y: Vec<f64> = t.iter().map(|&t| -0.3 + 1.3 * (-2.0 * t).exp()).collect();
    let t2 = t.clone();
    let mut prob = Fun {
        m: 25,
        p: 3,
        r: move |x: &[f64], r: &mut [f64]| {
            for i in 0..25 {
                r[i] = x[0] + x[1] * (-x[2] * t[i]).exp() - y[i];
            }
            true
        },
        j: move |x: &[f64], j: &mut [f64]| {
            for i in 0..25 {
                let e = (-x[2] * t2[i]).exp();
                j[i] = 1.0;
                j[25 + i] = e;
                j[50 + i] = -x[1] * t2[i] * e;
            }
            true
        },
    };
    let mut x = [0.5, 1.0, 1.0];
    let options = Options::default().with_limits(30, 200);
    let rep = Solver::new()
        .solve(
            &mut prob,
            &mut x,
            &[0.0, 0.0, 0.0],
            &[1.0, 10.0, 50.0],
            &options,
        )
        .expect("solve");
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(rep.iterations <= 15, "{rep:?}");
    assert_eq!(x[0], 0.0);
}
