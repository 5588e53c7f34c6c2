//! The second-order correction of a rejected step (ours, `Safeguards::second_order_correction`):
//! the residuals' departure from the linear model at the rejected point gives a correction `c`,
//! and `v + c` is tried once before the radius shrinks.

use super::descent::Descent;
use super::model::SHIFTED_TOL;
use super::step::StepInfo;
use super::trial::{Assessment, Trial};
use super::workspace::Workspace;
use crate::Problem;
use crate::linalg::{backward_solve, cholesky_shifted, dot, forward_solve, jt_vec, norm};

/// A second-order correction is tried only when it is at most this fraction of the step's
/// scaled length (GSL's `avmax` for geodesic acceleration, Transtrum and Sethna 2012).
pub(super) const MAX_CORRECTION: f64 = 0.75;

impl Workspace {
    /// Second-order correction of the rejected trial step `v` (in `step`, its residuals in
    /// `r_trial`): `c` minimises `||J c + e||^2 + lambda ||D c||^2` with `e = r(x + v) - r(x)
    /// - J v`, the part of the residuals' change the linear model missed, and `lambda` the
    /// step's Levenberg parameter; `step` becomes `v + c` (cut to the box), `x_trial` its point.
    /// Only with every variable free, and only when `||D c|| <= max_ratio ||D v||`; returns
    /// whether the corrected step was set (`soc_step` keeps `v`).
    pub(super) fn corrected_step(&mut self, max_ratio: f64) -> bool {
        let (m, p) = (self.m, self.p);
        if self.fixed[..p].iter().any(|&f| f) {
            return false;
        }
        for i in 0..m {
            self.correction.e[i] = self.r_trial[i] - self.r[i];
        }
        for j in 0..p {
            let sj = self.step[j];
            for (e, &v) in self.correction.e[..m]
                .iter_mut()
                .zip(&self.jac[j * m..(j + 1) * m])
            {
                *e -= v * sj;
            }
        }
        jt_vec(&self.jac, &self.correction.e, m, p, &mut self.correction.b);
        for j in 0..p {
            self.correction.b[j] = -self.correction.b[j] / self.d[j];
            for k in 0..=j {
                let v = dot(
                    &self.factors.r[j * p..(j + 1) * p],
                    &self.factors.r[k * p..(k + 1) * p],
                );
                self.correction.a[j * p + k] = v;
                self.correction.a[k * p + j] = v;
            }
        }
        if !cholesky_shifted(
            &self.correction.a[..p * p],
            self.lambda,
            p,
            SHIFTED_TOL,
            &mut self.correction.l[..p * p],
        ) {
            return false;
        }
        forward_solve(&self.correction.l[..p * p], p, &mut self.correction.b[..p]);
        backward_solve(&self.correction.l[..p * p], p, &mut self.correction.b[..p]);
        let vnorm = self.scaled_norm_step();
        let cnorm = norm(&self.correction.b[..p]);
        if !(cnorm <= max_ratio * vnorm) {
            return false;
        }
        self.correction.step[..p].copy_from_slice(&self.step[..p]);
        for i in 0..p {
            let t = (self.x[i] + self.step[i] + self.correction.b[i] / self.d[i])
                .clamp(self.lo[i], self.hi[i]);
            self.step[i] = t - self.x[i];
            self.x_trial[i] = t;
        }
        true
    }

    /// Puts the uncorrected step back after a corrected one failed.
    pub(super) fn restore_uncorrected_step(&mut self) {
        let p = self.p;
        self.step[..p].copy_from_slice(&self.correction.step[..p]);
    }
}

impl Descent<'_> {
    /// A rejected trial step gets one second-order correction
    /// ([`Safeguards::second_order_correction`](crate::Safeguards::second_order_correction), [`Workspace::corrected_step`]): when the corrected
    /// step is accepted it replaces the trial, judged like any trial but against the uncorrected
    /// step's PREDUC (the model predicted nothing for the correction), else the rejected trial
    /// stands with its step.
    pub(super) fn correct_if_rejected<P: Problem>(
        &mut self,
        ws: &mut Workspace,
        problem: &mut P,
        trial: Trial,
        assessment: Assessment,
    ) -> (Trial, Assessment) {
        // (No longer step is pending here: `trial_step` clears the saved good step before it
        // returns an evaluated trial.)
        if assessment.accepted
            || !self.opt.safeguards.second_order_correction
            || trial.restored
            || self.counts.residuals >= self.opt.limits.evaluations
            || !ws.corrected_step(MAX_CORRECTION)
        {
            return (trial, assessment);
        }
        let (f, reldx) = self.evaluate_trial_point(ws, problem);
        if f.is_finite() {
            let corrected = Trial {
                info: StepInfo {
                    newton: false,
                    dnorm: ws.scaled_norm_step(),
                    ..trial.info
                },
                f,
                reldx,
                restored: false,
            };
            let judged = self.assess(ws, &corrected);
            if judged.accepted {
                return (corrected, judged);
            }
        }
        ws.restore_uncorrected_step();
        (trial, assessment)
    }
}
