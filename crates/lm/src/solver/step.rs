//! The bounded step: the active set, the free-set models built from the factorisation, the
//! subproblem solved on them, the cut at the box, and the step's predicted reduction.

use super::factorisation::{triangle_of_qr, triangular_full_rank};
use super::model::{LeastSquaresModel, QuadraticModel, WideLeastSquaresModel};
use super::subproblem::{StopPoll, TrResult, trust_region};
use super::workspace::Workspace;
use crate::Safeguards;
use crate::linalg::{dot, shifted_scratch_len, sym_mat_vec};
use crate::qr::householder_qr;

/// What a step computation produced.
#[derive(Clone, Copy, Debug)]
pub(super) struct StepInfo {
    /// Predicted reduction of the model for the step (PREDUC).
    pub(super) preduc: f64,
    /// Predicted reduction of the full Gauss-Newton (Newton) step on the first free set
    /// (NREDUC), or negative when that step does not exist (singular model).
    pub(super) nreduc: f64,
    /// Predicted reduction of the Newton step of the model in use on the first free set (N2FB's
    /// NREDUC: the augmented model's when it is in use, else equal to `nreduc`), negative when
    /// that step does not exist.
    pub(super) model_nreduc: f64,
    /// Scaled length of the first pass's Newton step (NL2SOL's DST0), negative when it does not
    /// exist.
    pub(super) newton_norm: f64,
    /// The step is the Newton step (STPPAR = 0; a step cut at a bound whose remainder, re-solved on the remaining free
    /// variables, is the Newton step counts too).
    pub(super) newton: bool,
    /// `||D s||`.
    pub(super) dnorm: f64,
    /// A variable not held on a bound has a numerically dead column ([`DEAD_COLUMN`]): the
    /// Gauss-Newton model is singular, so (as in N2FB, which gives code 7 for a zero column) there
    /// is no Newton step and NREDUC does not exist, although the step is computed on the live
    /// variables.
    pub(super) dead_free: bool,
}

impl StepInfo {
    const NONE: StepInfo = StepInfo {
        preduc: 0.0,
        nreduc: -1.0,
        model_nreduc: -1.0,
        newton_norm: -1.0,
        newton: false,
        dnorm: 0.0,
        dead_free: false,
    };
}

impl Workspace {
    /// Builds the model Hessian for the chosen model.
    pub(super) fn build_model(&mut self, augmented: bool) {
        let n = self.p * self.p;
        self.h[..n].copy_from_slice(&self.factors.jtj[..n]);
        if augmented {
            for (h, s) in self.h[..n].iter_mut().zip(&self.secant.s[..n]) {
                *h += s;
            }
        }
    }

    /// Predicted reduction of the model for the step in `self.step`, and `s^T S s` (for the model
    /// switch). The Gauss-Newton part is `-(c^T v + 0.5 v^T v)` with `v = R D s`, which avoids
    /// the squared condition number of `J^T J`.
    pub(super) fn predicted(&mut self, augmented: bool) -> (f64, f64) {
        let p = self.p;
        for i in 0..p {
            self.d_step[i] = self.d[i] * self.step[i];
        }
        for i in 0..p {
            let mut v = 0.0;
            for j in i..p {
                v += self.factors.r[j * p + i] * self.d_step[j];
            }
            self.r_d_step[i] = v;
        }
        let pred_gn = -(dot(&self.factors.c[..p], &self.r_d_step[..p])
            + 0.5 * dot(&self.r_d_step[..p], &self.r_d_step[..p]));
        sym_mat_vec(&self.secant.s, &self.step, p, &mut self.s_step);
        let sss = dot(&self.step[..p], &self.s_step[..p]);
        let pred = if augmented {
            pred_gn - 0.5 * sss
        } else {
            pred_gn
        };
        (pred, sss)
    }

    /// Holds a variable on a bound whose gradient points out of the box (and a variable whose
    /// bounds coincide), and clears the step.
    /// A numerically dead variable is held too; returns whether one of them is not held by a
    /// bound (then the Gauss-Newton model is singular: [`StepInfo::dead_free`]).
    ///
    /// A held dead column's `g` is exactly 0, which would read as "held by its bound" for any
    /// dead variable on a bound: a lobe killed with its exponent on the upper bound then let
    /// codes 4 and 5 fire once the live variables converged, although lowering the exponent
    /// lowers f. So a held dead variable is judged by its true gradient `J^T r`, as N2FB (which
    /// holds nothing) and the searches' preset judge it.
    pub(super) fn hold_active_bounds(&mut self) -> bool {
        let mut dead_free = false;
        for i in 0..self.p {
            let at_lo = self.x[i] <= self.lo[i];
            let at_hi = self.x[i] >= self.hi[i];
            let g = if self.factors.dead[i] {
                self.factors.jtr[i]
            } else {
                self.g[i]
            };
            let bound = (at_lo && g >= 0.0) || (at_hi && g <= 0.0) || (at_lo && at_hi);
            dead_free |= self.factors.dead_seen[i] && !bound;
            self.fixed[i] = bound || self.factors.dead[i];
            self.step[i] = 0.0;
        }
        dead_free
    }

