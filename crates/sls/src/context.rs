//! The trial context: the one place where evaluations are counted, budgets and the target are
//! checked, and the best candidate and the anytime trace are kept (argmin's `Problem` wrapper and
//! `Executor` in one).

use crate::objective::{Objective, Rows};
use crate::search::{Descent, DescentEnd, DescentLimits, Search, Stop};
use crate::trial::{Budget, BudgetState, EvalCounts, Stamp, StopReason, TracePoint, TrialResult};
use crate::{AlgorithmConfig, DescentModel, SearchRng};
use bounded_lm::{Options, Problem, SolveError, Solver};
use cpu_time::ThreadTime;
use rand::SeedableRng;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// When the CPU clock is read. A thread's CPU time can only advance as fast as wall time, so
/// after a read that left `R` seconds of the CPU budget, the budget cannot be spent before `R`
/// wall seconds have passed. Every charge and every [`Problem::should_stop`] reads the wall clock
/// (`Instant`, a vDSO call of a few tens of nanoseconds, negligible next to even a 25-row
/// evaluation) and reads the thread's CPU clock (a system call, about 0.4 us) only once that
/// much wall time has passed (times [`CLOCK_SLACK`], for the two clocks' granularity), or at
/// least every [`CLOCK_MAX_INTERVAL`] seconds. So the CPU cutoff is noticed at the first call
/// after it, whatever the model size or the work between calls, while the CPU clock is read a
/// handful of times per trial plus once per call only in the last stretch before the cutoff.
/// Counting rows or calls instead would let a few slow solver steps of a many-lobe model pass
/// unchecked (64 steps of a 16-lobe model are 3 s over a 0.05 s cutoff).
const CLOCK_SLACK: f64 = 0.95;
/// The longest wall-time interval between two reads of the CPU clock, in seconds.
const CLOCK_MAX_INTERVAL: f64 = 0.05;

/// Which counter a charge goes to.
#[derive(Clone, Copy)]
enum Kind {
    Residual,
    Jacobian,
    Rmse,
}

/// Counting, clocks and budget checks.
struct Meter {
    counts: EvalCounts,
    budget: Budget,
    cpu: ThreadTime,
    wall: Instant,
    /// Wall time of the last CPU-clock read.
    last_read: Instant,
    /// Wall seconds after `last_read` before the CPU clock must be read again.
    next_read: f64,
    stopped: Option<Stop>,
    /// Raised from another thread to stop the trial (a caller's Ctrl-C).
    interrupt: Option<Arc<AtomicBool>>,
}

impl Meter {
    fn new(budget: Budget) -> Self {
        Self {
            counts: EvalCounts::default(),
            budget,
            cpu: ThreadTime::now(),
            wall: Instant::now(),
            last_read: Instant::now(),
            next_read: budget
                .cpu_seconds
                .map_or(f64::INFINITY, |c| (c * CLOCK_SLACK).min(CLOCK_MAX_INTERVAL)),
            stopped: None,
            interrupt: None,
        }
    }

    /// Admits `rows` sample-evaluations of `kind` and counts them, or refuses (and remembers the
    /// stop) when they would exceed the evaluation budget or the CPU time is spent. A trial
    /// therefore never exceeds its evaluation budget.
    fn charge(&mut self, kind: Kind, rows: usize) -> Result<(), Stop> {
        if let Some(stop) = self.stopped {
            return Err(stop);
        }
        let rows = rows as u64;
        if let Some(limit) = self.budget.sample_evaluations
            && self.counts.total() + rows > limit
        {
            return Err(self.stop(Stop::EvaluationBudget));
        }
        self.poll_clock()?;
        match kind {
            Kind::Residual => self.counts.residual_rows += rows,
            Kind::Jacobian => self.counts.jacobian_rows += rows,
            Kind::Rmse => self.counts.rmse_rows += rows,
        }
        Ok(())
    }

