//! The N2FB-style iteration: scaled trust-region Levenberg-Marquardt with an active set for the
//! bounds, NL2SOL's convergence tests and (optionally) its adaptive augmented model.
//!
//! The loop ([`iterate`]) reads like NL2SOL's driver: start a new iteration
//! ([`Descent::new_iteration`]: Jacobian, scaling `D`, factorisation, the pending radius
//! change), compute a trial step in the trust region ([`Workspace::compute_step`]), evaluate it
//! ([`Descent::trial_step`]), assess it (DA7SST: accept or reject and how the radius changes,
//! [`TrustRadius::after_step`]), and test for convergence ([`Descent::convergence_test`],
//! [`Descent::stop_test`]). The names follow NL2SOL and PORT (Dennis, Gay and Welsch 1981;
//! Gay 1983): RADFAC, RADINC, PREDUC, NREDUC, RELDX, STPPAR.
//!
//! Modules: [`workspace`] (the buffers), [`scaling`], [`factorisation`], [`step`] (active set
//! and the bounded step), [`model`] and [`subproblem`] (the trust-region subproblem),
//! [`secant`], [`correction`] (second-order correction), [`radius`], [`assessment`],
//! [`trial`] (a trial step and its assessment) and [`descent`] (the state between iterations).

mod assessment;
mod correction;
mod descent;
mod factorisation;
mod model;
mod radius;
mod scaling;
mod secant;
mod step;
mod subproblem;
mod trial;
mod workspace;

use crate::linalg::dot;
use crate::{Options, Problem, Report, SolveError};
use descent::{Descent, Start, TrialResult};
#[cfg(doc)]
use radius::TrustRadius;
use workspace::Workspace;

/// Bounded trust-region Levenberg-Marquardt solver.
///
/// The solver owns its workspace, sized by the size query `Workspace::required(m, p)`:
/// repeated solves of the same or a smaller size allocate nothing, and
/// [`Solver::with_capacity`] allocates it up front.
#[derive(Clone, Debug, Default)]
pub struct Solver {
    ws: Workspace,
}

impl Solver {
    /// A solver with an empty workspace (it grows on the first solve).
    pub fn new() -> Self {
        Self::default()
    }

    /// A solver whose workspace is allocated for `m` residuals and `p` parameters, so no solve
    /// of that size or smaller allocates.
    pub fn with_capacity(m: usize, p: usize) -> Self {
        Self {
            ws: Workspace::with_required(&Workspace::required(m, p)),
        }
    }

    /// Minimises `0.5 * sum r_i(x)^2` subject to `lower <= x <= upper`.
    ///
    /// `x` holds the start on entry and the best point found on return. A start outside the box
    /// is projected onto it (not an error). Infinite bounds are allowed.
    ///
    /// # Errors
    /// [`SolveError::DimensionMismatch`] when a slice length disagrees with the problem,
    /// [`SolveError::InconsistentBounds`] when `lower_i > upper_i` or a bound is NaN,
    /// [`SolveError::InvalidOptions`] for out-of-range options, and
    /// [`SolveError::StartNotEvaluable`] when the residuals or the Jacobian cannot be computed at
    /// the (projected) start.
    pub fn solve<P: Problem>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
        lower: &[f64],
        upper: &[f64],
        options: &Options,
    ) -> Result<Report, SolveError> {
        options.validate()?;
        let m = problem.residual_count();
        let p = problem.parameter_count();
        for (what, len) in [
            ("x", x.len()),
            ("lower", lower.len()),
            ("upper", upper.len()),
        ] {
            if len != p {
                return Err(SolveError::DimensionMismatch {
                    what,
                    expected: p,
                    found: len,
                });
            }
        }
        for i in 0..p {
            let (l, u) = (lower[i], upper[i]);
            if l.is_nan() || u.is_nan() || l > u || l == f64::INFINITY || u == f64::NEG_INFINITY {
                return Err(SolveError::InconsistentBounds {
                    index: i,
                    lower: l,
                    upper: u,
                });
            }
        }
        let ws = &mut self.ws;
        ws.prepare(&Workspace::required(m, p));
        for i in 0..p {
            ws.lo[i] = lower[i];
            ws.hi[i] = upper[i];
            // A NaN start component is placed at the nearest finite point of the box.
            let xi = if x[i].is_nan() { 0.0 } else { x[i] };
            ws.x[i] = xi.clamp(lower[i], upper[i]);
        }
        let report = iterate(ws, problem, options)?;
        x.copy_from_slice(&ws.x[..p]);
        Ok(report)
    }
}

/// The main loop (the tests and their precedence: `docs/solver.md`).
fn iterate<P: Problem>(
    ws: &mut Workspace,
    problem: &mut P,
    opt: &Options,
) -> Result<Report, SolveError> {
    let mut descent = match Descent::start(ws, problem, opt)? {
        Start::Done(report) => return Ok(report),
        Start::Descent(d) => d,
    };
    loop {
        if descent.need_jacobian
            && let Some(outcome) = descent.new_iteration(ws, problem)?
        {
            return Ok(descent.report(outcome));
        }
        let trial = match descent.trial_step(ws, problem) {
            TrialResult::Stop(outcome) => return Ok(descent.report(outcome)),
            TrialResult::Failed => continue,
            TrialResult::Evaluated(trial) => trial,
        };
        let assessment = descent.assess(ws, &trial);
        let (trial, assessment) = descent.correct_if_rejected(ws, problem, trial, assessment);
        let gts = dot(&ws.g[..ws.p], &ws.step[..ws.p]);
        let change = descent
            .radius
            .after_step(&trial, &assessment, gts, descent.model.switching);
        let converged = descent.convergence_test(ws, problem, &trial, &assessment);
        if change.try_longer && converged.is_none() {
            descent.keep_good(ws, &trial);
            descent.radius.try_longer(change.factor, trial.info.dnorm);
            continue;
        }
        if assessment.accepted {
            descent.accept(ws, &trial, &assessment, &change);
        }
        if let Some(outcome) = converged.or_else(|| descent.stop_test(&trial, &assessment)) {
            return Ok(descent.report(outcome));
        }
        if !assessment.accepted && assessment.switch_models {
            descent.model.retry_with_other(ws);
        }
    }
}
