//! The N2FB-style iteration: scaled trust-region Levenberg-Marquardt with an active set for the
//! bounds, NL2SOL's convergence tests and (optionally) its adaptive augmented model.

use crate::linalg::{
    backward_solve, cholesky_shifted, dot, forward_solve, householder_qr, jt_vec, norm,
    shifted_triangular, sym_mat_vec, upper_solve, upper_transpose_solve,
};
use crate::{Options, Outcome, Problem, RadiusUpdate, Report, SolveError, StepModel};

/// Relative pivot threshold at which the augmented model `D^-1 (J^T J + S) D^-1` counts as
/// singular or indefinite (no Newton step).
const RANK_TOL: f64 = 1e-14;
/// Relative size of a diagonal entry of the triangular factor of the scaled free Jacobian below
/// which the Gauss-Newton model counts as singular (no Gauss-Newton step).
const QR_RANK_TOL: f64 = 1e-13;
/// Relative pivot threshold for shifted (lambda > 0) factorizations.
const SHIFTED_TOL: f64 = 1e-15;
/// Accepted relative error of the constrained step length (NL2SOL's EPSLON).
const RADIUS_SLACK: f64 = 0.1;
/// At most this many longer steps are tried from the same point in one iteration.
const MAX_RADINC: i32 = 1;
/// A step is accepted when the actual reduction exceeds this fraction of the predicted one.
const ACCEPT_RATIO: f64 = 1e-4;

/// Bounded trust-region Levenberg-Marquardt solver.
///
/// The solver owns its workspace; buffers only grow, so repeated solves of the same or a smaller
/// size allocate nothing.
#[derive(Clone, Debug, Default)]
pub struct Solver {
    ws: Workspace,
}

/// All buffers of a solve (grow-only).
#[derive(Clone, Debug, Default)]
struct Workspace {
    m: usize,
    p: usize,
    x: Vec<f64>,
    x_trial: Vec<f64>,
    x_prev: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    r: Vec<f64>,
    r_trial: Vec<f64>,
    r_prev: Vec<f64>,
    jac: Vec<f64>,
    /// Copy of `J D^-1` reduced in place by Householder QR.
    qr: Vec<f64>,
    /// `Q^T r` work vector (length m).
    rq: Vec<f64>,
    /// `R` of `J D^-1 = Q R` (p x p upper, rows beyond m zero).
    rmat: Vec<f64>,
    /// First p entries of `Q^T r`.
    cvec: Vec<f64>,
    /// `[R_F | c']` reduced to `[T | u]` for the free set.
    bmat: Vec<f64>,
    d: Vec<f64>,
    jtj: Vec<f64>,
    g: Vec<f64>,
    g_prev: Vec<f64>,
    /// Secant approximation of the second-order term (augmented model).
    s_mat: Vec<f64>,
    /// The model Hessian in use (`jtj` or `jtj + s_mat`).
    h: Vec<f64>,
    step: Vec<f64>,
    step_alt: Vec<f64>,
    gm: Vec<f64>,
    hs: Vec<f64>,
    fixed: Vec<bool>,
    free: Vec<usize>,
    sub_h: Vec<f64>,
    sub_l: Vec<f64>,
    sub_g: Vec<f64>,
    sub_z: Vec<f64>,
    sub_q: Vec<f64>,
    sub_best: Vec<f64>,
    sub_u: Vec<f64>,
    sub_w: Vec<f64>,
    shat: Vec<f64>,
    vtmp: Vec<f64>,
    y: Vec<f64>,
    ysharp: Vec<f64>,
    w: Vec<f64>,
    /// A good trial point, its residuals and step, saved while a longer step is tried.
    x_good: Vec<f64>,
    r_good: Vec<f64>,
    step_good: Vec<f64>,
    /// Last Levenberg-Marquardt parameter, a warm start for the next subproblem.
    lambda: f64,
}

/// What a step computation produced.
#[derive(Clone, Copy, Debug)]
struct StepInfo {
    /// Predicted reduction of the model for the step.
    preduc: f64,
    /// Predicted reduction of the full Gauss-Newton (Newton) step on the first free set, or
    /// negative when that step does not exist (singular model).
    nreduc: f64,
    /// Scaled length of the first pass's Newton step (NL2SOL's DST0), negative when it does not
    /// exist.
    newton_norm: f64,
    /// The step is the unconstrained Newton step (lambda 0, not cut by a bound).
    newton: bool,
    /// `||D s||`.
    dnorm: f64,
}

fn grow(v: &mut Vec<f64>, n: usize) {
    v.resize(n, 0.0);
}

