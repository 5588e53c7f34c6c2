//! What an algorithm may do during a trial: the [`Search`] trait.
//!
//! Algorithms are written against this trait rather than against [`crate::TrialContext`]
//! directly, so their control logic can be tested with a scripted fake (see the AED tests).
//! Everything that costs sample-evaluations goes through it, so counting, budgets, the best
//! candidate and the anytime trace live in one place.

use crate::trial::BudgetState;
use crate::{Rows, SearchRng, StopReason};
use bounded_lm::Outcome;

/// Why an algorithm must stop at once. Methods of [`Search`] return it as an error, so an
/// algorithm unwinds with `?`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// A full-data RMSE at or below the target was found.
    Target,
    /// The CPU-time budget is spent.
    CpuBudget,
    /// The sample-evaluation budget is spent.
    EvaluationBudget,
    /// The trial's interrupt flag was raised (see [`crate::TrialContext::set_interrupt`]).
    Interrupted,
    /// The algorithm ended its trial with a failure ([`Search::fail`]): its message is in the
    /// trial's result ([`crate::TrialResult::failure`]).
    Failed,
}

impl From<Stop> for StopReason {
    fn from(s: Stop) -> Self {
        match s {
            Stop::Target => StopReason::Target,
            Stop::CpuBudget => StopReason::CpuBudget,
            Stop::EvaluationBudget => StopReason::EvaluationBudget,
            Stop::Interrupted => StopReason::Interrupted,
            Stop::Failed => StopReason::Failed,
        }
    }
}

/// Limits of one descent (the solver's MXITER and MXFCAL).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DescentLimits {
    /// Iteration limit; reaching it ends the descent with [`Outcome::IterationLimit`].
    pub iterations: usize,
    /// Residual-evaluation limit; reaching it ends the descent with
    /// [`Outcome::EvaluationLimit`].
    pub evaluations: usize,
}

impl Default for DescentLimits {
    /// PORT's defaults: 150 iterations, 200 residual evaluations.
    fn default() -> Self {
        Self {
            iterations: 150,
            evaluations: 200,
        }
    }
}

/// How a descent ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DescentEnd {
    /// The solver ran and returned this outcome (N2FB codes 3 to 10).
    Solver(Outcome),
    /// The residuals or the Jacobian could not be computed at the start (N2FB code 63/65),
    /// typically a random pick whose `d^n` overflows; the candidate is unchanged.
    StartNotEvaluable,
}

/// Result of [`Search::descend`]; the solution itself is written into the caller's `x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Descent {
    /// How the descent ended.
    pub end: DescentEnd,
    /// Solver iterations made.
    pub iterations: usize,
}

impl Descent {
    /// Whether the descent stopped on its iteration limit: what AED reads as "promising".
    pub fn hit_iteration_limit(&self) -> bool {
        self.end == DescentEnd::Solver(Outcome::IterationLimit)
    }

    /// A compact code for counters: N2FB's return code, 63 for an unevaluable start.
    pub fn code(&self) -> u8 {
        match self.end {
            DescentEnd::Solver(o) => o.code(),
            DescentEnd::StartNotEvaluable => 63,
        }
    }
}

