//! DA7SST's judgement of a trial step (accept or reject, switch models) and NL2SOL's
//! convergence and stopping tests after it.

use super::descent::Descent;
use super::subproblem::StopPoll;
use super::trial::{Assessment, Trial};
use super::workspace::Workspace;
use crate::linalg::dot;
use crate::{Outcome, Problem, Safeguards};

/// A step is accepted when the actual reduction exceeds this fraction of the predicted one.
pub(super) const ACCEPT_RATIO: f64 = 1e-4;

/// Slack on the bound `||D_F^-1 g_F|| <= sqrt(p rfctol) ||r||` that relative function
/// convergence implies (see [`Workspace::gradient_permits_rel_conv`]).
pub(super) const REL_CONV_GRADIENT_SLACK: f64 = 10.0;

impl Descent<'_> {
    /// Accept or reject the step (actual against predicted reduction), and whether the other
    /// model (adaptive choice) would have predicted the actual reduction better.
    pub(super) fn assess(&self, ws: &mut Workspace, trial: &Trial) -> Assessment {
        let f0 = self.f;
        let ared = f0 - trial.f;
        let ratio = ared / trial.info.preduc;
        let accepted = ared > 0.0 && ratio > ACCEPT_RATIO;
        let mut switch_models = false;
        if self.model.switching && !trial.restored && !(ared > 0.1 * trial.info.preduc) {
            let augmented = self.model.augmented;
            // The augmented model predicts `pred_gn - 0.5 s^T S s`; with the sign reversed the
            // augmented model always looks worse and the adaptive solver never leaves the
            // Gauss-Newton model.
            let (pred, sss) = ws.predicted(augmented);
            let pred_alt = if augmented {
                pred + 0.5 * sss
            } else {
                pred - 0.5 * sss
            };
            if (ared - pred_alt).abs() < (ared - trial.info.preduc).abs() && sss != 0.0 {
                switch_models = true;
            }
        }
        Assessment {
            f0,
            ared,
            ratio,
            accepted,
            switch_models,
        }
    }

    /// NL2SOL's convergence tests after a step, run only when the model is trusted (actual
    /// reduction at most twice PREDUC): X-, relative function and singular convergence.
    pub(super) fn convergence_test<P: Problem>(
        &self,
        ws: &mut Workspace,
        problem: &mut P,
        trial: &Trial,
        a: &Assessment,
    ) -> Option<Outcome> {
        let opt = self.opt;
        let info = &trial.info;
        if !(a.ared <= 2.0 * info.preduc) {
            return None;
        }
        let emax = opt.tolerances.relative_function * a.f0.abs();
        let emaxs = opt.tolerances.singular * a.f0.abs();
        // The gate on the projected gradient (computed at x0 = ws.x, where NREDUC was) keeps a
        // broken NREDUC from claiming convergence; see `gradient_permits_rel_conv`.
        // N2FB judges by the NREDUC of the model in use. With the augmented model that counts
        // only where the Gauss-Newton step exists too (J nonsingular on the free set), so an
        // augmented model that merely predicts no decrease where J is singular cannot claim
        // convergence; without it, a large-residual minimum approached by augmented Newton steps
        // (whose Gauss-Newton NREDUC shrinks only linearly) ended in singular convergence.
        let within = |reduction: f64| reduction > 0.0 && reduction <= emax;
        // A free dead column makes the Gauss-Newton model singular, so its NREDUC (zero at a
        // point where the column vanishes) does not show that f cannot fall: N2FB skips the
        // test when the Newton step does not exist (DST0 < 0), and so do we in every preset.
        let rel = !info.dead_free
            && (within(info.nreduc)
                || (info.nreduc >= 0.0 && within(info.model_nreduc))
                || (info.nreduc == 0.0 && info.preduc == 0.0))
            && ws.gradient_permits_rel_conv(opt.tolerances.relative_function);
        // A restored step is not the last one computed (NL2SOL's GOODX = false).
        let xconv = info.newton && a.accepted && !trial.restored && trial.reldx <= opt.tolerances.x;
        match (xconv, rel) {
            (true, true) => return Some(Outcome::BothConvergence),
            (true, false) => return Some(Outcome::XConvergence),
            (false, true) => return Some(Outcome::RelativeFunctionConvergence),
            (false, false) => {}
        }
        if info.preduc <= emaxs {
            // N2FB tests a step of scaled length LMAXS. When the scaling makes that step tiny
            // next to x itself (huge Jacobian columns, ||D x|| >> LMAXS), a small PREDUC says
            // nothing about singularity: the region is just small and the projected gradient
            // may still be large. So by default the test step is at least as long as x (our
            // change, Safeguards::singular_radius_at_least_x; docs/solver.md).
            let test_radius = if opt.safeguards.singular_radius_at_least_x {
                opt.radius.singular_test.max(ws.scaled_norm_x())
            } else {
                opt.radius.singular_test
            };
            if info.dnorm > test_radius || info.newton {
                return Some(Outcome::SingularConvergence);
            }
            // Re-solve at the test radius from x0 without evaluating f.
            let mut ask = || problem.should_stop();
            let mut poll = StopPoll::new(&mut ask);
            let reduction = ws.singular_test_reduction(
                test_radius,
                self.model.augmented,
                opt.safeguards,
                &mut poll,
            );
            if poll.stopped() {
                return Some(Outcome::Interrupted);
            }
            if reduction <= emaxs {
                return Some(Outcome::SingularConvergence);
            }
        }
        None
    }

    /// The tests after the convergence tests: absolute function convergence after an accepted
    /// step, false convergence after a rejected or poor one whose RELDX is at round-off.
    pub(super) fn stop_test(&self, trial: &Trial, a: &Assessment) -> Option<Outcome> {
        if a.accepted && self.f < self.opt.tolerances.absolute_function {
            return Some(Outcome::AbsoluteFunctionConvergence);
        }
        if (!a.accepted || a.ratio < 0.1) && trial.reldx <= self.opt.tolerances.false_convergence {
            return Some(Outcome::FalseConvergence);
        }
        None
    }
}