    /// Stops if the CPU cutoff is spent, reading the CPU clock only when the wall time since the
    /// last read says it may be (see [`CLOCK_SLACK`]).
    fn poll_clock(&mut self) -> Result<(), Stop> {
        if let Some(stop) = self.stopped {
            return Err(stop);
        }
        // One relaxed load per call: negligible next to any evaluation.
        if self
            .interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
        {
            return Err(self.stop(Stop::Interrupted));
        }
        if self.budget.cpu_seconds.is_some()
            && self.last_read.elapsed().as_secs_f64() >= self.next_read
        {
            self.check_clock()?;
        }
        Ok(())
    }

    /// Reads the CPU clock and stops if the cutoff is spent.
    fn check_clock(&mut self) -> Result<(), Stop> {
        let Some(limit) = self.budget.cpu_seconds else {
            return Ok(());
        };
        self.last_read = Instant::now();
        let left = limit - self.cpu.elapsed().as_secs_f64();
        if left <= 0.0 {
            return Err(self.stop(Stop::CpuBudget));
        }
        self.next_read = (left * CLOCK_SLACK).min(CLOCK_MAX_INTERVAL);
        Ok(())
    }

    fn stop(&mut self, stop: Stop) -> Stop {
        self.stopped = Some(stop);
        stop
    }

    fn stamp(&self) -> Stamp {
        Stamp {
            cpu_seconds: self.cpu.elapsed().as_secs_f64(),
            wall_seconds: self.wall.elapsed().as_secs_f64(),
            evaluations: self.counts,
        }
    }
}

/// The least-squares problem a descent sees: the objective over the selected rows, with every
/// call charged to the meter. Once the budget is spent it reports failed evaluations so that
/// the solver winds down at once.
struct Fit<'a, O: Objective> {
    objective: &'a O,
    work: &'a mut O::Workspace,
    meter: &'a mut Meter,
    rows: usize,
}

impl<O: Objective> Problem for Fit<'_, O> {
    fn residual_count(&self) -> usize {
        self.rows
    }
    fn parameter_count(&self) -> usize {
        self.objective.dim()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        if self.meter.charge(Kind::Residual, self.rows).is_err() {
            // The trial is over and `descend` discards this descent. The solver asks
            // `should_stop` after a failed evaluation, which ends the solve at once (code 11)
            // instead of shrinking the radius and retrying.
            return false;
        }
        self.objective.residuals(self.work, x, r)
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        // One Jacobian row per sample, whatever the objective computes alongside (brdf-model
        // recomputes the residuals with the Jacobian): the unit is "a row of J at a sample".
        self.meter.charge(Kind::Jacobian, self.rows).is_ok()
            && self.objective.jacobian(self.work, x, jac)
    }
    /// Asked by the solver once per iteration and during long step computations: polls the
    /// clock like every charge.
    fn should_stop(&mut self) -> bool {
        self.meter.poll_clock().is_err()
    }
}

/// What the context knows of the full-data RMSE of its last candidate.
#[derive(Clone, Copy, Debug)]
enum Known {
    /// The RMSE itself.
    Exact(f64),
    /// Only that it is above this value (an evaluation cut short).
    Above(f64),
}

/// Names of the descent-outcome counters, by N2FB code.
fn descent_counter(code: u8) -> &'static str {
    match code {
        3 => "descent_x_convergence",
        4 => "descent_relative_function_convergence",
        5 => "descent_both_convergence",
        6 => "descent_absolute_function_convergence",
        7 => "descent_singular_convergence",
        8 => "descent_false_convergence",
        9 => "descent_evaluation_limit",
        10 => "descent_iteration_limit",
        11 => "descent_interrupted",
        _ => "descent_start_not_evaluable",
    }
}

thread_local! {
    /// The solver of the last trial that finished on this thread; the next trial here takes it.
    /// Its workspace has then already grown to the full data's size, so a trial does not
    /// allocate it and fault its pages in again: in a perf profile of AED on the tuning
    /// instance, page faults and unmapping from the solver's growing buffers were about 8% of
    /// the CPU time. A solve resets every part of the solver's state it reads (descents within a
    /// trial already share one solver); the seeded goldens and `tuning_bench`'s counts are
    /// unchanged by the reuse.
    static SPARE_SOLVER: std::cell::Cell<Option<Solver>> = const { std::cell::Cell::new(None) };
}