impl Workspace {
    fn prepare(&mut self, m: usize, p: usize) {
        self.m = m;
        self.p = p;
        for v in [
            &mut self.x,
            &mut self.x_trial,
            &mut self.x_prev,
            &mut self.lo,
            &mut self.hi,
            &mut self.d,
            &mut self.g,
            &mut self.g_prev,
            &mut self.step,
            &mut self.step_alt,
            &mut self.x_good,
            &mut self.step_good,
            &mut self.gm,
            &mut self.hs,
            &mut self.sub_g,
            &mut self.sub_z,
            &mut self.sub_q,
            &mut self.sub_best,
            &mut self.sub_u,
            &mut self.sub_w,
            &mut self.shat,
            &mut self.vtmp,
            &mut self.cvec,
            &mut self.y,
            &mut self.ysharp,
            &mut self.w,
        ] {
            grow(v, p);
        }
        for v in [
            &mut self.r,
            &mut self.r_trial,
            &mut self.r_prev,
            &mut self.r_good,
            &mut self.rq,
        ] {
            grow(v, m);
        }
        grow(&mut self.jac, m * p);
        grow(&mut self.qr, m * p);
        grow(&mut self.bmat, p * (p + 1));
        for v in [
            &mut self.jtj,
            &mut self.rmat,
            &mut self.s_mat,
            &mut self.h,
            &mut self.sub_h,
            &mut self.sub_l,
        ] {
            grow(v, p * p);
        }
        self.fixed.resize(p, false);
        self.free.resize(p, 0);
        self.lambda = 0.0;
    }

    /// Updates the scaling: `D_i = max(0.6 D_i, ||J_i||_2)` (N2FB's adaptive rule, but with the
    /// column 2-norm of the original NL2SOL instead of the column max); a column whose norm is
    /// below 1e-6 uses 1 instead, so a dead parameter keeps a sane scale. Measured on NIST (GN
    /// model, default budgets): this rule 50/54, column max 44/54, non-decreasing 2-norm
    /// (MINPACK) 49/54.
    fn update_scaling(&mut self, first: bool) {
        let m = self.m;
        for j in 0..self.p {
            let cn = norm(&self.jac[j * m..(j + 1) * m]);
            let cand = if cn < 1e-6 { 1.0 } else { cn };
            self.d[j] = if first {
                cand
            } else {
                cand.max(0.6 * self.d[j])
            };
        }
    }

    /// QR of the scaled Jacobian `J D^-1 = Q R`, `c = Q^T r`, and from them `J^T J` and
    /// `g = J^T r` (unscaled) for the augmented model, the secant update and the active set.
    fn factor_jacobian(&mut self) {
        let (m, p) = (self.m, self.p);
        for j in 0..p {
            let inv = 1.0 / self.d[j];
            for (q, &v) in self.qr[j * m..(j + 1) * m]
                .iter_mut()
                .zip(&self.jac[j * m..(j + 1) * m])
            {
                *q = v * inv;
            }
        }
        self.rq[..m].copy_from_slice(&self.r[..m]);
        householder_qr(&mut self.qr[..m * p], m, p, &mut self.rq[..m]);
        for j in 0..p {
            for i in 0..p {
                self.rmat[j * p + i] = if i <= j && i < m {
                    self.qr[j * m + i]
                } else {
                    0.0
                };
            }
            self.cvec[j] = if j < m { self.rq[j] } else { 0.0 };
        }
        for j in 0..p {
            let cj = &self.rmat[j * p..(j + 1) * p];
            self.g[j] = self.d[j] * dot(cj, &self.cvec[..p]);
            for k in 0..=j {
                let v = self.d[j] * self.d[k] * dot(cj, &self.rmat[k * p..(k + 1) * p]);
                self.jtj[j * p + k] = v;
                self.jtj[k * p + j] = v;
            }
        }
    }

    /// Builds the model Hessian for the chosen model.
    fn build_model(&mut self, augmented: bool) {
        let n = self.p * self.p;
        self.h[..n].copy_from_slice(&self.jtj[..n]);
        if augmented {
            for (h, s) in self.h[..n].iter_mut().zip(&self.s_mat[..n]) {
                *h += s;
            }
        }
    }

    /// `RELDX = max_i D_i |a_i - b_i| / max_i D_i (|a_i| + |b_i|)`.
    fn reldx(&self, a: &[f64], b: &[f64]) -> f64 {
        let mut num = 0.0f64;
        let mut den = 0.0f64;
        for i in 0..self.p {
            num = num.max(self.d[i] * (a[i] - b[i]).abs());
            den = den.max(self.d[i] * (a[i].abs() + b[i].abs()));
        }
        if den > 0.0 { num / den } else { 0.0 }
    }

    /// Predicted reduction of the model for the step in `self.step`, and `s^T S s` (for the model
    /// switch). The Gauss-Newton part is `-(c^T v + 0.5 v^T v)` with `v = R D s`, which avoids
    /// the squared condition number of `J^T J`.
    fn predicted(&mut self, augmented: bool) -> (f64, f64) {
        let p = self.p;
        for i in 0..p {
            self.shat[i] = self.d[i] * self.step[i];
        }
        for i in 0..p {
            let mut v = 0.0;
            for j in i..p {
                v += self.rmat[j * p + i] * self.shat[j];
            }
            self.vtmp[i] = v;
        }
        let pred_gn =
            -(dot(&self.cvec[..p], &self.vtmp[..p]) + 0.5 * dot(&self.vtmp[..p], &self.vtmp[..p]));
        sym_mat_vec(&self.s_mat, &self.step, p, &mut self.hs);
        let sss = dot(&self.step[..p], &self.hs[..p]);
        let pred = if augmented {
            pred_gn - 0.5 * sss
        } else {
            pred_gn
        };
        (pred, sss)
    }