    /// Lists the free variables in `free`; returns their number.
    pub(super) fn collect_free(&mut self) -> usize {
        let mut n = 0;
        for i in 0..self.p {
            if !self.fixed[i] {
                self.free[n] = i;
                n += 1;
            }
        }
        n
    }

    /// The free-set Gauss-Newton model at the partial step `s` in least-squares form
    /// `0.5 ||u + T z||^2` (`ls_t` = T, `ls_u` = u).
    pub(super) fn build_least_squares_model(&mut self, n: usize, first: bool) {
        let p = self.p;
        if n == p && first {
            // Nothing held and no partial step yet: the free-set model is R itself.
            self.sub.t[..p * p].copy_from_slice(&self.factors.r[..p * p]);
            self.sub.u[..p].copy_from_slice(&self.factors.c[..p]);
            return;
        }
        // c' = c + R D s, then QR of [R_F | c'] gives the free-set model. R and c are zero below
        // row min(m, p), so only those rows take part: the same result, and with a subsample
        // smaller than the model (m << p) a much cheaper QR.
        for i in 0..p {
            self.d_step[i] = self.d[i] * self.step[i];
        }
        let rows = self.m.min(p);
        for a in 0..n {
            let ia = self.free[a];
            self.sub.block[a * rows..(a + 1) * rows]
                .copy_from_slice(&self.factors.r[ia * p..ia * p + rows]);
        }
        for i in 0..rows {
            let mut v = self.factors.c[i];
            for j in i..p {
                v += self.factors.r[j * p + i] * self.d_step[j];
            }
            self.sub.rhs[i] = v;
        }
        householder_qr(
            &mut self.sub.block[..rows * n],
            rows,
            n,
            &mut self.sub.rhs[..rows],
        );
        triangle_of_qr(
            &self.sub.block[..rows * n],
            rows,
            &self.sub.rhs[..rows],
            n,
            &mut self.sub.t[..n * n],
            &mut self.sub.u[..n],
        );
    }

    /// The free-set model at the partial step `s` in normal form (augmented model): scaled
    /// model gradient `D^-1 (g + H s)` and scaled Hessian `D^-1 H D^-1` of the free variables.
    pub(super) fn build_quadratic_model(&mut self, n: usize) {
        let p = self.p;
        sym_mat_vec(&self.h, &self.step, p, &mut self.g_model);
        for i in 0..p {
            self.g_model[i] += self.g[i];
        }
        for a in 0..n {
            let ia = self.free[a];
            self.sub.g[a] = self.g_model[ia] / self.d[ia];
            for b in 0..n {
                let ib = self.free[b];
                self.sub.h[a * n + b] = self.h[ia * p + ib] / (self.d[ia] * self.d[ib]);
            }
        }
    }

    /// Largest fraction `alpha <= 1` of the free-set sub-step `z` (scaled) that keeps
    /// `x + s + alpha D^-1 z` in the box, and the variable (and whether its upper bound) that
    /// limits it.
    pub(super) fn feasible_fraction(&self, n: usize) -> (f64, Option<(usize, bool)>) {
        let mut alpha = 1.0f64;
        let mut hit = None;
        for a in 0..n {
            let i = self.free[a];
            let ds = self.sub.z[a] / self.d[i];
            let cur = self.x[i] + self.step[i];
            if ds > 0.0 && cur + ds > self.hi[i] {
                let t = ((self.hi[i] - cur) / ds).max(0.0);
                if t < alpha {
                    alpha = t;
                    hit = Some((i, true));
                }
            } else if ds < 0.0 && cur + ds < self.lo[i] {
                let t = ((self.lo[i] - cur) / ds).max(0.0);
                if t < alpha {
                    alpha = t;
                    hit = Some((i, false));
                }
            }
        }
        (alpha, hit)
    }

    /// Solves the free-set trust-region subproblem of the chosen model (its least-squares form
    /// built) within `radius` into `sub_z`: the augmented model in normal form, the
    /// Gauss-Newton model in its dual form when it has fewer rows than free variables, else by
    /// Givens rotations.
    pub(super) fn solve_subproblem(
        &mut self,
        n: usize,
        radius: f64,
        augmented: bool,
        safeguards: Safeguards,
        poll: &mut StopPoll<'_>,
    ) -> TrResult {
        let stop_at_min_norm = safeguards.stop_at_minimum_norm_step;
        if augmented {
            self.build_quadratic_model(n);
        }
        let lambda = self.lambda;
        let z = &mut self.sub.z[..n];
        let scratch = (&mut self.sub.best[..], &mut self.sub.q[..]);
        if augmented {
            let mut sub = QuadraticModel {
                n,
                h: &self.sub.h[..n * n],
                g: &self.sub.g[..n],
                chol: &mut self.sub.chol[..n * n],
            };
            trust_region(&mut sub, radius, lambda, stop_at_min_norm, poll, z, scratch)
        } else if self.m < n {
            let k = self.m;
            let mut sub = WideLeastSquaresModel {
                n,
                k,
                t: &self.sub.t[..n * n],
                u: &self.sub.u[..n],
                gram: &mut self.sub.gram[..k * k],
                chol: &mut self.sub.wide_chol[..k * k],
                w: &mut self.sub.w[..k],
                v: &mut self.sub.v[..k],
            }
            .with_gram();
            trust_region(&mut sub, radius, lambda, stop_at_min_norm, poll, z, scratch)
        } else {
            let mut sub = LeastSquaresModel {
                n,
                t: &self.sub.t[..n * n],
                u: &self.sub.u[..n],
                t_lambda: &mut self.sub.t_lambda[..n * n],
                u_lambda: &mut self.sub.u_lambda[..n],
                row: &mut self.sub.row[..shifted_scratch_len(n)],
                scale_tiny: safeguards.scale_tiny_rotations,
            };
            trust_region(&mut sub, radius, lambda, stop_at_min_norm, poll, z, scratch)
        }
    }