/// The operations a search algorithm uses during one trial.
///
/// [`crate::TrialContext`] is the real implementation; it counts every sample-evaluation,
/// checks the target and the budget, and records the best candidate and the anytime trace.
pub trait Search {
    /// Number of free parameters.
    fn dim(&self) -> usize;
    /// Lower bounds of the box.
    fn lower(&self) -> &[f64];
    /// Upper bounds of the box.
    fn upper(&self) -> &[f64];
    /// Size of the full data set.
    fn sample_count(&self) -> usize;
    /// The trial's random number generator (seeded from the trial seed).
    fn rng(&mut self) -> &mut SearchRng;
    /// The paper's `RandomPick`: a uniform candidate in the box (optimiser coordinates).
    fn random_pick(&mut self, x: &mut [f64]);
    /// Full-data RMSE of `x` (`+inf` when unevaluable). Recomputed only when `x` differs from
    /// the last candidate evaluated (or descended to on the full data set). Fails with
    /// [`Stop::Target`] when the RMSE reaches the target, or with a budget stop.
    fn evaluate(&mut self, x: &[f64]) -> Result<f64, Stop>;
    /// [`Search::evaluate`] for a caller that only needs the RMSE when it is below `bound`:
    /// `Some(rmse)` is the exact full-data RMSE (possibly above `bound`), `None` means it is
    /// above `bound` (and above the best so far, so the best candidate and the trace did not
    /// change). The paper's evaluation count, the best candidate, the trace and the target test
    /// are exactly those of [`Search::evaluate`]; the context may stop summing squares early
    /// (counted in `EvalCounts::rmse_rows_computed`). Pass `f64::NEG_INFINITY` when only the
    /// incumbent and the target matter.
    fn evaluate_below(&mut self, x: &[f64], bound: f64) -> Result<Option<f64>, Stop> {
        let _ = bound;
        self.evaluate(x).map(Some)
    }
    /// Bounded least-squares descent (the paper's N2FB) from `x` over `rows`, drawing a fresh
    /// subsample if asked; `x` receives the solution (unchanged when the start is unevaluable).
    /// Fails with a budget stop, which may interrupt the descent.
    fn descend(
        &mut self,
        x: &mut [f64],
        rows: Rows,
        limits: DescentLimits,
    ) -> Result<Descent, Stop>;
    /// Residuals `model_i(x) - y_i` of `x` over the full data set into `r` (length
    /// [`Search::sample_count`]), charged as one residual row per sample, as a descent's
    /// residual evaluation. `Ok(false)` when they cannot be computed (e.g. `d^n` overflows), or
    /// when `x` is not a finite point of the box (callers that take points from outside, such
    /// as the Python binding, check them first to say what was wrong). The default (for test
    /// fakes) computes nothing and returns `Ok(false)`.
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> Result<bool, Stop> {
        let _ = (x, r);
        Ok(false)
    }
    /// Column-major Jacobian of the residuals (`jac[j * m + i] = d r_i / d x_j`, `m` the
    /// [`Search::sample_count`]) at `x` over the full data set, charged as one Jacobian row
    /// per sample, as a descent's Jacobian evaluation. `Ok(false)` as for
    /// [`Search::residuals`]; the default computes nothing and returns `Ok(false)`.
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> Result<bool, Stop> {
        let _ = (x, jac);
        Ok(false)
    }
    /// Fails with the trial's stop once the CPU budget is spent, the trial was interrupted or
    /// an earlier call stopped it; costs no evaluation. For algorithms that work a while
    /// between evaluations (the Python binding calls it on every method). The default never
    /// stops.
    fn check_budget(&mut self) -> Result<(), Stop> {
        Ok(())
    }
    /// The trial's budget (its limits) and how much of it is spent so far: CPU seconds of the
    /// trial's thread (read now) and sample-evaluations. Costs no evaluation. The default (for
    /// test fakes) is an unlimited budget with nothing spent.
    fn budget(&self) -> BudgetState {
        BudgetState::default()
    }
    /// Ends the trial with a failure: records `message` (the first one given) in the trial's
    /// result ([`crate::TrialResult::failure`], stop [`StopReason::Failed`]) and returns
    /// [`Stop::Failed`] for the algorithm to return (`Err(search.fail(...))`); every later call
    /// fails with it. The harness stores no failed trial: it reports the message, naming the
    /// configuration, and skips that configuration's remaining trials. The default (for test
    /// fakes) drops the message.
    fn fail(&mut self, message: String) -> Stop {
        let _ = message;
        Stop::Failed
    }
    /// Adds one to the algorithm-specific counter `name` (reported in
    /// [`crate::TrialResult::counters`]).
    fn count(&mut self, name: &'static str);
    /// Coordinate `i` of a candidate in the problem's natural units (e.g. the exponent `n` when
    /// the optimiser holds `ln(1 + n)`): the identity unless the objective reparameterises.
    /// Monotone increasing; used by SA's paper-style perturbation.
    fn natural_value(&self, i: usize, x: f64) -> f64 {
        let _ = i;
        x
    }
    /// Inverse of [`Search::natural_value`].
    fn optimiser_value(&self, i: usize, v: f64) -> f64 {
        let _ = i;
        v
    }
    /// RMSE of `x` over a fresh random subsample of `k` samples (`+inf` if unevaluable),
    /// charged as `k` RMSE rows. It neither updates the best candidate and the trace nor tests
    /// the target (only full-data RMSEs do); `k` at or above the data size is
    /// [`Search::evaluate`]. Used by SA steps with `sample_size > 0`.
    fn evaluate_subsample(&mut self, x: &[f64], k: usize) -> Result<f64, Stop> {
        let _ = k;
        self.evaluate(x)
    }
}