/// Everything one trial owns: the objective's workspace, the seeded RNG, the solver, the clocks,
/// the evaluation counts, the best candidate and the anytime trace. Implements [`Search`].
pub struct TrialContext<'a, O: Objective> {
    objective: &'a O,
    work: O::Workspace,
    rng: SearchRng,
    solver: Solver,
    options: Options,
    meter: Meter,
    target: f64,
    reached_at: Option<Stamp>,
    best_x: Vec<f64>,
    best_rmse: f64,
    trace: Vec<TracePoint>,
    counters: Vec<(&'static str, u64)>,
    /// The last candidate whose full-data RMSE was charged, and what is known of it.
    known_x: Vec<f64>,
    known_rmse: Option<Known>,
    /// Whether [`Search::evaluate_below`] may stop summing early.
    early_exit: bool,
    /// Residuals of [`Search::evaluate_subsample`] (grown once, then reused).
    subsample_residuals: Vec<f64>,
    /// Why the algorithm failed ([`Search::fail`]), the first message given.
    failure: Option<String>,
}

impl<O: Objective> Drop for TrialContext<'_, O> {
    /// Leaves the solver to the next trial on this thread (the thread-local `SPARE_SOLVER`).
    fn drop(&mut self) {
        SPARE_SOLVER.set(Some(std::mem::take(&mut self.solver)));
    }
}

impl<'a, O: Objective> TrialContext<'a, O> {
    /// A context for one trial; starts the trial's CPU and wall clocks (call it on the thread
    /// that runs the trial).
    pub fn new(objective: &'a O, seed: u64, budget: Budget, target: f64) -> Self {
        let dim = objective.dim();
        Self {
            objective,
            work: objective.workspace(),
            rng: SearchRng::seed_from_u64(seed),
            solver: SPARE_SOLVER.take().unwrap_or_default(),
            options: DescentModel::default().options(),
            meter: Meter::new(budget),
            target,
            reached_at: None,
            best_x: Vec::with_capacity(dim),
            best_rmse: f64::INFINITY,
            trace: Vec::with_capacity(64),
            counters: Vec::with_capacity(16),
            known_x: vec![f64::NAN; dim],
            known_rmse: None,
            early_exit: true,
            subsample_residuals: Vec::new(),
            failure: None,
        }
    }

    /// Lets [`Search::evaluate_below`] stop summing squares once the bound is passed (the
    /// default), or not. The trial's decisions, the paper's counts and the trace are the same
    /// either way; only `EvalCounts::rmse_rows_computed` and the CPU time differ.
    pub fn set_early_exit(&mut self, enabled: bool) {
        self.early_exit = enabled;
    }

    /// Stops the trial with [`StopReason::Interrupted`] at the next evaluation or solver
    /// iteration after `flag` is raised (from any thread). Lets a caller cancel a long trial,
    /// e.g. on Ctrl-C; a trial whose flag is never raised is unchanged.
    pub fn set_interrupt(&mut self, flag: Arc<AtomicBool>) {
        self.meter.interrupt = Some(flag);
    }

    /// The descent's step model: bounded-lm's default, NL2SOL's adaptive choice between the
    /// Gauss-Newton and the augmented model (as in PORT's N2FB) allowed to switch only after
    /// [`TrialContext::set_adaptive_delay`] secant updates per parameter, or Gauss-Newton only
    /// (the default before 2026-12-02). Switching from the first update made AED, AERS and RPLS
    /// slower on the paper's tuning instance; the delayed switch leaves AED's short descents
    /// unchanged (`docs/solver.md`, "Step model and secant scaling"). For comparisons.
    pub fn set_step_model(&mut self, model: bounded_lm::StepModel) {
        self.options.model = model;
    }

    /// Whether the descents put the secant term in the scaling
    /// (`bounded_lm::SecantScaling`, N2FB's rule, on by default) and after how many
    /// secant updates per parameter (its delay, default 2;
    /// with 0, N2FB's rule, AED measured 8% slower on the paper's tuning instance: bounded-lm's
    /// `docs/solver.md`). For comparisons.
    pub fn set_secant_scaling(&mut self, on: bool, delay: usize) {
        self.options.scaling.secant = if on {
            bounded_lm::SecantScaling::After { delay }
        } else {
            bounded_lm::SecantScaling::Off
        };
    }

