//! Robustness: no premature singular convergence while the gradient is large, the caller's
//! stop hook, and the MGH collection (no success code on a wrong answer).

mod common;

use bounded_lm::problems::mgh::{Kind, Mgh};
use bounded_lm::{Options, Outcome, Problem, SecantScaling, Solver};
use common::mgh_run;

const INF: f64 = f64::INFINITY;

/// `y = a exp(b t)` fitted from a start with a steep exponential: the Jacobian columns are
/// ~1e13, so a step of scaled length 1 (N2FB's LMAX0 and LMAXS) is a round-off change of x and
/// predicts no relative reduction, although the gradient is huge.
struct SteepExp;
impl Problem for SteepExp {
    fn residual_count(&self) -> usize {
        12
    }
    fn parameter_count(&self) -> usize {
        2
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        for (i, ri) in r.iter_mut().enumerate() {
            let t = i as f64 / 11.0;
            *ri = x[0] * (x[1] * t).exp() - 2.0 * (0.5 * t).exp();
        }
        r.iter().all(|v| v.is_finite())
    }
    fn jacobian(&mut self, x: &[f64], j: &mut [f64]) -> bool {
        for i in 0..12 {
            let t = i as f64 / 11.0;
            let e = (x[1] * t).exp();
            j[i] = e;
            j[12 + i] = x[0] * t * e;
        }
        true
    }
}