impl Workspace {
    /// Whether the scaled projected gradient at `x` is small enough for relative function
    /// convergence. In exact arithmetic `NREDUC = 0.5 ||c_F||^2 <= rfctol f` implies
    /// `||D_F^-1 g_F|| = ||R_F^T c_F|| <= sqrt(p) ||c_F|| <= sqrt(p rfctol) ||r||` (scaled columns
    /// have norm at most 1), so this gate (with [`REL_CONV_GRADIENT_SLACK`]) never blocks a
    /// correctly computed code 4; it blocks one computed from a broken factorization. `g` is
    /// recomputed as `J^T r` from the Jacobian itself, independently of the QR. The free set
    /// is every variable not held on a bound by the sign of its gradient (the KKT conditions);
    /// dead variables count with their true, negligible gradient.
    pub(super) fn gradient_permits_rel_conv(&self, rel_tol: f64) -> bool {
        let (m, p) = (self.m, self.p);
        let mut g2 = 0.0;
        for j in 0..p {
            let gj = dot(&self.jac[j * m..(j + 1) * m], &self.r[..m]);
            let held =
                (self.x[j] <= self.lo[j] && gj >= 0.0) || (self.x[j] >= self.hi[j] && gj <= 0.0);
            if !held {
                let v = gj / self.d[j];
                g2 += v * v;
            }
        }
        let r2 = dot(&self.r[..m], &self.r[..m]);
        let bound = REL_CONV_GRADIENT_SLACK * REL_CONV_GRADIENT_SLACK * p as f64 * rel_tol * r2;
        g2 <= bound
    }

    /// The singular-convergence test step (N2FB): PREDUC of the step re-solved at `radius`
    /// (LMAXS) from the same point without evaluating f; the trial step and lambda are kept.
    /// Meaningless when `poll` says stop.
    pub(super) fn singular_test_reduction(
        &mut self,
        radius: f64,
        augmented: bool,
        safeguards: Safeguards,
        poll: &mut StopPoll<'_>,
    ) -> f64 {
        std::mem::swap(&mut self.step, &mut self.singular_step);
        let saved_lambda = self.lambda;
        let alt = self.compute_step(radius, augmented, safeguards, poll);
        self.lambda = saved_lambda;
        std::mem::swap(&mut self.step, &mut self.singular_step);
        alt.preduc
    }
}