    /// Computes the bounded step from `x` within scaled radius `radius` into `self.step`.
    ///
    /// Active set: a variable on a bound whose gradient points out of the box is held. The
    /// trust-region subproblem is solved on the free variables; when the step leaves the box it is
    /// cut where it first reaches a bound, that variable is held there, and the rest of the step
    /// is re-solved from the cut point (model gradient `g + H s`, remaining radius).
    fn compute_step(&mut self, radius: f64, augmented: bool) -> StepInfo {
        let p = self.p;
        for i in 0..p {
            let at_lo = self.x[i] <= self.lo[i];
            let at_hi = self.x[i] >= self.hi[i];
            self.fixed[i] =
                (at_lo && self.g[i] >= 0.0) || (at_hi && self.g[i] <= 0.0) || (at_lo && at_hi);
            self.step[i] = 0.0;
        }
        let mut info = StepInfo {
            preduc: 0.0,
            nreduc: -1.0,
            newton_norm: -1.0,
            newton: false,
            dnorm: 0.0,
        };
        let mut remaining = radius;
        let mut first = true;
        for _pass in 0..=p {
            let mut n = 0;
            for i in 0..p {
                if !self.fixed[i] {
                    self.free[n] = i;
                    n += 1;
                }
            }
            if n == 0 {
                break;
            }
            // The Gauss-Newton free-set model 0.5 ||u + T z||^2 (sub_h = T, sub_u = u). The
            // augmented model needs it on the first pass too: relative function convergence is
            // always judged by the Gauss-Newton reduction 0.5 ||u||^2, which vanishes at every
            // stationary point and does not exist where J is singular (so an augmented model
            // that merely predicts no decrease cannot claim convergence).
            let mut nreduc_gn = -1.0;
            if !augmented || first {
                if n == p && first {
                    // Nothing held and no partial step yet: the free-set model is R itself.
                    self.sub_h[..p * p].copy_from_slice(&self.rmat[..p * p]);
                    self.sub_u[..p].copy_from_slice(&self.cvec[..p]);
                } else {
                    // Least-squares form: c' = c + R D s, then QR of [R_F | c'] gives the free-set
                    // model 0.5 ||u + T z||^2.
                    for i in 0..p {
                        self.shat[i] = self.d[i] * self.step[i];
                    }
                    let rows = p;
                    for a in 0..n {
                        let ia = self.free[a];
                        self.bmat[a * rows..(a + 1) * rows]
                            .copy_from_slice(&self.rmat[ia * p..(ia + 1) * p]);
                    }
                    for i in 0..p {
                        let mut v = self.cvec[i];
                        for j in i..p {
                            v += self.rmat[j * p + i] * self.shat[j];
                        }
                        self.sub_w[i] = v;
                    }
                    householder_qr(&mut self.bmat[..rows * n], rows, n, &mut self.sub_w[..rows]);
                    for b in 0..n {
                        for a in 0..n {
                            self.sub_h[b * n + a] =
                                if a <= b { self.bmat[b * rows + a] } else { 0.0 };
                        }
                        self.sub_u[b] = self.sub_w[b];
                    }
                }
                if augmented {
                    let dmax = (0..n).fold(0.0f64, |a, i| a.max(self.sub_h[i * n + i].abs()));
                    if dmax > 0.0
                        && (0..n).all(|i| self.sub_h[i * n + i].abs() > QR_RANK_TOL * dmax)
                    {
                        nreduc_gn = 0.5 * dot(&self.sub_u[..n], &self.sub_u[..n]);
                    }
                }
            }
            if augmented {
                // Normal-equation form: model gradient at the partial step and the scaled
                // Hessian of the free variables.
                sym_mat_vec(&self.h, &self.step, p, &mut self.gm);
                for i in 0..p {
                    self.gm[i] += self.g[i];
                }
                for a in 0..n {
                    let ia = self.free[a];
                    self.sub_g[a] = self.gm[ia] / self.d[ia];
                    for b in 0..n {
                        let ib = self.free[b];
                        self.sub_h[a * n + b] = self.h[ia * p + ib] / (self.d[ia] * self.d[ib]);
                    }
                }
            }
            let tr = trust_region(
                Sub {
                    n,
                    qr: !augmented,
                    h: &self.sub_h[..n * n],
                    g: if augmented {
                        &self.sub_g[..n]
                    } else {
                        &self.sub_u[..n]
                    },
                    l: &mut self.sub_l[..n * n],
                    ul: &mut self.sub_q[..n],
                    w: &mut self.sub_best[..n],
                },
                remaining,
                self.lambda,
                &mut self.sub_z[..n],
                &mut self.vtmp[..n],
            );
            self.lambda = tr.lambda;
            if first {
                info.nreduc = if augmented {
                    nreduc_gn
                } else {
                    tr.newton_reduction
                };
                info.newton_norm = tr.newton_norm;
            }
            // N2FB's STPPAR: whether the last sub-step solved is the Newton step (lambda = 0).
            info.newton = tr.is_newton;
            // Largest feasible fraction of the sub-step.
            let mut alpha = 1.0f64;
            let mut hit = usize::MAX;
            let mut hit_upper = false;
            for a in 0..n {
                let i = self.free[a];
                let ds = self.sub_z[a] / self.d[i];
                let cur = self.x[i] + self.step[i];
                if ds > 0.0 && cur + ds > self.hi[i] {
                    let t = ((self.hi[i] - cur) / ds).max(0.0);
                    if t < alpha {
                        alpha = t;
                        hit = i;
                        hit_upper = true;
                    }
                } else if ds < 0.0 && cur + ds < self.lo[i] {
                    let t = ((self.lo[i] - cur) / ds).max(0.0);
                    if t < alpha {
                        alpha = t;
                        hit = i;
                        hit_upper = false;
                    }
                }
            }
            for a in 0..n {
                let i = self.free[a];
                self.step[i] += alpha * self.sub_z[a] / self.d[i];
            }
            if hit == usize::MAX {
                break;
            }
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
        info
    }

    /// N2FB's gradient tests (DG7ITB) after a step accepted with the radius unchanged, with `w`
    /// = model Hessian times the step (at the old point), `g_prev` the old gradient and `g` the
    /// new one: the radius may still double when the model predicted the new gradient well,
    /// `||D^-1 (H s + g_old - g_new)|| <= 0.5 ||D^-1 g_new||` (free variables), or when the
    /// slope along the step is still at least 3/4 of the old one, `g_new^T s < 0.75 g_old^T s`.
    fn gradient_tests(&self) -> bool {
        let mut err2 = 0.0;
        let mut gn2 = 0.0;
        let mut gts_new = 0.0;
        let mut gts_old = 0.0;
        for i in 0..self.p {
            let s = self.x[i] - self.x_prev[i];
            gts_new += self.g[i] * s;
            gts_old += self.g_prev[i] * s;
            let e = (self.w[i] + self.g_prev[i] - self.g[i]) / self.d[i];
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

    /// Swaps the trial point, its residuals and the step with the saved good ones (saving one,
    /// or restoring it; buffers are swapped, not copied).
    fn swap_good(&mut self) {
        std::mem::swap(&mut self.x_trial, &mut self.x_good);
        std::mem::swap(&mut self.r_trial, &mut self.r_good);
        std::mem::swap(&mut self.step, &mut self.step_good);
    }

    fn scaled_norm_step(&self) -> f64 {
        let mut s = 0.0;
        for i in 0..self.p {
            let v = self.d[i] * self.step[i];
            s += v * v;
        }
        s.sqrt()
    }

    /// NL2SOL's secant update of `S` after an accepted step (`step` = s, `y` = gradient change,
    /// `ysharp` = `(J_new - J_old)^T r_new`), with Dennis-Gay-Welsch sizing.
    fn secant_update(&mut self) {
        let p = self.p;
        sym_mat_vec(&self.s_mat, &self.step, p, &mut self.w);
        let sss = dot(&self.step[..p], &self.w[..p]);
        let sy_sharp = dot(&self.step[..p], &self.ysharp[..p]);
        if sss != 0.0 {
            let tau = (sy_sharp / sss).abs().min(1.0);
            for v in self.s_mat[..p * p].iter_mut() {
                *v *= tau;
            }
            for v in self.w[..p].iter_mut() {
                *v *= tau;
            }
        }
        let sy = dot(&self.step[..p], &self.y[..p]);
        // Skip the update when the curvature information is useless (s^T y ~ 0).
        if !(sy.abs() > 1e-30 * norm(&self.step[..p]) * norm(&self.y[..p])) || sy == 0.0 {
            return;
        }
        for i in 0..p {
            self.w[i] = self.ysharp[i] - self.w[i];
        }
        let ws = dot(&self.w[..p], &self.step[..p]);
        for j in 0..p {
            for i in 0..p {
                let v = (self.w[i] * self.y[j] + self.y[i] * self.w[j]) / sy
                    - ws * self.y[i] * self.y[j] / (sy * sy);
                self.s_mat[j * p + i] += v;
            }
        }
        if self.s_mat[..p * p].iter().any(|v| !v.is_finite()) {
            self.s_mat[..p * p].fill(0.0);
        }
    }
}

/// Result of the scaled trust-region subproblem.
#[derive(Clone, Copy, Debug)]
struct TrResult {
    lambda: f64,
    /// Predicted reduction of the Newton step, negative when the model is singular or indefinite.
    newton_reduction: f64,
    /// Scaled length of the Newton step (NL2SOL's DST0), negative when it does not exist.
    newton_norm: f64,
    is_newton: bool,
}

/// A free-set subproblem in one of two forms.
///
/// `qr`: the model is `0.5 ||u + T z||^2` with `T` upper triangular (`h` = T, `g` = u);
/// shifted systems are factored by Givens rotations of `[T; sqrt(lambda) I]`, so `J^T J` is never
/// formed. Otherwise the model is `g^T z + 0.5 z^T H z` (augmented model, possibly indefinite),
/// factored by Cholesky of `H + lambda I`.
struct Sub<'a> {
    n: usize,
    qr: bool,
    h: &'a [f64],
    g: &'a [f64],
    /// Factor of the shifted system: lower `L` (Cholesky) or upper `T_lambda` (QR).
    l: &'a mut [f64],
    /// Rotated right-hand side (QR form).
    ul: &'a mut [f64],
    /// Scratch.
    w: &'a mut [f64],
}

impl Sub<'_> {
    /// Newton step into `z` and its predicted reduction, or `None` when the model is singular
    /// (or indefinite).
    fn newton(&mut self, z: &mut [f64]) -> Option<f64> {
        let n = self.n;
        if self.qr {
            let dmax = (0..n).fold(0.0f64, |a, i| a.max(self.h[i * n + i].abs()));
            if !(dmax > 0.0) || (0..n).any(|i| !(self.h[i * n + i].abs() > QR_RANK_TOL * dmax)) {
                return None;
            }
            for i in 0..n {
                z[i] = -self.g[i];
            }
            upper_solve(self.h, n, z);
            Some(0.5 * dot(self.g, self.g))
        } else {
            if !cholesky_shifted(self.h, 0.0, n, RANK_TOL, self.l) {
                return None;
            }
            for i in 0..n {
                z[i] = -self.g[i];
            }
            forward_solve(self.l, n, z);
            backward_solve(self.l, n, z);
            Some(-0.5 * dot(self.g, z))
        }
    }

    /// Step at `lam > 0` into `z`; false when the shifted system is not positive definite.
    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        let n = self.n;
        if self.qr {
            shifted_triangular(self.h, self.g, n, lam, self.l, self.ul, self.w);
            if (0..n).any(|i| self.l[i * n + i] == 0.0) {
                return false;
            }
            for i in 0..n {
                z[i] = -self.ul[i];
            }
            upper_solve(self.l, n, z);
        } else {
            if !cholesky_shifted(self.h, lam, n, SHIFTED_TOL, self.l) {
                return false;
            }
            for i in 0..n {
                z[i] = -self.g[i];
            }
            forward_solve(self.l, n, z);
            backward_solve(self.l, n, z);
        }
        true
    }