    /// The descents' solver configuration ([`DescentModel`]; replaces the step model and the
    /// secant settings, keeps the budgets the searches set per descent).
    pub fn set_descent_model(&mut self, descent: DescentModel) {
        self.options = descent.options();
    }

    /// Whether the descents hold the variables of numerically dead Jacobian columns
    /// (`bounded_lm::Safeguards::hold_dead_columns`; off in the searches, see
    /// [`DescentModel::options`]). For comparisons.
    pub fn set_hold_dead_columns(&mut self, on: bool) {
        self.options.safeguards.hold_dead_columns = on;
    }

    /// Whether the descents' singular-convergence test step is at least `||D x||` long
    /// (`bounded_lm::Safeguards::singular_radius_at_least_x`; off in the searches, see
    /// [`DescentModel::options`]). For comparisons.
    pub fn set_singular_radius_at_least_x(&mut self, on: bool) {
        self.options.safeguards.singular_radius_at_least_x = on;
    }

    /// Whether the descents stop the search for the Levenberg parameter at the minimum-norm
    /// step of a singular model (`bounded_lm::Safeguards::stop_at_minimum_norm_step`; off in the
    /// searches, see [`DescentModel::options`]). For comparisons.
    pub fn set_stop_at_minimum_norm_step(&mut self, on: bool) {
        self.options.safeguards.stop_at_minimum_norm_step = on;
    }

    /// Whether the descents' Givens rotations scale tiny entries before squaring them
    /// (`bounded_lm::Safeguards::scale_tiny_rotations`; off in the searches, see
    /// [`DescentModel::options`]). For comparisons.
    pub fn set_scale_tiny_rotations(&mut self, on: bool) {
        self.options.safeguards.scale_tiny_rotations = on;
    }

    /// Whether a rejected descent step gets one second-order correction
    /// (`bounded_lm::Safeguards::second_order_correction`; off in the searches, see
    /// [`DescentModel::options`]). For comparisons.
    pub fn set_second_order_correction(&mut self, on: bool) {
        self.options.safeguards.second_order_correction = on;
    }

    /// How fast the descents' scaling may fall (`bounded_lm::Scaling::decay`, N2FB's
    /// DFAC 0.6 by default; 1 is MINPACK's non-decreasing scaling). For comparisons.
    pub fn set_scaling_decay(&mut self, decay: f64) {
        self.options.scaling.decay = decay;
    }

    /// Secant updates per parameter before the descents' adaptive model choice may switch
    /// to the augmented model (the delay of `bounded_lm::StepModel::Adaptive`; no effect on the
    /// Gauss-Newton model, which never switches). For comparisons.
    pub fn set_adaptive_delay(&mut self, delay: usize) {
        if let bounded_lm::StepModel::Adaptive { delay: d } = &mut self.options.model {
            *d = delay;
        }
    }

    /// The evaluations counted so far.
    pub fn counts(&self) -> EvalCounts {
        self.meter.counts
    }

    /// Best full-data RMSE so far (`+inf` before the first evaluation).
    pub fn best_rmse(&self) -> f64 {
        self.best_rmse
    }

    /// Ends the trial: `end` is what the algorithm returned (`Ok` if it finished by itself).
    pub fn finish(mut self, end: Result<(), Stop>) -> TrialResult {
        let stop = match end {
            _ if self.failure.is_some() => StopReason::Failed,
            Ok(()) => StopReason::Finished,
            Err(s) => s.into(),
        };
        let ended_at = self.reached_at.unwrap_or_else(|| self.meter.stamp());
        self.counters.sort_by_key(|&(name, _)| name);
        TrialResult {
            stop,
            reached_at: self.reached_at,
            ended_at,
            best_rmse: self.best_rmse,
            best_x: std::mem::take(&mut self.best_x),
            trace: std::mem::take(&mut self.trace),
            counters: self
                .counters
                .iter()
                .map(|&(name, value)| (name.to_string(), value))
                .collect(),
            failure: self.failure.take(),
        }
    }