fn gradient_norm(prob: &mut impl Problem, x: &[f64]) -> f64 {
    let (m, n) = (prob.residual_count(), prob.parameter_count());
    let (mut r, mut j) = (vec![0.0; m], vec![0.0; m * n]);
    prob.residuals(x, &mut r);
    prob.jacobian(x, &mut j);
    (0..n)
        .map(|k| (0..m).map(|i| j[k * m + i] * r[i]).sum::<f64>().powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn no_singular_convergence_while_the_gradient_is_large() {
    let mut x = [1.0, 30.0];
    let g0 = gradient_norm(&mut SteepExp, &x);
    let rep = Solver::new()
        .solve(
            &mut SteepExp,
            &mut x,
            &[-INF; 2],
            &[INF; 2],
            &Options::default(),
        )
        .unwrap();
    let g = gradient_norm(&mut SteepExp, &x);
    if matches!(
        rep.outcome,
        Outcome::SingularConvergence | Outcome::FalseConvergence
    ) {
        assert!(g < 1e-6 * g0, "{rep:?} at {x:?}: gradient {g} (start {g0})");
    }
    assert!(rep.outcome.is_success(), "{rep:?} {x:?}");
    assert!(
        (x[0] - 2.0).abs() < 1e-6 && (x[1] - 0.5).abs() < 1e-6,
        "{x:?}"
    );

    // MGH's Jennrich-Sampson from 10 x0 (f = 2.8e34): this returned singular convergence after
    // one iteration and 2 evaluations, at the start, with a gradient of ~1e36.
    // With the default options (N2FB's LMAX0 = 1, a round-off step there) it ends with an
    // honest failure code; with the first radius lifted above round-off it is solved.
    let mut p = Mgh::new(Kind::JennrichSampson, 2, 10);
    let mut x = p.start(10.0);
    let rep = Solver::new()
        .solve(&mut p, &mut x, &[-INF; 2], &[INF; 2], &Options::default())
        .unwrap();
    assert!(!rep.outcome.is_success() || rep.f < 1e3, "{rep:?}");
    let mut lifted = Options::default();
    lifted.safeguards.lift_round_off_radius = true;
    let mut x = p.start(10.0);
    let rep = Solver::new()
        .solve(&mut p, &mut x, &[-INF; 2], &[INF; 2], &lifted)
        .unwrap();
    assert!(rep.iterations > 1 && rep.f < 1e3, "{rep:?}");
}

/// N2FB's own singular-convergence test (a test step of scaled length LMAXS alone, as the
/// searches run it) fires at a round-off step far from a stationary point; the default's test
/// step of at least `||D x||` does not (the steep exponential is then solved, see above).
#[test]
fn the_singular_test_step_at_least_x_is_what_stops_code_7_at_the_start() {
    code_7_at_the_start_only_with_n2fb_test_step(&mut SteepExp, &[1.0, 30.0]);
    let mut jennrich = Mgh::new(Kind::JennrichSampson, 2, 10);
    let x0 = jennrich.start(10.0);
    code_7_at_the_start_only_with_n2fb_test_step(&mut jennrich, &x0);
}

fn code_7_at_the_start_only_with_n2fb_test_step(prob: &mut impl Problem, x0: &[f64]) {
    let mut n2fb_test = Options::default();
    n2fb_test.safeguards.singular_radius_at_least_x = false;
    let mut solve = |x: &mut [f64], options: &Options| {
        let n = x.len();
        Solver::new()
            .solve(prob, x, &vec![-INF; n], &vec![INF; n], options)
            .unwrap()
    };
    let mut plain_x = x0.to_vec();
    let plain = solve(&mut plain_x, &n2fb_test);
    let mut x = x0.to_vec();
    let default = solve(&mut x, &Options::default());
    assert_eq!(plain.outcome, Outcome::SingularConvergence, "{plain:?}");
    assert!(plain.residual_evaluations <= 3, "{plain:?}");
    let (g0, g) = (gradient_norm(prob, x0), gradient_norm(prob, &plain_x));
    assert!(
        g > 1e-3 * g0,
        "{plain:?} at {plain_x:?}: gradient {g} (start {g0})"
    );
    assert_ne!(default.outcome, Outcome::SingularConvergence, "{default:?}");
}

/// Rosenbrock's residuals `(10 (x2 - x1^2), 1 - x1)`.
fn rosenbrock(x: &[f64], r: &mut [f64]) -> bool {
    r[0] = 10.0 * (x[1] - x[0] * x[0]);
    r[1] = 1.0 - x[0];
    true
}

/// Rosenbrock's Jacobian (column-major).
fn rosenbrock_jacobian(x: &[f64], j: &mut [f64]) -> bool {
    j.copy_from_slice(&[-20.0 * x[0], -1.0, 10.0, 0.0]);
    true
}

/// Solves a two-parameter problem without bounds from `x` with the default options.
fn solve_unbounded(prob: &mut impl Problem, x: &mut [f64; 2]) -> bounded_lm::Report {
    Solver::new()
        .solve(prob, x, &[-INF; 2], &[INF; 2], &Options::default())
        .unwrap()
}

/// Stops after `limit` calls of the hook.
struct Stopping {
    calls: usize,
    limit: usize,
}
impl Problem for Stopping {
    fn residual_count(&self) -> usize {
        2
    }
    fn parameter_count(&self) -> usize {
        2
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        rosenbrock(x, r)
    }
    fn jacobian(&mut self, x: &[f64], j: &mut [f64]) -> bool {
        rosenbrock_jacobian(x, j)
    }
    fn should_stop(&mut self) -> bool {
        self.calls += 1;
        self.calls > self.limit
    }
}

#[test]
fn should_stop_interrupts_between_iterations() {
    let mut prob = Stopping { calls: 0, limit: 3 };
    let mut x = [-1.2, 1.0];
    let rep = solve_unbounded(&mut prob, &mut x);
    assert_eq!(rep.outcome, Outcome::Interrupted);
    assert_eq!(rep.outcome.code(), 11);
    assert!(!rep.outcome.is_success());
    assert_eq!(rep.iterations, 3);
    assert_eq!(prob.calls, 4, "asked once per iteration");
    // x is the last accepted point and f belongs to it.
    let mut r = [0.0; 2];
    prob.residuals(&x, &mut r);
    assert_eq!(rep.f, 0.5 * (r[0] * r[0] + r[1] * r[1]));
    // Never stopping changes nothing.
    let mut prob = Stopping {
        calls: 0,
        limit: usize::MAX,
    };
    let mut x = [-1.2, 1.0];
    let rep = solve_unbounded(&mut prob, &mut x);
    assert!(rep.outcome.is_success());
    assert_eq!(prob.calls, rep.iterations);
}

/// A linear least-squares problem with `p` parameters (`r = A x - b`, `A` a dense,
/// well-conditioned `2p x p` matrix) whose stop hook counts its calls and says stop from the
/// call numbered `stop_at` on.
struct LargeLinear {
    p: usize,
    a: Vec<f64>,
    calls: usize,
    stop_at: usize,
}
impl LargeLinear {
    fn new(p: usize, stop_at: usize) -> Self {
        let m = 2 * p;
        // Column-major; a dominant diagonal keeps it well conditioned.
        let a = (0..m * p)
            .map(|k| {
                let (i, j) = (k % m, k / m);
                if i == j {
                    4.0
                } else {
                    ((i * 7 + j * 13) % 11) as f64 / 50.0
                }
            })
            .collect();
        Self {
            p,
            a,
            calls: 0,
            stop_at,
        }
    }
}
impl Problem for LargeLinear {
    fn residual_count(&self) -> usize {
        2 * self.p
    }
    fn parameter_count(&self) -> usize {
        self.p
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        let m = 2 * self.p;
        for (i, ri) in r.iter_mut().enumerate() {
            *ri = (0..self.p).map(|j| self.a[j * m + i] * x[j]).sum::<f64>() - 1.0;
        }
        true
    }
    fn jacobian(&mut self, _x: &[f64], j: &mut [f64]) -> bool {
        j.copy_from_slice(&self.a);
        true
    }
    fn should_stop(&mut self) -> bool {
        self.calls += 1;
        self.calls >= self.stop_at
    }
}

/// A large model asks the stop hook while it computes a step (a trust-region solve of 200 free
/// variables is millions of flops), so a CPU cutoff is noticed before the step's evaluation; a
/// small model asks only once per iteration, so its steps pay nothing for it.
#[test]
fn a_large_model_asks_the_stop_hook_during_the_step() {
    let solve = |prob: &mut LargeLinear| {
        let p = prob.p;
        let mut x = vec![100.0; p];
        let (lo, hi) = (vec![-1e3; p], vec![1e3; p]);
        Solver::new()
            .solve(prob, &mut x, &lo, &hi, &Options::default())
            .unwrap()
    };
    // The first question comes before the first Jacobian; the second, inside the first step.
    let mut large = LargeLinear::new(200, 2);
    let rep = solve(&mut large);
    assert_eq!(rep.outcome, Outcome::Interrupted, "{rep:?}");
    assert_eq!(
        rep.residual_evaluations, 1,
        "stopped before evaluating the first step"
    );
    // Never stopping: the questions inside steps change nothing of the solution.
    let mut large = LargeLinear::new(200, usize::MAX);
    let rep = solve(&mut large);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert!(
        large.calls > rep.iterations,
        "asked during steps too: {} calls",
        large.calls
    );
    let mut small = LargeLinear::new(5, usize::MAX);
    let rep = solve(&mut small);
    assert!(rep.outcome.is_success(), "{rep:?}");
    assert_eq!(small.calls, rep.iterations, "asked once per iteration only");
}

/// Rosenbrock whose budget runs out after `budget` residual evaluations: from then on every
/// evaluation fails and the stop hook says stop, as the search layer's trial context does when
/// its CPU cutoff passes in the middle of an iteration.
struct Refusing {
    evaluations: usize,
    budget: usize,
    refused: usize,
}
impl Problem for Refusing {
    fn residual_count(&self) -> usize {
        2
    }
    fn parameter_count(&self) -> usize {
        2
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        self.evaluations += 1;
        if self.evaluations > self.budget {
            self.refused += 1;
            return false;
        }
        rosenbrock(x, r)
    }
    fn jacobian(&mut self, x: &[f64], j: &mut [f64]) -> bool {
        rosenbrock_jacobian(x, j)
    }
    fn should_stop(&mut self) -> bool {
        self.refused > 0
    }
}

/// A failed evaluation asks the stop hook at once: the solver does not shrink the radius
/// through a series of refused evaluations (each a new step computation) down to false
/// convergence.
#[test]
fn a_refused_evaluation_ends_the_solve_when_the_caller_says_stop() {
    for budget in [1, 5, 12] {
        let mut prob = Refusing {
            evaluations: 0,
            budget,
            refused: 0,
        };
        let mut x = [-1.2, 1.0];
        let rep = solve_unbounded(&mut prob, &mut x);
        assert_eq!(
            rep.outcome,
            Outcome::Interrupted,
            "budget {budget}: {rep:?}"
        );
        assert_eq!(
            prob.refused, 1,
            "budget {budget}: stopped at the first refusal"
        );
        // x and f are the last accepted point's.
        let mut r = [0.0; 2];
        prob.budget = usize::MAX;
        prob.residuals(&x, &mut r);
        assert_eq!(rep.f, 0.5 * (r[0] * r[0] + r[1] * r[1]));
    }
}

/// More parameters than residuals (a 25-row subsample of a 50-lobe model has 251): the
/// Gauss-Newton model is singular and the trust-region step is solved in its dual form. The
/// solve must still make progress and end with an honest code, never a success claim at a point
/// where the gradient is large.
struct Wide {
    m: usize,
    p: usize,
}
impl Wide {
    fn entry(&self, i: usize, j: usize) -> f64 {
        // A fixed, well-spread matrix: no two columns parallel.
        (((i * 7 + j * 13) % 17) as f64 - 8.0) / 8.0 + if i == j % self.m { 2.0 } else { 0.0 }
    }
}
impl Problem for Wide {
    fn residual_count(&self) -> usize {
        self.m
    }
    fn parameter_count(&self) -> usize {
        self.p
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        // r_i = sum_j A_ij x_j + 0.1 x_i^2 (i < m) - 1: mildly nonlinear, zero residual reachable.
        for (i, ri) in r.iter_mut().enumerate() {
            let lin: f64 = (0..self.p).map(|j| self.entry(i, j) * x[j]).sum();
            *ri = lin + 0.1 * x[i] * x[i] - 1.0;
        }
        true
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        for j in 0..self.p {
            for i in 0..self.m {
                jac[j * self.m + i] = self.entry(i, j) + if i == j { 0.2 * x[i] } else { 0.0 };
            }
        }
        true
    }
}

#[test]
fn fewer_residuals_than_parameters_reach_a_zero_residual() {
    for (m, p) in [(3, 8), (25, 251)] {
        let mut prob = Wide { m, p };
        let mut x = vec![0.5; p];
        let (lo, hi) = (vec![-10.0; p], vec![10.0; p]);
        let rep = Solver::new()
            .solve(&mut prob, &mut x, &lo, &hi, &Options::default())
            .unwrap();
        assert!(rep.f < 1e-12, "m {m} p {p}: {rep:?}");
        assert!(rep.outcome.is_success(), "m {m} p {p}: {rep:?}");
    }
}

/// MGH's Brown and Dennis function (n = 4, m = 20; f* = 0.5 * 85822.2 = 42911.1) is a large
/// residual problem whose Gauss-Newton diagonal misses most of the curvature in x3 and x4: with
/// the Jacobian column norms as the scaling the trust region lets the steps zigzag in x3, x4
/// while x1, x2 creep (150 iterations, the limit, without the secant scaling). N2FB's scaling,
/// with the diagonal of the secant term S, fixes the creep, and the augmented model gives the
/// superlinear end game of a large-residual problem: with N2FB's configuration
/// ([`Options::n2fb`]) and with the defaults (the augmented model allowed after 2p secant
/// updates) both starts take at most 30 iterations (measured 21 / 24 and 23 / 27), and both end
/// with relative function convergence (before the augmented model's NREDUC counted, the
/// defaults ended 10 x0 with singular convergence at the minimum). The Gauss-Newton model with
/// the secant scaling still reaches the minimum, in at most 90 iterations (measured 71 and 81).
#[test]
fn secant_scaling_solves_brown_and_dennis() {
    let f_star = 42_911.100_8;
    let gauss_newton = Options::gauss_newton();
    for factor in [1.0, 10.0] {
        for (options, max_iterations) in [
            (Options::n2fb(), 30),
            (Options::default(), 30),
            (gauss_newton.clone(), 90),
        ] {
            let mut p = Mgh::new(Kind::BrownDennis, 4, 20);
            let mut x = p.start(factor);
            let rep = Solver::new()
                .solve(&mut p, &mut x, &[-INF; 4], &[INF; 4], &options)
                .unwrap();
            let case = format!("{factor} x0, {:?}: {rep:?}", options.model);
            assert_eq!(rep.outcome, Outcome::RelativeFunctionConvergence, "{case}");
            assert!(rep.iterations <= max_iterations, "{case}");
            assert!((rep.f - f_star).abs() <= 1e-6 * f_star, "{case}");
        }
    }
}

/// MGH with the Gauss-Newton model with and without the secant
/// term in the scaling (both with the second-order correction), and with N2FB's configuration
/// (without it): at least 71, 65 and 69 of the 78 unbounded runs solved (70, 66 and 69 without
/// the correction), never with a success code on a wrong unbounded answer (the defaults are
/// checked by `mgh_collection` in tests/mgh.rs).
#[test]
fn mgh_collection_other_scalings() {
    let gauss_newton = Options::gauss_newton();
    let mut no_secant = gauss_newton.clone();
    no_secant.scaling.secant = SecantScaling::Off;
    for (name, options, at_least) in [
        ("gauss-newton", gauss_newton, 71),
        ("no secant", no_secant, 65),
        ("n2fb", Options::n2fb(), 69),
    ] {
        let runs = mgh_run::run_all(&options);
        let summary = mgh_run::summary(&runs);
        let table = mgh_run::table(&runs);
        for r in runs.iter().filter(|r| r.bound.is_none()) {
            assert!(
                !r.wrong_success(),
                "{name}: success code on a wrong answer: {r:?}\n{table}"
            );
        }
        let solved = runs
            .iter()
            .filter(|r| r.bound.is_none() && r.solved)
            .count();
        assert!(solved >= at_least, "{name}: {summary}\n{table}");
    }
}

/// The scaling's decay (`Scaling::decay`, NL2SOL's DFAC) trades one kind of problem for
/// another, as docs/solver.md says. With MINPACK's non-decreasing scaling (1) Penalty II
/// (n = 10), a curved valley, is solved from x0 where N2FB's 0.6 creeps to the iteration limit;
/// but an exponential started steep (Jacobian columns ~1e13 at the start, ~1 at the solution)
/// is solved only when `D` may fall with its columns. Both without the second-order
/// correction, which solves Penalty II from x0 with 0.6 on its own
/// (`second_order_correction_follows_curved_valleys`).
#[test]
fn scaling_decay_trades_curved_valleys_for_steep_starts() {
    let mut n2fb_decay = Options::default();
    n2fb_decay.safeguards.second_order_correction = false;
    let mut minpack = n2fb_decay.clone();
    minpack.scaling.decay = 1.0;
    let penalty = |options: &Options| {
        let mut p = Mgh::new(Kind::PenaltyII, 10, 20);
        let mut x = p.start(1.0);
        let rep = Solver::new()
            .solve(&mut p, &mut x, &[-INF; 10], &[INF; 10], options)
            .unwrap();
        let f_star = p.f_minima()[0];
        (rep, (rep.f - f_star).abs() <= 1e-5 * f_star)
    };
    let (rep, solved) = penalty(&minpack);
    assert!(solved && rep.outcome.is_success(), "{rep:?}");
    let (rep, solved) = penalty(&n2fb_decay);
    assert!(!solved && rep.outcome == Outcome::IterationLimit, "{rep:?}");

    let steep = |options: &Options| {
        let mut x = [1.0, 30.0];
        let rep = Solver::new()
            .solve(&mut SteepExp, &mut x, &[-INF; 2], &[INF; 2], options)
            .unwrap();
        (rep, (x[0] - 2.0).abs() < 1e-6 && (x[1] - 0.5).abs() < 1e-6)
    };
    let (rep, solved) = steep(&n2fb_decay);
    assert!(solved && rep.outcome.is_success(), "{rep:?}");
    let (rep, solved) = steep(&minpack);
    assert!(
        !solved && rep.outcome == Outcome::SingularConvergence,
        "{rep:?}"
    );
}

/// The second-order correction of a rejected step (`Safeguards::second_order_correction`) lets the
/// steps follow a curved valley where the quadratic models see only its tangent: MGH's Penalty II
/// (n = 10) from x0 and Osborne 1 from 10 x0 reach their listed minima with a success code
/// (measured: 107 and 62 iterations), and creep to the iteration limit without it (f 1.6e-3 and
/// 0.31 relative above the minimum). The correction costs residual evaluations but no
/// Jacobians; they count against the budget (200 by default; a budget of 40 ends with code 9
/// after at most 40).
#[test]
fn second_order_correction_follows_curved_valleys() {
    let mut without = Options::default();
    without.safeguards.second_order_correction = false;
    for (kind, n, m, factor) in [
        (Kind::PenaltyII, 10, 20, 1.0),
        (Kind::Osborne1, 5, 33, 10.0),
    ] {
        let solve = |options: &Options| {
            let mut p = Mgh::new(kind, n, m);
            let mut x = p.start(factor);
            let rep = Solver::new()
                .solve(&mut p, &mut x, &vec![-INF; n], &vec![INF; n], options)
                .unwrap();
            (rep, p.reaches_minimum(rep.f))
        };
        let (rep, solved) = solve(&Options::default());
        assert!(solved && rep.outcome.is_success(), "{kind:?}: {rep:?}");
        assert!(
            rep.residual_evaluations <= 200 && rep.iterations <= 120,
            "{kind:?}: {rep:?}"
        );
        let (rep, solved) = solve(&without);
        assert!(
            !solved && rep.outcome == Outcome::IterationLimit,
            "{kind:?}: {rep:?}"
        );
        // The corrections' evaluations count against the budget like any other.
        let (rep, _) = solve(&Options::default().with_limits(150, 40));
        assert_eq!(rep.outcome, Outcome::EvaluationLimit, "{kind:?}: {rep:?}");
        assert!(rep.residual_evaluations <= 40, "{kind:?}: {rep:?}");
    }
}

/// An out-of-range scaling decay is refused with an error naming the option.
#[test]
fn scaling_decay_outside_zero_to_one_is_refused() {
    for decay in [0.0, -0.5, 1.5, f64::NAN] {
        let mut options = Options::default();
        options.scaling.decay = decay;
        let mut x = [1.0, 30.0];
        let err = Solver::new()
            .solve(&mut SteepExp, &mut x, &[-INF; 2], &[INF; 2], &options)
            .unwrap_err();
        assert!(err.to_string().contains("scaling.decay"), "{decay}: {err}");
    }
}