    /// Computes the bounded step from `x` within scaled radius `radius` into `self.step`.
    ///
    /// Active set: a variable on a bound whose gradient points out of the box is held. The
    /// trust-region subproblem is solved on the free variables; when the step leaves the box it is
    /// cut where it first reaches a bound, that variable is held there, and the rest of the step
    /// is re-solved from the cut point (model gradient `g + H s`, remaining radius).
    /// When `poll` says stop, the step is unfinished: the caller checks [`StopPoll::stopped`].
    pub(super) fn compute_step(
        &mut self,
        radius: f64,
        augmented: bool,
        safeguards: Safeguards,
        poll: &mut StopPoll<'_>,
    ) -> StepInfo {
        let p = self.p;
        let dead_free = self.hold_active_bounds();
        let mut info = StepInfo::NONE;
        let mut remaining = radius;
        let mut first = true;
        for _pass in 0..=p {
            let n = self.collect_free();
            if n == 0 {
                break;
            }
            // The Gauss-Newton free-set model. The augmented model needs it on the first pass
            // too: relative function convergence is always judged by the Gauss-Newton
            // reduction 0.5 ||u||^2, which vanishes at every stationary point and does not exist
            // where J is singular (so an augmented model that merely predicts no decrease cannot
            // claim convergence).
            let mut nreduc_gn = -1.0;
            if !augmented || first {
                self.build_least_squares_model(n, first);
                if augmented && triangular_full_rank(&self.sub.t[..n * n], n) {
                    nreduc_gn = 0.5 * dot(&self.sub.u[..n], &self.sub.u[..n]);
                }
            }
            let tr = self.solve_subproblem(n, remaining, augmented, safeguards, poll);
            if poll.stopped() {
                return info;
            }
            self.lambda = tr.lambda;
            if first {
                info.nreduc = if augmented {
                    nreduc_gn
                } else {
                    tr.newton_reduction
                };
                info.model_nreduc = tr.newton_reduction;
                info.newton_norm = tr.newton_norm;
            }
            // N2FB's STPPAR: whether the last sub-step solved is the Newton step (lambda = 0).
            info.newton = tr.is_newton;
            let (alpha, hit) = self.feasible_fraction(n);
            for a in 0..n {
                let i = self.free[a];
                self.step[i] += alpha * self.sub.z[a] / self.d[i];
            }
            let Some((hit, hit_upper)) = hit else {
                break;
            };
            info.newton = false;
            // A variable sitting on its bound whose step leaves the box at once (alpha = 0,
            // nothing moved yet) is active: the free set excludes it, so NREDUC (and STPPAR)
            // are those of the next pass, the problem restricted to the truly free variables.
            if first && !(alpha > 0.0) {
                self.fixed[hit] = true;
                continue;
            }
            first = false;
            self.step[hit] = if hit_upper {
                self.hi[hit] - self.x[hit]
            } else {
                self.lo[hit] - self.x[hit]
            };
            self.fixed[hit] = true;
            let used = self.scaled_norm_step();
            let rem2 = radius * radius - used * used;
            if rem2 <= (1e-6 * radius) * (1e-6 * radius) {
                break;
            }
            remaining = rem2.sqrt();
        }
        // Keep x + s inside the box exactly (round-off in the cut).
        for i in 0..p {
            let t = (self.x[i] + self.step[i]).clamp(self.lo[i], self.hi[i]);
            self.step[i] = t - self.x[i];
        }
        let (pred, _) = self.predicted(augmented);
        info.preduc = pred;
        info.dnorm = self.scaled_norm_step();
        // A free dead column makes the model singular in every preset (`dead_free` bars the
        // success codes). Only when such columns are held is NREDUC that of another problem
        // (the held variables' model) and dropped; left free, the step and its radius update
        // keep the factorization's numbers.
        info.dead_free = dead_free;
        if dead_free && self.factors.dead[..p].iter().any(|&d| d) {
            info.nreduc = -1.0;
            info.model_nreduc = -1.0;
            info.newton_norm = -1.0;
            info.newton = false;
        }
        info
    }
}
