//! The state of one descent between iterations and its steps: the start, a new iteration at
//! an accepted point (Jacobian, scaling, factorisation, secant update), the trial step and its
//! evaluation, the saved good step, and acceptance.

use super::radius::{RadiusChange, TrustRadius};
use super::step::StepInfo;
use super::subproblem::StopPoll;
use super::trial::{Assessment, Trial};
use super::workspace::Workspace;
use crate::linalg::{dot, jt_vec, sym_mat_vec};
use crate::{
    Options, Outcome, Problem, RadiusUpdate, Report, SecantScaling, SolveError, StepModel,
};

/// A first trust radius below this times `||D x||` is a round-off change of x.
pub(super) const ROUND_OFF_STEP: f64 = 16.0 * f64::EPSILON;

pub(super) fn half_sum_squares(r: &[f64]) -> f64 {
    0.5 * dot(r, r)
}

/// Iterations and evaluations so far (N2FB's NITER, NFCALL, NGCALL).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Counts {
    pub(super) iterations: usize,
    pub(super) residuals: usize,
    pub(super) jacobians: usize,
}

/// What happened to a trial step before it could be assessed.
pub(super) enum TrialResult {
    /// The solve ends here.
    Stop(Outcome),
    /// The residuals could not be evaluated there: the step was rejected, the radius shrunk.
    Failed,
    /// A step to assess.
    Evaluated(Trial),
}

/// A good step kept while a longer one is tried from the same point (NL2SOL's FLSTGD, PLSTGD,
/// DSTSAV); its point, residuals and step are in the workspace's saved step ([`Workspace::swap_saved`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Good {
    pub(super) f: f64,
    pub(super) info: StepInfo,
    pub(super) reldx: f64,
}

/// NL2SOL's choice between the Gauss-Newton and the augmented model.
#[derive(Clone, Copy, Debug)]
pub(super) struct ModelChoice {
    pub(super) adaptive: bool,
    /// The adaptive choice may switch models in this iteration (`adaptive` and S has had
    /// the delay of [`StepModel::Adaptive`] in updates per parameter).
    pub(super) switching: bool,
    pub(super) augmented: bool,
    /// A failed step was already retried with the other model in this iteration.
    pub(super) switched_this_iteration: bool,
}

impl ModelChoice {
    /// Retries a failed step from the same point with the other model, once per iteration.
    pub(super) fn retry_with_other(&mut self, ws: &mut Workspace) {
        if !self.switched_this_iteration {
            self.augmented = !self.augmented;
            self.switched_this_iteration = true;
            ws.build_model(self.augmented);
        }
    }
}

/// The state of one descent between iterations (everything but the workspace buffers).
pub(super) struct Descent<'o> {
    pub(super) opt: &'o Options,
    pub(super) counts: Counts,
    /// f at `x` and at `x_prev`.
    pub(super) f: f64,
    pub(super) f_prev: f64,
    pub(super) radius: TrustRadius,
    pub(super) model: ModelChoice,
    /// The last step was accepted: the next pass starts a new iteration.
    pub(super) need_jacobian: bool,
    /// `jac` holds J at `x_prev` (the secant update needs the old Jacobian).
    pub(super) have_prev_jacobian: bool,
    /// A good step saved while a longer one is tried.
    pub(super) good: Option<Good>,
}

/// Either the descent, or the report when the start already ends the solve.
pub(super) enum Start<'o> {
    Descent(Descent<'o>),
    Done(Report),
}

