//! Tests of the trial context: counting, budgets, the trace, reuse of known RMSEs.

use super::*;
use crate::DsConfig;
use crate::objective::toy::Toy;

fn ds() -> AlgorithmConfig {
    AlgorithmConfig::new(DsConfig::default())
}

#[test]
fn ds_reaches_the_target_on_a_toy_fit() {
    let toy = Toy::new(200, 0.0, 1);
    let budget = Budget {
        cpu_seconds: Some(10.0),
        sample_evaluations: None,
    };
    let r = run_trial(&toy, &ds(), 7, budget, 1e-3);
    assert_eq!(r.stop, StopReason::Target, "{r:?}");
    assert!(r.best_rmse <= 1e-3);
    assert_eq!(r.reached_at, Some(r.ended_at));
    assert_eq!(r.first_reaching(1e-3), r.reached_at);
    // Every DS evaluation is a full-data RMSE of 200 rows.
    let c = r.ended_at.evaluations;
    assert_eq!(c.residual_rows + c.jacobian_rows, 0);
    assert_eq!(c.rmse_rows % 200, 0);
}

#[test]
fn a_raised_interrupt_stops_the_trial_and_a_lowered_one_changes_nothing() {
    let toy = Toy::new(100, 0.05, 2);
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(200_000),
    };
    let raised = Arc::new(AtomicBool::new(true));
    let r = run_trial_interruptible(&toy, &ds(), 11, budget, 0.0, Some(raised));
    assert_eq!(r.stop, StopReason::Interrupted);
    assert_eq!(r.ended_at.evaluations.total(), 0);
    let lowered = Arc::new(AtomicBool::new(false));
    let a = run_trial_interruptible(&toy, &ds(), 11, budget, 0.0, Some(lowered));
    let b = run_trial(&toy, &ds(), 11, budget, 0.0);
    assert_eq!(a.without_clock(), b.without_clock());
}

#[test]
fn same_seed_same_trial_different_seed_different_trial() {
    let toy = Toy::new(100, 0.05, 2);
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(200_000),
    };
    let a = run_trial(&toy, &ds(), 11, budget, 0.0).without_clock();
    let b = run_trial(&toy, &ds(), 11, budget, 0.0).without_clock();
    let c = run_trial(&toy, &ds(), 12, budget, 0.0).without_clock();
    assert_eq!(a, b);
    assert_ne!(a.best_x, c.best_x);
    assert_eq!(a.stop, StopReason::EvaluationBudget);
}

#[test]
fn evaluation_budget_is_never_exceeded_and_trace_is_monotone() {
    let toy = Toy::new(100, 0.05, 3);
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(123_456),
    };
    let r = run_trial(&toy, &ds(), 5, budget, 0.0);
    assert_eq!(r.stop, StopReason::EvaluationBudget);
    let total = r.ended_at.evaluations.total();
    assert!(total <= 123_456 && total > 123_456 - 100, "{total}");
    assert!(r.reached_at.is_none());
    assert!(!r.trace.is_empty());
    for w in r.trace.windows(2) {
        assert!(w[1].rmse < w[0].rmse);
        assert!(w[1].at.evaluations.total() >= w[0].at.evaluations.total());
        assert!(w[1].at.cpu_seconds >= w[0].at.cpu_seconds);
    }
    assert_eq!(r.trace.last().map(|p| p.rmse), Some(r.best_rmse));
}

#[test]
fn cpu_budget_stops_promptly() {
    let toy = Toy::new(2000, 0.05, 4);
    let cutoff = 0.05;
    let budget = Budget {
        cpu_seconds: Some(cutoff),
        sample_evaluations: None,
    };
    let r = run_trial(&toy, &ds(), 9, budget, 0.0);
    assert_eq!(r.stop, StopReason::CpuBudget);
    let overshoot = r.ended_at.cpu_seconds - cutoff;
    // One clock-check interval is a few thousand rows: well under a millisecond even at
    // opt-level 1; allow 5 ms for a loaded machine.
    assert!((0.0..0.005).contains(&overshoot), "overshoot {overshoot} s");
}