    /// `q <- L^-1 q` where `L L^T` is the last shifted system.
    fn lower_solve(&self, q: &mut [f64]) {
        if self.qr {
            upper_transpose_solve(self.l, self.n, q);
        } else {
            forward_solve(self.l, self.n, q);
        }
    }

    /// Gradient norm, a bound on `||H||`, and the smallest diagonal entry of `H`.
    fn bracket_data(&self) -> (f64, f64, f64) {
        let n = self.n;
        if self.qr {
            // gradient T^T u; ||T^T T|| <= ||T||_F^2; H is positive semidefinite.
            let mut g2 = 0.0;
            for j in 0..n {
                let v = dot(&self.h[j * n..j * n + j + 1], &self.g[..j + 1]);
                g2 += v * v;
            }
            let f2 = dot(&self.h[..n * n], &self.h[..n * n]);
            (g2.sqrt(), f2, 0.0)
        } else {
            let mut hnorm = 0.0f64;
            let mut min_diag = f64::INFINITY;
            for j in 0..n {
                let col: f64 = self.h[j * n..(j + 1) * n].iter().map(|v| v.abs()).sum();
                hnorm = hnorm.max(col);
                min_diag = min_diag.min(self.h[j * n + j]);
            }
            (norm(self.g), hnorm, min_diag)
        }
    }
}