    /// Records `rmse` of `x` as a full-data evaluation: best candidate, trace, target.
    fn record(&mut self, x: &[f64], rmse: f64) -> Result<f64, Stop> {
        if rmse < self.best_rmse {
            self.best_rmse = rmse;
            self.best_x.clear();
            self.best_x.extend_from_slice(x);
            let at = self.meter.stamp();
            self.trace.push(TracePoint { at, rmse });
            if rmse <= self.target {
                self.reached_at = Some(at);
                return Err(self.meter.stop(Stop::Target));
            }
        }
        Ok(rmse)
    }

    fn remember(&mut self, x: &[f64], known: Known) {
        self.known_x.copy_from_slice(x);
        self.known_rmse = Some(known);
    }

    /// The full-data RMSE of `x`, computed in full (its paper count already charged).
    fn full_rmse(&mut self, x: &[f64]) -> f64 {
        let rmse = self.objective.rmse(&mut self.work, x);
        self.meter.counts.rmse_rows_computed += self.objective.sample_count() as u64;
        self.remember(x, Known::Exact(rmse));
        rmse
    }

    /// Admits a full-data residual or Jacobian evaluation at `x` for [`Search::residuals`] and
    /// [`Search::jacobian`]: fails with the trial's stop; `Ok(false)` (nothing charged) when
    /// `x` is not a finite point of the box or the output is not `sized`; else charges one
    /// row of `kind` per sample, the unit of a descent's evaluations, and selects every row.
    fn admit_full_data(&mut self, kind: Kind, x: &[f64], sized: bool) -> Result<bool, Stop> {
        if let Some(stop) = self.meter.stopped {
            return Err(stop);
        }
        if !self.in_box(x) || !sized {
            return Ok(false);
        }
        self.meter.charge(kind, self.objective.sample_count())?;
        self.objective
            .select(&mut self.work, Rows::Full, &mut self.rng);
        Ok(true)
    }

    /// Whether `x` is a finite point of the box, of the right length.
    fn in_box(&self, x: &[f64]) -> bool {
        x.len() == self.objective.dim()
            && x.iter()
                .zip(self.objective.lower().iter().zip(self.objective.upper()))
                .all(|(&v, (&lo, &hi))| v.is_finite() && lo <= v && v <= hi)
    }