/// The toy with every evaluation burning about `ms` of CPU: many expensive calls between
/// clock reads (the old check read the clock every 64 calls, here 64 x 3 ms = 0.19 s).
struct SlowToy {
    toy: Toy,
    ms: f64,
}

impl SlowToy {
    fn burn(&self) {
        let t = ThreadTime::now();
        while t.elapsed().as_secs_f64() < self.ms * 1e-3 {
            std::hint::spin_loop();
        }
    }
}

impl Objective for SlowToy {
    type Workspace = <Toy as Objective>::Workspace;
    fn workspace(&self) -> Self::Workspace {
        self.toy.workspace()
    }
    fn dim(&self) -> usize {
        self.toy.dim()
    }
    fn lower(&self) -> &[f64] {
        self.toy.lower()
    }
    fn upper(&self) -> &[f64] {
        self.toy.upper()
    }
    fn sample_count(&self) -> usize {
        self.toy.sample_count()
    }
    fn rmse(&self, ws: &mut Self::Workspace, x: &[f64]) -> f64 {
        self.burn();
        self.toy.rmse(ws, x)
    }
    fn select(&self, ws: &mut Self::Workspace, rows: Rows, rng: &mut SearchRng) -> usize {
        self.toy.select(ws, rows, rng)
    }
    fn residuals(&self, ws: &mut Self::Workspace, x: &[f64], r: &mut [f64]) -> bool {
        self.burn();
        self.toy.residuals(ws, x, r)
    }
    fn jacobian(&self, ws: &mut Self::Workspace, x: &[f64], jac: &mut [f64]) -> bool {
        self.burn();
        self.toy.jacobian(ws, x, jac)
    }
}

#[test]
fn cpu_budget_holds_when_every_call_is_expensive() {
    let slow = SlowToy {
        toy: Toy::new(30, 0.05, 4),
        ms: 3.0,
    };
    let cutoff = 0.05;
    let budget = Budget {
        cpu_seconds: Some(cutoff),
        sample_evaluations: None,
    };
    for name in ["rpls", "aed", "ds"] {
        let config = AlgorithmConfig::default_for(name).unwrap();
        let r = run_trial(&slow, &config, 3, budget, 0.0);
        assert_eq!(r.stop, StopReason::CpuBudget);
        let overshoot = r.ended_at.cpu_seconds - cutoff;
        // At most the call in progress at the cutoff (3 ms) plus the solver's own work;
        // 15 ms leaves room for a loaded machine.
        assert!(
            (0.0..0.015).contains(&overshoot),
            "{name}: overshoot {overshoot} s"
        );
    }
}

#[test]
fn unchanged_candidates_are_not_re_evaluated() {
    let toy = Toy::new(50, 0.0, 5);
    let mut ctx = TrialContext::new(&toy, 1, Budget::default(), 0.0);
    let x = [1.0, 1.0, 0.0];
    let a = ctx.evaluate(&x).unwrap();
    let b = ctx.evaluate(&x).unwrap();
    assert_eq!(a.to_bits(), b.to_bits());
    assert_eq!(ctx.counts().rmse_rows, 50);
    ctx.evaluate(&[1.0, 1.0, 0.1]).unwrap();
    assert_eq!(ctx.counts().rmse_rows, 100);
    let r = ctx.finish(Ok(()));
    assert_eq!(r.stop, StopReason::Finished);
    assert!(r.counters.contains(&("rmse_reused".to_string(), 1)));
}