impl<'o> Descent<'o> {
    /// Evaluates the start. Only here is a failed evaluation an error.
    pub(super) fn start<P: Problem>(
        ws: &mut Workspace,
        problem: &mut P,
        opt: &'o Options,
    ) -> Result<Start<'o>, SolveError> {
        let (m, p) = (ws.m, ws.p);
        if !problem.residuals(&ws.x[..p], &mut ws.r[..m]) {
            return Err(SolveError::StartNotEvaluable);
        }
        let f = half_sum_squares(&ws.r[..m]);
        if !f.is_finite() {
            return Err(SolveError::StartNotEvaluable);
        }
        let d = Descent {
            opt,
            counts: Counts {
                residuals: 1,
                ..Counts::default()
            },
            f,
            f_prev: f,
            radius: TrustRadius {
                rule: opt.radius.update,
                radius: opt.radius.initial,
                pending_factor: 0.0,
                radinc: 0,
            },
            model: ModelChoice {
                adaptive: matches!(opt.model, StepModel::Adaptive { .. }),
                switching: opt.model == StepModel::Adaptive { delay: 0 },
                augmented: false,
                switched_this_iteration: false,
            },
            need_jacobian: true,
            have_prev_jacobian: false,
            good: None,
        };
        if p == 0 {
            return Ok(Start::Done(d.report(Outcome::RelativeFunctionConvergence)));
        }
        if f < opt.tolerances.absolute_function {
            return Ok(Start::Done(d.report(Outcome::AbsoluteFunctionConvergence)));
        }
        ws.secant.s[..p * p].fill(0.0);
        Ok(Start::Descent(d))
    }

    pub(super) fn report(&self, outcome: Outcome) -> Report {
        Report {
            outcome,
            f: self.f,
            iterations: self.counts.iterations,
            residual_evaluations: self.counts.residuals,
            jacobian_evaluations: self.counts.jacobians,
        }
    }

    /// Starts an iteration at the accepted point: the Jacobian, the scaling `D`, the QR
    /// factorization, the pending radius change and the secant update. A failed Jacobian returns
    /// to the previous point with half the radius.
    pub(super) fn new_iteration<P: Problem>(
        &mut self,
        ws: &mut Workspace,
        problem: &mut P,
    ) -> Result<Option<Outcome>, SolveError> {
        let (m, p) = (ws.m, ws.p);
        if self.counts.iterations >= self.opt.limits.iterations {
            return Ok(Some(Outcome::IterationLimit));
        }
        if problem.should_stop() {
            return Ok(Some(Outcome::Interrupted));
        }
        // S is kept by the secant update for the augmented model and for the scaling.
        let secant_scaling = self.opt.scaling.secant != SecantScaling::Off;
        let keep_secant = self.have_prev_jacobian && (self.model.adaptive || secant_scaling);
        if keep_secant {
            // (J_old)^T r_new for y# before J is overwritten.
            jt_vec(&ws.jac, &ws.r, m, p, &mut ws.secant.ysharp);
        }
        self.counts.jacobians += 1;
        let ok = problem.jacobian(&ws.x[..p], &mut ws.jac[..m * p]) && ws.survey_jacobian();
        if !ok {
            return self.after_failed_jacobian(ws);
        }
        self.counts.iterations += 1;
        if keep_secant && secant_scaling {
            // The scaling needs the updated S, so S is updated before the factorization, from
            // g = J^T r computed directly (as in NL2SOL, where DUPDAT follows the secant update).
            ws.g[..p].copy_from_slice(&ws.survey.jtr[..p]);
            ws.secant_update_from_gradients();
        }
        self.rescale(ws);
        ws.factor_jacobian(self.opt.safeguards.hold_dead_columns);
        self.radius.start_iteration(ws);
        if keep_secant && !secant_scaling {
            // Without the secant term in the scaling, S is updated after the factorization from
            // the gradient it gives (the order with which the Adaptive results were measured).
            ws.secant_update_from_gradients();
        }
        self.have_prev_jacobian = true;
        self.need_jacobian = false;
        self.model.switched_this_iteration = false;
        ws.build_model(self.model.augmented);
        Ok(None)
    }

    /// A failed Jacobian at an accepted point is treated like a failed evaluation of the step
    /// that led there: back to the previous point with half the radius. The factorization, g,
    /// `J^T J` and D still describe that point: they are only recomputed after a successful
    /// Jacobian. At the start it is an error.
    fn after_failed_jacobian(&mut self, ws: &mut Workspace) -> Result<Option<Outcome>, SolveError> {
        if self.counts.iterations == 0 {
            return Err(SolveError::StartNotEvaluable);
        }
        ws.return_to_previous();
        self.f = self.f_prev;
        self.have_prev_jacobian = false;
        self.need_jacobian = false;
        self.radius.after_failed_jacobian();
        if self.counts.iterations >= self.opt.limits.iterations {
            return Ok(Some(Outcome::IterationLimit));
        }
        Ok(None)
    }

    /// The scaling `D` for the new Jacobian (with the secant term once `S` has had the delay's
    /// updates per parameter), whether the adaptive choice may switch models from now on, and
    /// on the first iteration the optional lift of a round-off radius.
    fn rescale(&mut self, ws: &mut Workspace) {
        let p = ws.p;
        let secant_in_scaling = match self.opt.scaling.secant {
            SecantScaling::After { delay } => ws.secant.updates >= delay.saturating_mul(p),
            SecantScaling::Off => false,
        };
        let first = self.counts.iterations == 1;
        ws.update_scaling(first, secant_in_scaling, self.opt.scaling.decay);
        self.model.switching = match self.opt.model {
            StepModel::Adaptive { delay } => ws.secant.updates >= delay.saturating_mul(p),
            StepModel::GaussNewton => false,
        };
        // A first step that is a round-off change of x is lifted to sqrt(eps) relative to x
        // in the scaled norm (Safeguards::lift_round_off_radius).
        if first && self.opt.safeguards.lift_round_off_radius {
            let norm_x = ws.scaled_norm_x();
            if self.radius.radius < ROUND_OFF_STEP * norm_x {
                self.radius.radius = f64::EPSILON.sqrt() * norm_x;
            }
        }
    }

    /// Computes the step in the trust region and evaluates f there, or takes the saved good
    /// step when the longer one is not worth evaluating or does not beat it.
    pub(super) fn trial_step<P: Problem>(
        &mut self,
        ws: &mut Workspace,
        problem: &mut P,
    ) -> TrialResult {
        let p = ws.p;
        let opt = self.opt;
        let mut ask = || problem.should_stop();
        let mut poll = StopPoll::new(&mut ask);
        let info = ws.compute_step(
            self.radius.radius,
            self.model.augmented,
            opt.safeguards,
            &mut poll,
        );
        if poll.stopped() {
            return TrialResult::Stop(Outcome::Interrupted);
        }
        if let Some(good) = self.good {
            // DG7ITB: the longer step is evaluated only if it predicts more than 1.2 times the
            // reduction the saved step achieved (and the budget allows); otherwise the saved
            // step is taken.
            let worthwhile = info.dnorm > 0.0
                && info.preduc > 1.2 * (self.f - good.f)
                && self.counts.residuals < opt.limits.evaluations;
            if !worthwhile {
                return TrialResult::Evaluated(self.restore_good(ws));
            }
        }
        if info.dnorm == 0.0 || !(info.preduc > 0.0) {
            // No descent step inside the box. With a zero step (projected gradient exactly zero)
            // or a Gauss-Newton reduction within tolerance, x is stationary on its active face,
            // which both reductions being zero signals to N2FB. Otherwise (the model predicts no
            // decrease though f is not known to be optimal) report singular convergence, never a
            // success code.
            let emax = opt.tolerances.relative_function * self.f.abs();
            let stationary = (info.dnorm == 0.0 || (info.nreduc >= 0.0 && info.nreduc <= emax))
                && !info.dead_free
                && ws.gradient_permits_rel_conv(opt.tolerances.relative_function);
            return TrialResult::Stop(if stationary {
                Outcome::RelativeFunctionConvergence
            } else {
                Outcome::SingularConvergence
            });
        }
        if self.counts.residuals >= opt.limits.evaluations {
            return TrialResult::Stop(Outcome::EvaluationLimit);
        }
        for i in 0..p {
            ws.x_trial[i] = (ws.x[i] + ws.step[i]).clamp(ws.lo[i], ws.hi[i]);
        }
        let (f_trial, reldx) = self.evaluate_trial_point(ws, problem);
        if let Some(good) = self.good {
            // DA7SST: a longer step that does not beat the saved one (or cannot be evaluated)
            // is dropped and the saved step taken.
            if !(f_trial < good.f) {
                return TrialResult::Evaluated(self.restore_good(ws));
            }
            self.good = None;
        }
        if !f_trial.is_finite() {
            // Failed evaluation: reject the step and shrink the radius.
            self.radius.after_failed_evaluation(info.dnorm);
            if reldx <= opt.tolerances.false_convergence {
                return TrialResult::Stop(Outcome::FalseConvergence);
            }
            // A caller that refuses evaluations once its budget is spent would otherwise see
            // the radius shrink step by step down to false convergence, each step a new
            // factorization: ask at once whether it wants to stop.
            if problem.should_stop() {
                return TrialResult::Stop(Outcome::Interrupted);
            }
            return TrialResult::Failed;
        }
        TrialResult::Evaluated(Trial {
            info,
            f: f_trial,
            reldx,
            restored: false,
        })
    }

    /// Evaluates the residuals at `x_trial` into `r_trial` (counted against the budget):
    /// `f` there (NaN when they cannot be evaluated) and the step's RELDX.
    pub(super) fn evaluate_trial_point<P: Problem>(
        &mut self,
        ws: &mut Workspace,
        problem: &mut P,
    ) -> (f64, f64) {
        let (m, p) = (ws.m, ws.p);
        self.counts.residuals += 1;
        let f = if problem.residuals(&ws.x_trial[..p], &mut ws.r_trial[..m]) {
            half_sum_squares(&ws.r_trial[..m])
        } else {
            f64::NAN
        };
        (f, ws.reldx(&ws.x_trial, &ws.x))
    }

    /// Takes the saved good step back as the trial step.
    pub(super) fn restore_good(&mut self, ws: &mut Workspace) -> Trial {
        let good = self.good.take().expect("a saved good step");
        ws.swap_saved();
        Trial {
            info: good.info,
            f: good.f,
            reldx: good.reldx,
            restored: true,
        }
    }

    /// Keeps a good step and tries the longer one from the same point (same Jacobian).
    pub(super) fn keep_good(&mut self, ws: &mut Workspace, trial: &Trial) {
        ws.swap_saved();
        self.good = Some(Good {
            f: trial.f,
            info: trial.info,
            reldx: trial.reldx,
        });
    }

    /// Accepts the trial point; RADFAC is applied at the next iteration.
    pub(super) fn accept(
        &mut self,
        ws: &mut Workspace,
        trial: &Trial,
        a: &Assessment,
        change: &RadiusChange,
    ) {
        ws.accept_trial();
        self.f_prev = self.f;
        self.f = trial.f;
        self.need_jacobian = true;
        self.radius.pending_factor = change.factor;
        if self.radius.rule == RadiusUpdate::Nl2sol && change.factor == 1.0 {
            // Model Hessian times the step, for the gradient tests at the new point.
            sym_mat_vec(&ws.h, &ws.step, ws.p, &mut ws.h_step);
        }
        if a.switch_models {
            self.model.augmented = !self.model.augmented;
        }
    }
}