    fn is_known(&self, x: &[f64]) -> bool {
        self.known_rmse.is_some()
            && x.iter()
                .zip(&self.known_x)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

impl<O: Objective> Search for TrialContext<'_, O> {
    fn dim(&self) -> usize {
        self.objective.dim()
    }
    fn lower(&self) -> &[f64] {
        self.objective.lower()
    }
    fn upper(&self) -> &[f64] {
        self.objective.upper()
    }
    fn sample_count(&self) -> usize {
        self.objective.sample_count()
    }
    fn rng(&mut self) -> &mut SearchRng {
        &mut self.rng
    }
    fn random_pick(&mut self, x: &mut [f64]) {
        self.objective.random_pick(&mut self.rng, x);
    }
    fn natural_value(&self, i: usize, x: f64) -> f64 {
        self.objective.natural_value(i, x)
    }
    fn optimiser_value(&self, i: usize, v: f64) -> f64 {
        self.objective.optimiser_value(i, v)
    }
    fn evaluate_subsample(&mut self, x: &[f64], k: usize) -> Result<f64, Stop> {
        let n = self.objective.sample_count();
        if k >= n {
            return self.evaluate(x);
        }
        if let Some(stop) = self.meter.stopped {
            return Err(stop);
        }
        self.meter.charge(Kind::Rmse, k)?;
        self.meter.counts.rmse_rows_computed += k as u64;
        let m = self
            .objective
            .select(&mut self.work, Rows::Subsample(k), &mut self.rng);
        if self.subsample_residuals.len() < m {
            self.subsample_residuals.resize(m, 0.0);
        }
        let r = &mut self.subsample_residuals[..m];
        if !self.objective.residuals(&mut self.work, x, r) {
            return Ok(f64::INFINITY);
        }
        let sum: f64 = r.iter().map(|v| v * v).sum();
        let rmse = (sum / m as f64).sqrt();
        // Overflow and NaN alike mean "unevaluable", as for the full-data RMSE.
        Ok(if rmse.is_finite() {
            rmse
        } else {
            f64::INFINITY
        })
    }

    fn evaluate(&mut self, x: &[f64]) -> Result<f64, Stop> {
        if let Some(stop) = self.meter.stopped {
            return Err(stop);
        }
        let rmse = match self.known_rmse {
            Some(Known::Exact(rmse)) if self.is_known(x) => {
                self.count("rmse_reused");
                rmse
            }
            Some(Known::Above(_)) if self.is_known(x) => {
                // Charged (in the paper's count) when it was cut short: complete it.
                self.count("rmse_reused");
                self.full_rmse(x)
            }
            _ => {
                self.meter
                    .charge(Kind::Rmse, self.objective.sample_count())?;
                self.full_rmse(x)
            }
        };
        self.record(x, rmse)
    }

    fn evaluate_below(&mut self, x: &[f64], bound: f64) -> Result<Option<f64>, Stop> {
        if let Some(stop) = self.meter.stopped {
            return Err(stop);
        }
        // The exact value is needed whenever it would improve the incumbent (trace, target).
        let cut = bound.max(self.best_rmse);
        if !self.early_exit || cut == f64::INFINITY || cut.is_nan() {
            return self.evaluate(x).map(Some);
        }
        match self.known_rmse {
            Some(Known::Exact(rmse)) if self.is_known(x) => {
                self.count("rmse_reused");
                return self.record(x, rmse).map(Some);
            }
            Some(Known::Above(above)) if self.is_known(x) => {
                self.count("rmse_reused");
                if above >= cut {
                    return Ok(None);
                }
            }
            _ => {
                self.meter
                    .charge(Kind::Rmse, self.objective.sample_count())?;
            }
        }
        let (rmse, rows) = self.objective.rmse_below(&mut self.work, x, cut);
        self.meter.counts.rmse_rows_computed += rows as u64;
        match rmse {
            Some(rmse) => {
                self.remember(x, Known::Exact(rmse));
                self.record(x, rmse).map(Some)
            }
            None => {
                self.remember(x, Known::Above(cut));
                Ok(None)
            }
        }
    }

    fn descend(
        &mut self,
        x: &mut [f64],
        rows: Rows,
        limits: DescentLimits,
    ) -> Result<Descent, Stop> {
        if let Some(stop) = self.meter.stopped {
            return Err(stop);
        }
        let n = self.objective.sample_count();
        let rows = if rows.count(n) >= n { Rows::Full } else { rows };
        let m = self.objective.select(&mut self.work, rows, &mut self.rng);
        self.options.limits.iterations = limits.iterations;
        self.options.limits.evaluations = limits.evaluations;
        let mut fit = Fit {
            objective: self.objective,
            work: &mut self.work,
            meter: &mut self.meter,
            rows: m,
        };
        let lower = self.objective.lower();
        let upper = self.objective.upper();
        let result = self.solver.solve(&mut fit, x, lower, upper, &self.options);
        if let Some(stop) = self.meter.stopped {
            return Err(stop);
        }
        let descent = match result {
            Ok(report) => {
                if rows == Rows::Full && report.f.is_finite() {
                    // The solver's final f is 0.5 * sum r^2 over the full data at x: the
                    // full-data RMSE comes for free.
                    self.remember(x, Known::Exact((2.0 * report.f / n as f64).sqrt()));
                }
                Descent {
                    end: DescentEnd::Solver(report.outcome),
                    iterations: report.iterations,
                }
            }
            Err(error) => {
                // Limits are validated by the configs and the box by the objective, so the only
                // error a well-formed objective can produce is an unevaluable start.
                debug_assert_eq!(error, SolveError::StartNotEvaluable);
                Descent {
                    end: DescentEnd::StartNotEvaluable,
                    iterations: 0,
                }
            }
        };
        self.count("descents");
        self.count(descent_counter(descent.code()));
        Ok(descent)
    }

    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> Result<bool, Stop> {
        let n = self.objective.sample_count();
        if !self.admit_full_data(Kind::Residual, x, r.len() == n)? {
            return Ok(false);
        }
        if !self.objective.residuals(&mut self.work, x, r) {
            return Ok(false);
        }
        let sum: f64 = r.iter().map(|v| v * v).sum();
        let rmse = (sum / n as f64).sqrt();
        if rmse.is_finite() {
            // As after a full-data descent: an evaluation of this `x` next costs nothing.
            self.remember(x, Known::Exact(rmse));
        }
        Ok(true)
    }

    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> Result<bool, Stop> {
        let n = self.objective.sample_count();
        let sized = jac.len() == n * self.objective.dim();
        Ok(self.admit_full_data(Kind::Jacobian, x, sized)?
            && self.objective.jacobian(&mut self.work, x, jac))
    }

    fn check_budget(&mut self) -> Result<(), Stop> {
        self.meter.poll_clock()
    }

    fn budget(&self) -> BudgetState {
        BudgetState {
            limits: self.meter.budget,
            cpu_seconds: self.meter.cpu.elapsed().as_secs_f64(),
            evaluations: self.meter.counts.total(),
        }
    }

    fn fail(&mut self, message: String) -> Stop {
        self.failure.get_or_insert(message);
        self.meter.stop(Stop::Failed)
    }

    fn count(&mut self, name: &'static str) {
        match self.counters.iter_mut().find(|(n, _)| *n == name) {
            Some((_, v)) => *v += 1,
            None => self.counters.push((name, 1)),
        }
    }
}

/// Runs one trial of `algorithm` on `objective` from `seed` until the full-data RMSE reaches
/// `target` or `budget` is spent, on the calling thread (never spawns threads; CPU time is the
/// calling thread's clock, started here).
///
/// The configuration should have passed [`AlgorithmConfig::validate`]; an invalid one ends the
/// trial at once with [`StopReason::Finished`], no evaluations and the counter
/// `invalid_config`.
pub fn run_trial<O: Objective>(
    objective: &O,
    algorithm: &AlgorithmConfig,
    seed: u64,
    budget: Budget,
    target: f64,
) -> TrialResult {
    run_trial_interruptible(objective, algorithm, seed, budget, target, None)
}

/// [`run_trial`] that also stops, with [`StopReason::Interrupted`], once `interrupt` is
/// raised. Until then the trial is the same as [`run_trial`]'s with the same seed.
pub fn run_trial_interruptible<O: Objective>(
    objective: &O,
    algorithm: &AlgorithmConfig,
    seed: u64,
    budget: Budget,
    target: f64,
    interrupt: Option<Arc<AtomicBool>>,
) -> TrialResult {
    let settings = TrialSettings {
        interrupt,
        ..TrialSettings::default()
    };
    run_trial_with(objective, algorithm, seed, budget, target, &settings)
}

/// How a trial runs beyond its algorithm, seed, budget and target.
#[derive(Clone, Debug, Default)]
pub struct TrialSettings {
    /// Stops the trial with [`StopReason::Interrupted`] once raised.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// The descents' solver configuration.
    pub descent: DescentModel,
}

/// [`run_trial`] with [`TrialSettings`].
pub fn run_trial_with<O: Objective>(
    objective: &O,
    algorithm: &AlgorithmConfig,
    seed: u64,
    budget: Budget,
    target: f64,
    settings: &TrialSettings,
) -> TrialResult {
    let mut context = TrialContext::new(objective, seed, budget, target);
    if let Some(flag) = &settings.interrupt {
        context.set_interrupt(flag.clone());
    }
    context.set_descent_model(settings.descent);
    if algorithm.validate().is_err() {
        context.count("invalid_config");
        return context.finish(Ok(()));
    }
    let end = algorithm.run(&mut context);
    context.finish(end)
}

#[cfg(test)]
mod tests;