#[test]
fn residuals_and_jacobian_are_charged_as_a_descents() {
    let toy = Toy::new(40, 0.0, 5);
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(150),
    };
    let mut ctx = TrialContext::new(&toy, 1, budget, 0.0);
    let x = [1.0, 1.0, 0.0];
    let mut r = vec![0.0; 40];
    assert_eq!(ctx.residuals(&x, &mut r), Ok(true));
    let mut ws = toy.workspace();
    toy.select(&mut ws, Rows::Full, &mut SearchRng::seed_from_u64(0));
    let mut expected = vec![0.0; 40];
    assert!(toy.residuals(&mut ws, &x, &mut expected));
    assert_eq!(r, expected);
    let mut jac = vec![0.0; 40 * 3];
    assert_eq!(ctx.jacobian(&x, &mut jac), Ok(true));
    let mut expected_jac = vec![0.0; 40 * 3];
    assert!(toy.jacobian(&mut ws, &x, &mut expected_jac));
    assert_eq!(jac, expected_jac);
    let c = ctx.counts();
    assert_eq!((c.residual_rows, c.jacobian_rows, c.rmse_rows), (40, 40, 0));
    // The residuals gave the RMSE: evaluating the same point is free.
    let rmse = ctx.evaluate(&x).unwrap();
    let direct = (expected.iter().map(|v| v * v).sum::<f64>() / 40.0).sqrt();
    assert_eq!(rmse.to_bits(), direct.to_bits());
    assert_eq!(ctx.counts().rmse_rows, 0);
    // Points outside the box, non-finite or of the wrong length are not evaluated (and
    // not charged); a wrong buffer length neither.
    for bad in [[1.0, 6.0, 0.0], [f64::NAN, 1.0, 0.0]] {
        assert_eq!(ctx.residuals(&bad, &mut r), Ok(false));
        assert_eq!(ctx.jacobian(&bad, &mut jac), Ok(false));
    }
    assert_eq!(ctx.residuals(&x[..2], &mut r), Ok(false));
    assert_eq!(ctx.jacobian(&x, &mut jac[..10]), Ok(false));
    assert_eq!(ctx.counts().total(), 80);
    // 80 + 40 = 120 fits the budget of 150; another 40 would not, and the stop sticks.
    assert_eq!(ctx.residuals(&x, &mut r), Ok(true));
    assert_eq!(ctx.jacobian(&x, &mut jac), Err(Stop::EvaluationBudget));
    assert_eq!(ctx.residuals(&x, &mut r), Err(Stop::EvaluationBudget));
    assert_eq!(ctx.counts().total(), 120);
    assert_eq!(ctx.check_budget(), Err(Stop::EvaluationBudget));
    let result = ctx.finish(Err(Stop::EvaluationBudget));
    assert_eq!(result.best_rmse.to_bits(), direct.to_bits());
}

#[test]
fn check_budget_notices_the_cpu_cutoff_without_evaluating() {
    let toy = Toy::new(10, 0.0, 5);
    let budget = Budget {
        cpu_seconds: Some(0.01),
        sample_evaluations: None,
    };
    let mut ctx = TrialContext::new(&toy, 1, budget, 0.0);
    assert_eq!(ctx.check_budget(), Ok(()));
    let t = ThreadTime::now();
    while t.elapsed().as_secs_f64() < 0.02 {
        std::hint::spin_loop();
    }
    assert_eq!(ctx.check_budget(), Err(Stop::CpuBudget));
    assert_eq!(ctx.counts().total(), 0);
    assert_eq!(ctx.finish(Err(Stop::CpuBudget)).stop, StopReason::CpuBudget);
}

#[test]
fn invalid_configuration_ends_the_trial_at_once() {
    let toy = Toy::new(50, 0.0, 5);
    let bad = AlgorithmConfig::new(DsConfig {
        rtol: -1.0,
        ..DsConfig::default()
    });
    assert_eq!(bad.validate().unwrap_err().field, "rtol");
    let r = run_trial(&toy, &bad, 1, Budget::default(), 0.0);
    assert_eq!(r.stop, StopReason::Finished);
    assert_eq!(r.ended_at.evaluations.total(), 0);
}
