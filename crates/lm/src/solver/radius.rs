//! The trust radius and NL2SOL's bookkeeping for changing it (DA7SST, DG7ITB): the factor
//! RADFAC after each assessed step, the longer step tried from the same point, and DG7ITB's
//! gradient tests.

use super::trial::{Assessment, Trial};
use super::workspace::Workspace;
use crate::RadiusUpdate;

/// At most this many longer steps are tried from the same point in one iteration.
pub(super) const MAX_RADINC: i32 = 1;

/// The trust radius and NL2SOL's bookkeeping for changing it (DA7SST, DG7ITB).
#[derive(Clone, Copy, Debug)]
pub(super) struct TrustRadius {
    pub(super) rule: RadiusUpdate,
    /// The radius in the scaled norm `||D s||` (V(RADIUS)).
    pub(super) radius: f64,
    /// RADFAC of the last accepted step: the radius becomes RADFAC * ||D_new s|| once the new
    /// scaling is known (0: nothing pending).
    pub(super) pending_factor: f64,
    /// RADINC: radius decreases (negative) and longer steps tried (positive) in this iteration;
    /// after a decrease a good step keeps the radius instead of increasing it.
    pub(super) radinc: i32,
}

/// How the radius changes after an assessed step ([`TrustRadius::after_step`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct RadiusChange {
    /// RADFAC (N2FB's rule; 0 for the classic rule, which changes the radius at once).
    pub(super) factor: f64,
    /// Try the longer step at once from the same point (DA7SST's IRC = 5).
    pub(super) try_longer: bool,
}

impl TrustRadius {
    /// Starts an iteration: applies the factor of the last accepted step with the new scaling.
    /// N2FB (DG7ITB): `t = RADFAC * ||D_new s||`; the radius becomes t when RADFAC < 1 or t is
    /// larger, so a short step never shrinks it otherwise; RADFAC 1 becomes 2 when the gradient
    /// tests pass.
    pub(super) fn start_iteration(&mut self, ws: &Workspace) {
        self.radinc = 0;
        if self.rule == RadiusUpdate::Nl2sol && self.pending_factor > 0.0 {
            if self.pending_factor == 1.0 && ws.gradient_tests() {
                self.pending_factor = 2.0;
            }
            let t = self.pending_factor * ws.scaled_norm_last_step();
            if self.pending_factor < 1.0 || t > self.radius {
                self.radius = t;
            }
            self.pending_factor = 0.0;
        }
    }

    /// After a step whose residuals could not be evaluated.
    pub(super) fn after_failed_evaluation(&mut self, dnorm: f64) {
        self.radius = 0.5 * dnorm.min(self.radius);
        self.radinc -= 1;
    }

    /// After a failed Jacobian at an accepted point (the solver returns to the previous point).
    pub(super) fn after_failed_jacobian(&mut self) {
        self.radius *= 0.5;
        self.pending_factor = 0.0;
    }

    /// DA7SST's radius decision for an assessed step; `gts` = `g^T s`. A rejected step changes
    /// the radius at once; an accepted one leaves RADFAC to be applied by
    /// [`TrustRadius::start_iteration`] (N2FB's rule). `switching`: the adaptive model choice
    /// may switch models in this iteration; then no longer step is tried (our departure from
    /// NL2SOL, measured in `docs/solver.md`, "Trust radius").
    pub(super) fn after_step(
        &mut self,
        trial: &Trial,
        a: &Assessment,
        gts: f64,
        switching: bool,
    ) -> RadiusChange {
        let info = &trial.info;
        let mut change = RadiusChange {
            factor: 0.0,
            try_longer: false,
        };
        match self.rule {
            RadiusUpdate::Nl2sol => {
                change.factor = if !a.accepted || a.ared <= 0.1 * info.preduc {
                    // Fletcher's decrease factor: minimiser of the quadratic through f0, the
                    // slope g^T s and f_trial along the step, within [0.1, 0.5].
                    let emax = gts + a.ared;
                    if emax < gts {
                        (0.5 * gts / emax).max(0.1)
                    } else {
                        0.5
                    }
                } else if !trial.restored && self.radinc >= 0 && a.ared >= -0.75 * gts {
                    // Good decrease, at least 3/4 of the linear prediction -g^T s (not of
                    // PREDUC: with lambda near 0, -g^T s is twice PREDUC), and no decrease
                    // earlier in this iteration: factor 2..4. Unless this was the Newton step,
                    // or the Newton step is less than twice as long or predicts less than 1.2
                    // times this reduction, the longer step is tried at once from the same point
                    // (IRC = 5, no new Jacobian).
                    let mut up = 4.0;
                    if a.ared < (0.5 / up - 1.0) * gts {
                        up = (0.5 * gts / (gts + a.ared)).max(2.0);
                    }
                    let newton_close = info.newton_norm >= 0.0
                        && (info.newton_norm < 2.0 * info.dnorm || info.nreduc < 1.2 * a.ared);
                    change.try_longer =
                        !info.newton && !newton_close && !switching && self.radinc < MAX_RADINC;
                    up
                } else {
                    1.0
                };
                if !a.accepted {
                    self.radius = change.factor * info.dnorm;
                    self.radinc -= 1;
                }
            }
            RadiusUpdate::Classic => {
                if !a.accepted {
                    // Minimiser of the quadratic through f0, slope g^T s, and f_trial along the
                    // step.
                    let denom = 2.0 * (trial.f - a.f0 - gts);
                    let t = if denom > 0.0 { -gts / denom } else { 0.5 };
                    self.radius = t.clamp(0.1, 0.5) * info.dnorm.min(self.radius);
                } else if a.ratio < 0.25 {
                    self.radius = 0.5 * info.dnorm.min(self.radius).max(0.25 * self.radius);
                } else if a.ratio > 0.75 {
                    self.radius = (4.0 * self.radius).min(self.radius.max(2.0 * info.dnorm));
                }
            }
        }
        change
    }

    /// A longer step is tried from the same point (IRC = 5).
    pub(super) fn try_longer(&mut self, factor: f64, dnorm: f64) {
        self.radinc += 1;
        self.radius = factor * dnorm;
    }
}

impl Workspace {
    /// N2FB's gradient tests (DG7ITB) after a step accepted with the radius unchanged, with
    /// `h_step` = model Hessian times the step (at the old point), `g_prev` the old gradient and
    /// `g` the new one: the radius may still double when the model predicted the new gradient
    /// well, `||D^-1 (H s + g_old - g_new)|| <= 0.5 ||D^-1 g_new||` (free variables), or when the
    /// slope along the step is still at least 3/4 of the old one, `g_new^T s < 0.75 g_old^T s`.
    pub(super) fn gradient_tests(&self) -> bool {
        let mut err2 = 0.0;
        let mut gn2 = 0.0;
        let mut gts_new = 0.0;
        let mut gts_old = 0.0;
        for i in 0..self.p {
            let s = self.x[i] - self.x_prev[i];
            gts_new += self.g[i] * s;
            gts_old += self.g_prev[i] * s;
            let e = (self.h_step[i] + self.g_prev[i] - self.g[i]) / self.d[i];
            err2 += e * e;
            let held = self.lo[i] >= self.hi[i]
                || (self.x[i] <= self.lo[i] && self.g[i] > 0.0)
                || (self.x[i] >= self.hi[i] && self.g[i] < 0.0);
            if !held {
                let v = self.g[i] / self.d[i];
                gn2 += v * v;
            }
        }
        err2.sqrt() <= 0.5 * gn2.sqrt() || gts_new < 0.75 * gts_old
    }
}