/// Minimises the free-set model subject to `||z|| <= radius` (More-Sorensen/Hebden iteration on
/// `lambda`); `z` receives the step, `best` is scratch.
fn trust_region(
    mut sub: Sub<'_>,
    radius: f64,
    lambda_guess: f64,
    z: &mut [f64],
    best: &mut [f64],
) -> TrResult {
    let n = sub.n;
    let (gnorm, hnorm, min_diag) = sub.bracket_data();
    if gnorm == 0.0 || !gnorm.is_finite() {
        z.fill(0.0);
        return TrResult {
            lambda: 0.0,
            newton_reduction: 0.0,
            newton_norm: 0.0,
            is_newton: true,
        };
    }
    let mut newton_reduction = -1.0;
    let mut newton_norm = -1.0;
    if let Some(red) = sub.newton(z) {
        let nz = norm(z);
        if nz.is_finite() && red.is_finite() {
            newton_reduction = red;
            newton_norm = nz;
            if nz <= radius * (1.0 + RADIUS_SLACK) {
                return TrResult {
                    lambda: 0.0,
                    newton_reduction,
                    newton_norm,
                    is_newton: true,
                };
            }
        }
    }
    let mut lo = (-min_diag).max(gnorm / radius - hnorm).max(0.0);
    let mut hi = gnorm / radius + hnorm;
    let mut lam = lambda_guess;
    let mut have_best = false;
    let mut best_lambda = hi;
    for _ in 0..60 {
        if !(lam > lo && lam < hi) {
            lam = if lo > 0.0 {
                (lo * hi).sqrt()
            } else {
                1e-3 * hi
            };
            lam = lam.max(lo + 1e-3 * (hi - lo));
        }
        if !sub.shifted(lam, z) {
            lo = lam;
            lam = 0.0;
            if hi - lo <= 1e-14 * hi {
                break;
            }
            continue;
        }
        let nz = norm(z);
        if !nz.is_finite() {
            lo = lam;
            lam = 0.0;
            continue;
        }
        if nz <= radius * (1.0 + RADIUS_SLACK) {
            best[..n].copy_from_slice(&z[..n]);
            best_lambda = lam;
            have_best = true;
        }
        if (nz - radius).abs() <= RADIUS_SLACK * radius {
            return TrResult {
                lambda: lam,
                newton_reduction,
                newton_norm,
                is_newton: false,
            };
        }
        if nz > radius {
            lo = lam;
        } else {
            hi = lam;
        }
        if hi - lo <= 1e-14 * hi {
            break;
        }
        // Newton step on 1/||z(lambda)|| - 1/radius (Hebden): needs ||L^-1 z||.
        sub.w[..n].copy_from_slice(&z[..n]);
        let mut q = std::mem::take(&mut sub.w);
        sub.lower_solve(q);
        let nq = norm(q);
        sub.w = std::mem::take(&mut q);
        lam += (nz / nq) * (nz / nq) * (nz - radius) / radius;
    }
    if have_best {
        z[..n].copy_from_slice(&best[..n]);
        TrResult {
            lambda: best_lambda,
            newton_reduction,
            newton_norm,
            is_newton: false,
        }
    } else {
        // No factorization succeeded inside the bracket: fall back to a scaled gradient step
        // (QR form: gradient T^T u).
        if sub.qr {
            for j in 0..n {
                z[j] = -dot(&sub.h[j * n..j * n + j + 1], &sub.g[..j + 1]);
            }
        } else {
            z[..n].copy_from_slice(&sub.g[..n]);
            for v in z[..n].iter_mut() {
                *v = -*v;
            }
        }
        let zn = norm(z);
        if zn > 0.0 {
            for v in z[..n].iter_mut() {
                *v *= radius / zn;
            }
        }
        TrResult {
            lambda: hi,
            newton_reduction,
            newton_norm,
            is_newton: false,
        }
    }
}

