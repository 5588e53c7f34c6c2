//! What a trial is given (budget, target) and what it returns (result, anytime trace).
//!
//! These types are the contract between the search algorithms and the harness: the harness
//! serialises [`TrialResult`] as one JSON line per trial and derives every statistic from it.

use serde::{Deserialize, Serialize};

/// Resources a trial may spend before it is stopped (censored). `None` means unlimited; at
/// least one limit should be set for targets that may be unreachable.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Budget {
    /// Cutoff in CPU seconds of the thread running the trial.
    pub cpu_seconds: Option<f64>,
    /// Cutoff in sample-evaluations ([`EvalCounts::total`]).
    pub sample_evaluations: Option<u64>,
}

/// A trial's budget as the algorithm sees it during the trial ([`crate::Search::budget`]): the
/// limits and what is spent so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BudgetState {
    /// The trial's limits.
    pub limits: Budget,
    /// CPU seconds of the trial's thread spent so far.
    pub cpu_seconds: f64,
    /// Sample-evaluations spent so far ([`EvalCounts::total`]).
    pub evaluations: u64,
}

impl BudgetState {
    /// CPU seconds left (`None`: no CPU limit).
    pub fn cpu_seconds_left(&self) -> Option<f64> {
        self.limits
            .cpu_seconds
            .map(|limit| (limit - self.cpu_seconds).max(0.0))
    }

    /// Sample-evaluations left (`None`: no evaluation limit).
    pub fn evaluations_left(&self) -> Option<u64> {
        self.limits
            .sample_evaluations
            .map(|limit| limit.saturating_sub(self.evaluations))
    }
}

/// Evaluation counts in sample-evaluations: one model value at one sample is one unit, so run
/// lengths compare across algorithms, subsample sizes and machines.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct EvalCounts {
    /// Residual rows computed for descents (and simplex/annealing steps on subsamples).
    pub residual_rows: u64,
    /// Jacobian rows computed (analytic or finite-difference), counted apart from residuals.
    pub jacobian_rows: u64,
    /// Rows of RMSE evaluations of candidates (full data, or SA's subsamples), the paper's
    /// count: a full-data RMSE counts every sample even when it was cut short (see
    /// [`EvalCounts::rmse_rows_computed`]). Budgets and the run lengths of figures use it.
    pub rmse_rows: u64,
    /// Rows of RMSE evaluations actually computed: fewer than [`EvalCounts::rmse_rows`] when a
    /// full-data RMSE only had to be compared with a bound (the target, the incumbent's RMSE)
    /// and the partial sum of squares passed it early. 0 in results written before it existed.
    #[serde(default)]
    pub rmse_rows_computed: u64,
}

impl EvalCounts {
    /// All sample-evaluations in the paper's count: residual + Jacobian + RMSE rows (saturating
    /// at `u64::MAX`: counts read from a results file may be anything).
    pub fn total(&self) -> u64 {
        self.residual_rows
            .saturating_add(self.jacobian_rows)
            .saturating_add(self.rmse_rows)
    }

    /// Sample-evaluations actually computed: residual + Jacobian + computed RMSE rows
    /// (saturating, as [`EvalCounts::total`]).
    pub fn total_computed(&self) -> u64 {
        self.residual_rows
            .saturating_add(self.jacobian_rows)
            .saturating_add(self.rmse_rows_computed)
    }
}

/// A point in a trial's life, measured three ways.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stamp {
    /// CPU seconds of the worker thread since the trial started.
    pub cpu_seconds: f64,
    /// Wall-clock seconds since the trial started.
    pub wall_seconds: f64,
    /// Sample-evaluations spent so far.
    pub evaluations: EvalCounts,
}

/// One improvement of the best full-data RMSE.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TracePoint {
    /// When the improvement happened.
    pub at: Stamp,
    /// The new best full-data RMSE.
    pub rmse: f64,
}

/// Why a trial ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The full-data RMSE reached the target.
    Target,
    /// The CPU-time cutoff was spent (censored run).
    CpuBudget,
    /// The sample-evaluation budget was spent (censored run).
    EvaluationBudget,
    /// The algorithm ended by itself without reaching the target (e.g. DS with restarts off).
    Finished,
    /// Stopped from outside (Ctrl-C in a caller) before the target or a budget: the result is
    /// incomplete and the harness never stores it.
    Interrupted,
    /// The algorithm failed ([`crate::Search::fail`]; [`TrialResult::failure`] says why): the
    /// harness never stores it and reports the failure.
    Failed,
}

/// Everything a trial reports.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrialResult {
    /// Why the trial stopped.
    pub stop: StopReason,
    /// When the target was reached, if it was.
    pub reached_at: Option<Stamp>,
    /// When the trial stopped (equals `reached_at` on success).
    pub ended_at: Stamp,
    /// Best full-data RMSE seen.
    pub best_rmse: f64,
    /// The best candidate in the optimiser's coordinates (free parameters only).
    pub best_x: Vec<f64>,
    /// Anytime trace: one entry per improvement of the best full-data RMSE, in time order.
    pub trace: Vec<TracePoint>,
    /// Algorithm-specific counters (restarts, descents by outcome, ...), for diagnostics.
    pub counters: Vec<(String, u64)>,
    /// Why the algorithm failed (stop [`StopReason::Failed`]); `None` otherwise, and then not
    /// written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

impl TrialResult {
    /// Whether the target was reached.
    pub fn reached(&self) -> bool {
        self.reached_at.is_some()
    }

    /// The result with every clock reading (CPU and wall seconds) zeroed: what two trials with
    /// the same seed must agree on bit for bit (evaluation counts, candidates, traces).
    pub fn without_clock(mut self) -> TrialResult {
        fn zero(s: &mut Stamp) {
            s.cpu_seconds = 0.0;
            s.wall_seconds = 0.0;
        }
        zero(&mut self.ended_at);
        if let Some(s) = self.reached_at.as_mut() {
            zero(s);
        }
        self.trace.iter_mut().for_each(|p| zero(&mut p.at));
        self
    }

    /// The first stamp at which the best RMSE was at or below `target`, from the trace. Lets
    /// the harness derive time-to-target for any target at least as loose as the trial's own.
    pub fn first_reaching(&self, target: f64) -> Option<Stamp> {
        self.trace.iter().find(|p| p.rmse <= target).map(|p| p.at)
    }
}

#[cfg(test)]
mod tests {
    use super::EvalCounts;

    /// Counts come from results files too: totals past u64::MAX saturate instead of
    /// overflowing (a panic in debug builds, found by crates/analysis/tests/fuzz_results.rs).
    #[test]
    fn totals_saturate() {
        let c = EvalCounts {
            residual_rows: u64::MAX,
            jacobian_rows: 2,
            rmse_rows: 3,
            rmse_rows_computed: u64::MAX,
        };
        assert_eq!(c.total(), u64::MAX);
        assert_eq!(c.total_computed(), u64::MAX);
    }
}