impl Solver {
    /// A solver with an empty workspace (it grows on the first solve).
    pub fn new() -> Self {
        Self::default()
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
        ws.prepare(m, p);
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

fn half_sum_squares(r: &[f64]) -> f64 {
    0.5 * dot(r, r)
}

/// The main loop (see the crate docs for the tests and their precedence).
fn iterate<P: Problem>(
    ws: &mut Workspace,
    problem: &mut P,
    opt: &Options,
) -> Result<Report, SolveError> {
    let (m, p) = (ws.m, ws.p);
    let mut nfev = 1usize;
    let mut njev = 0usize;
    let mut iterations = 0usize;
    if !problem.residuals(&ws.x[..p], &mut ws.r[..m]) {
        return Err(SolveError::StartNotEvaluable);
    }
    let mut f = half_sum_squares(&ws.r[..m]);
    if !f.is_finite() {
        return Err(SolveError::StartNotEvaluable);
    }
    let done = |outcome: Outcome, f: f64, iterations: usize, nfev: usize, njev: usize| Report {
        outcome,
        f,
        iterations,
        residual_evaluations: nfev,
        jacobian_evaluations: njev,
    };
    if p == 0 || f < opt.abs_function_tol {
        let outcome = if p == 0 {
            Outcome::RelativeFunctionConvergence
        } else {
            Outcome::AbsoluteFunctionConvergence
        };
        return Ok(done(outcome, f, 0, nfev, njev));
    }
    let mut augmented = false;
    let adaptive = opt.model == StepModel::Adaptive;
    ws.s_mat[..p * p].fill(0.0);
    let mut radius = opt.initial_radius;
    let mut need_jacobian = true;
    // Whether `jac` holds J at `x_prev` (the secant update needs the old Jacobian).
    let mut have_prev_jacobian = false;
    let mut switched_this_iteration = false;
    let mut f_prev = f;
    // RADFAC of the last accepted step: the radius becomes RADFAC * ||D_new s|| once the new
    // scaling is known.
    let mut radfac_pending = 0.0f64;
    // Radius decreases so far in this iteration (NL2SOL's RADINC, negative): after one, a good
    // step keeps the radius instead of increasing it.
    let mut radinc: i32 = 0;
    let nl2sol_radius = opt.radius_update == RadiusUpdate::Nl2sol;
    // A good step saved while a longer one is tried (NL2SOL's FLSTGD, PLSTGD, DSTSAV).
    let mut have_good = false;
    let mut good = Good {
        f,
        info: StepInfo {
            preduc: 0.0,
            nreduc: -1.0,
            newton_norm: -1.0,
            newton: false,
            dnorm: 0.0,
        },
        reldx: 0.0,
    };
    loop {
        if need_jacobian {
            if iterations >= opt.max_iterations {
                return Ok(done(Outcome::IterationLimit, f, iterations, nfev, njev));
            }
            if have_prev_jacobian && adaptive {
                // (J_old)^T r_new for y# before J is overwritten.
                jt_vec(&ws.jac, &ws.r, m, p, &mut ws.ysharp);
            }
            njev += 1;
            let ok = problem.jacobian(&ws.x[..p], &mut ws.jac[..m * p])
                && ws.jac[..m * p].iter().all(|v| v.is_finite());
            if !ok {
                if iterations == 0 {
                    return Err(SolveError::StartNotEvaluable);
                }
                // Treat like a failed evaluation of the step that led here: go back.
                ws.x[..p].copy_from_slice(&ws.x_prev[..p]);
                ws.r[..m].copy_from_slice(&ws.r_prev[..m]);
                // The factorization, g, J^T J and D still describe x_prev: they are only
                // recomputed after a successful Jacobian.
                f = f_prev;
                have_prev_jacobian = false;
                need_jacobian = false;
                radius *= 0.5;
                radfac_pending = 0.0;
                if iterations >= opt.max_iterations {
                    return Ok(done(Outcome::IterationLimit, f, iterations, nfev, njev));
                }
            } else {
                iterations += 1;
                ws.update_scaling(iterations == 1);
                radinc = 0;
                ws.factor_jacobian();
                if nl2sol_radius && radfac_pending > 0.0 {
                    if radfac_pending == 1.0 && ws.gradient_tests() {
                        radfac_pending = 2.0;
                    }
                    // N2FB (DG7ITB): t = RADFAC * ||D_new s||; the radius becomes t when
                    // RADFAC < 1 or t is larger, so a short step never shrinks it otherwise.
                    let mut s2 = 0.0;
                    for i in 0..p {
                        let v = ws.d[i] * (ws.x[i] - ws.x_prev[i]);
                        s2 += v * v;
                    }
                    let t = radfac_pending * s2.sqrt();
                    if radfac_pending < 1.0 || t > radius {
                        radius = t;
                    }
                    radfac_pending = 0.0;
                }
                if have_prev_jacobian && adaptive {
                    // y = g_new - g_old, y# = J_new^T r_new - J_old^T r_new.
                    for i in 0..p {
                        ws.y[i] = ws.g[i] - ws.g_prev[i];
                        ws.ysharp[i] = ws.g[i] - ws.ysharp[i];
                    }
                    ws.secant_update();
                }
                have_prev_jacobian = true;
                need_jacobian = false;
                switched_this_iteration = false;
                ws.build_model(augmented);
            }
        }

        let mut info = ws.compute_step(radius, augmented);
        let mut restored = false;
        let mut f_trial = f64::NAN;
        let mut reldx = 0.0;
        if have_good {
            // DG7ITB: the longer step is evaluated only if it predicts more than 1.2 times the
            // reduction the saved step achieved (and the budget allows); otherwise the saved
            // step is taken.
            let worthwhile =
                info.dnorm > 0.0 && info.preduc > 1.2 * (f - good.f) && nfev < opt.max_evaluations;
            if !worthwhile {
                have_good = false;
                ws.swap_good();
                (info, f_trial, reldx, restored) = (good.info, good.f, good.reldx, true);
            }
        }
        if !restored {
            if info.dnorm == 0.0 || !(info.preduc > 0.0) {
                // No descent step inside the box. With a zero step (projected gradient exactly
                // zero) or a Gauss-Newton reduction within tolerance, x is stationary on its
                // active face, which both reductions being zero signals to N2FB. Otherwise (the
                // model predicts no decrease though f is not known to be optimal) report
                // singular convergence, never a success code.
                let emax = opt.rel_function_tol * f.abs();
                let stationary = info.dnorm == 0.0 || (info.nreduc >= 0.0 && info.nreduc <= emax);
                let outcome = if stationary {
                    Outcome::RelativeFunctionConvergence
                } else {
                    Outcome::SingularConvergence
                };
                return Ok(done(outcome, f, iterations, nfev, njev));
            }
            if nfev >= opt.max_evaluations {
                return Ok(done(Outcome::EvaluationLimit, f, iterations, nfev, njev));
            }
            for i in 0..p {
                ws.x_trial[i] = (ws.x[i] + ws.step[i]).clamp(ws.lo[i], ws.hi[i]);
            }
            nfev += 1;
            let evaluated = problem.residuals(&ws.x_trial[..p], &mut ws.r_trial[..m]);
            f_trial = if evaluated {
                half_sum_squares(&ws.r_trial[..m])
            } else {
                f64::NAN
            };
            reldx = ws.reldx(&ws.x_trial, &ws.x);
            if have_good {
                // DA7SST: a longer step that does not beat the saved one (or cannot be
                // evaluated) is dropped and the saved step taken.
                have_good = false;
                if !(f_trial < good.f) {
                    ws.swap_good();
                    (info, f_trial, reldx, restored) = (good.info, good.f, good.reldx, true);
                }
            }
            if !f_trial.is_finite() {
                // Failed evaluation: reject the step and shrink the radius.
                radius = 0.5 * info.dnorm.min(radius);
                radinc -= 1;
                if reldx <= opt.false_conv_tol {
                    return Ok(done(Outcome::FalseConvergence, f, iterations, nfev, njev));
                }
                continue;
            }
        }
        let f0 = f;
        let ared = f0 - f_trial;
        let ratio = ared / info.preduc;
        let accepted = ared > 0.0 && ratio > ACCEPT_RATIO;

        // Model switch (adaptive): would the other model have predicted this reduction better?
        let mut switch_models = false;
        if adaptive && !restored {
            let (pred, sss) = ws.predicted(augmented);
            let pred_alt = if augmented {
                pred - 0.5 * sss
            } else {
                pred + 0.5 * sss
            };
            if (ared - pred_alt).abs() < (ared - info.preduc).abs() && sss != 0.0 {
                switch_models = true;
            }
        }

        let mut radfac = 0.0;
        let mut try_longer = false;
        if nl2sol_radius {
            // NL2SOL's DA7SST: the new radius is RADFAC times the scaled length of the step; after
            // an accepted step it is set at the next Jacobian, with the updated D (DG7ITB).
            let gts = dot(&ws.g[..p], &ws.step[..p]);
            radfac = if !accepted || ared <= 0.1 * info.preduc {
                // Fletcher's decrease factor: minimiser of the quadratic through f0, the slope
                // g^T s and f_trial along the step, within [0.1, 0.5].
                let emax = gts + ared;
                if emax < gts {
                    (0.5 * gts / emax).max(0.1)
                } else {
                    0.5
                }
            } else if !restored && radinc >= 0 && ared >= -0.75 * gts {
                // Good decrease, at least 3/4 of the linear prediction -g^T s (not of PREDUC:
                // with lambda near 0, -g^T s is twice PREDUC), and no decrease earlier in this
                // iteration: factor 2..4. Unless this was the Newton step, or the Newton step is
                // less than twice as long or predicts less than 1.2 times this reduction, the
                // longer step is tried at once from the same point (IRC = 5, no new Jacobian).
                let mut up = 4.0;
                if ared < (0.5 / up - 1.0) * gts {
                    up = (0.5 * gts / (gts + ared)).max(2.0);
                }
                let newton_close = info.newton_norm >= 0.0
                    && (info.newton_norm < 2.0 * info.dnorm || info.nreduc < 1.2 * ared);
                try_longer = !info.newton && !newton_close && !adaptive && radinc < MAX_RADINC;
                up
            } else {
                1.0
            };
            if !accepted {
                radius = radfac * info.dnorm;
                radinc -= 1;
            }
        } else if !accepted {
            let g_s = dot(&ws.g[..p], &ws.step[..p]);
            // Minimiser of the quadratic through f0, slope g^T s, and f_trial along the step.
            let denom = 2.0 * (f_trial - f0 - g_s);
            let t = if denom > 0.0 { -g_s / denom } else { 0.5 };
            radius = t.clamp(0.1, 0.5) * info.dnorm.min(radius);
        } else if ratio < 0.25 {
            radius = 0.5 * info.dnorm.min(radius).max(0.25 * radius);
        } else if ratio > 0.75 {
            radius = (4.0 * radius).min(radius.max(2.0 * info.dnorm));
        }

        // Convergence tests (NL2SOL's assessment), only when the model is trusted.
        let mut outcome: Option<Outcome> = None;
        if ared <= 2.0 * info.preduc {
            let emax = opt.rel_function_tol * f0.abs();
            let emaxs = opt.singular_tol * f0.abs();
            let rel = (info.nreduc > 0.0 && info.nreduc <= emax)
                || (info.nreduc == 0.0 && info.preduc == 0.0);
            // A restored step is not the last one computed (NL2SOL's GOODX = false).
            let xconv = info.newton && accepted && !restored && reldx <= opt.x_tol;
            outcome = match (xconv, rel) {
                (true, true) => Some(Outcome::BothConvergence),
                (true, false) => Some(Outcome::XConvergence),
                (false, true) => Some(Outcome::RelativeFunctionConvergence),
                (false, false) => None,
            };
            if outcome.is_none() && info.preduc <= emaxs {
                if info.dnorm > opt.singular_radius || info.newton {
                    outcome = Some(Outcome::SingularConvergence);
                } else {
                    // Re-solve at radius LMAXS from x0 without evaluating f.
                    std::mem::swap(&mut ws.step, &mut ws.step_alt);
                    let saved_lambda = ws.lambda;
                    let alt = ws.compute_step(opt.singular_radius, augmented);
                    ws.lambda = saved_lambda;
                    std::mem::swap(&mut ws.step, &mut ws.step_alt);
                    if alt.preduc <= emaxs {
                        outcome = Some(Outcome::SingularConvergence);
                    }
                }
            }
        }

        if try_longer && outcome.is_none() {
            // Keep this good step and try the longer one (same x, same Jacobian).
            ws.swap_good();
            good = Good {
                f: f_trial,
                info,
                reldx,
            };
            have_good = true;
            radinc += 1;
            radius = radfac * info.dnorm;
            continue;
        }

        if accepted {
            ws.x_prev[..p].copy_from_slice(&ws.x[..p]);
            ws.r_prev[..m].copy_from_slice(&ws.r[..m]);
            ws.g_prev[..p].copy_from_slice(&ws.g[..p]);
            f_prev = f;
            ws.x[..p].copy_from_slice(&ws.x_trial[..p]);
            std::mem::swap(&mut ws.r, &mut ws.r_trial);
            f = f_trial;
            need_jacobian = true;
            radfac_pending = radfac;
            if nl2sol_radius && radfac == 1.0 {
                // Model Hessian times the step, for the gradient tests at the new point.
                sym_mat_vec(&ws.h, &ws.step, p, &mut ws.w);
            }
            if switch_models {
                augmented = !augmented;
            }
        }
        if let Some(o) = outcome {
            return Ok(done(o, f, iterations, nfev, njev));
        }
        if accepted && f < opt.abs_function_tol {
            return Ok(done(
                Outcome::AbsoluteFunctionConvergence,
                f,
                iterations,
                nfev,
                njev,
            ));
        }
        if (!accepted || ratio < 0.1) && reldx <= opt.false_conv_tol {
            return Ok(done(Outcome::FalseConvergence, f, iterations, nfev, njev));
        }
        if !accepted && switch_models && !switched_this_iteration {
            // The other model explains the failure better: retry from x with it.
            augmented = !augmented;
            switched_this_iteration = true;
            ws.build_model(augmented);
        }
    }
}

/// A good step kept while a longer one is tried from the same point.
#[derive(Clone, Copy, Debug)]
struct Good {
    f: f64,
    info: StepInfo,
    reldx: f64,
}
