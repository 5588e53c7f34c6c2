//! The N2FB-style iteration: scaled trust-region Levenberg-Marquardt with an active set for the
//! bounds, NL2SOL's convergence tests and (optionally) its adaptive augmented model.
//!
//! The loop ([`iterate`]) reads like NL2SOL's driver: start a new iteration (Jacobian, scaling
//! `D`, factorization, the pending radius change), compute a trial step in the trust region
//! ([`Workspace::compute_step`]), evaluate it, assess it (DA7SST: accept or reject and how the
//! radius changes, [`TrustRadius::after_step`]), and test for convergence
//! ([`Descent::convergence_test`], [`Descent::stop_test`]). The names follow NL2SOL and PORT
//! (Dennis, Gay and Welsch 1981; Gay 1983): RADFAC, RADINC, PREDUC, NREDUC, RELDX, STPPAR.

use crate::linalg::{
    backward_solve, cholesky_shifted, dot, forward_solve, jt_vec, norm, shifted_scratch_len,
    shifted_triangular, survey_columns, sym_mat_vec, upper_solve, upper_transpose_solve,
};
use crate::qr::{TALL_QR_MIN_ROWS, householder_qr, tall_qr, tall_qr_scratch_len};
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
/// A second-order correction is tried only when it is at most this fraction of the step's
/// scaled length (GSL's `avmax` for geodesic acceleration, Transtrum and Sethna 2012).
const MAX_CORRECTION: f64 = 0.75;
/// A step is accepted when the actual reduction exceeds this fraction of the predicted one.
const ACCEPT_RATIO: f64 = 1e-4;
/// A column of the scaled Jacobian `J D^-1` whose norm is at most this fraction of the largest
/// is numerically dead (a BRDF lobe with `d^n ~ 1e-150`): moving its variable across the whole
/// trust region changes `J s` by less than the rounding of the live columns. It is zeroed before
/// the QR and its variable held, like a variable on a bound.
const DEAD_COLUMN: f64 = f64::EPSILON;
/// A first trust radius below this times `||D x||` is a round-off change of x.
const ROUND_OFF_STEP: f64 = 16.0 * f64::EPSILON;
/// Slack on the bound `||D_F^-1 g_F|| <= sqrt(p rfctol) ||r||` that relative function
/// convergence implies (see [`Workspace::gradient_permits_rel_conv`]).
const REL_CONV_GRADIENT_SLACK: f64 = 10.0;

/// Bounded trust-region Levenberg-Marquardt solver.
///
/// The solver owns its workspace; buffers only grow, so repeated solves of the same or a smaller
/// size allocate nothing.
#[derive(Clone, Debug, Default)]
pub struct Solver {
    ws: Workspace,
}

/// All buffers of a solve (grow-only). Each buffer has one meaning.
#[derive(Clone, Debug, Default)]
struct Workspace {
    m: usize,
    p: usize,
    /// Current iterate, trial point, and the point before the last accepted step.
    x: Vec<f64>,
    x_trial: Vec<f64>,
    x_prev: Vec<f64>,
    /// The box.
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// Residuals at `x`, `x_trial` and `x_prev`.
    r: Vec<f64>,
    r_trial: Vec<f64>,
    r_prev: Vec<f64>,
    /// Jacobian at `x` (column-major).
    jac: Vec<f64>,
    /// Copy of `J D^-1` reduced in place by Householder QR.
    qr: Vec<f64>,
    /// `Q^T r` work vector (length m).
    rq: Vec<f64>,
    /// `R` of `J D^-1 = Q R` (p x p upper, rows beyond m zero).
    rmat: Vec<f64>,
    /// First p entries of `Q^T r`.
    cvec: Vec<f64>,
    /// `D^-1` with 0 for dead columns, and the row block of [`tall_qr`] (tall Jacobians).
    col_scale: Vec<f64>,
    qr_scratch: Vec<f64>,
    /// Scaling `D`.
    d: Vec<f64>,
    /// `J^T J` (unscaled).
    jtj: Vec<f64>,
    /// Gradient `g = J^T r` at `x` and at `x_prev`.
    g: Vec<f64>,
    g_prev: Vec<f64>,
    /// Secant approximation of the second-order term (augmented model).
    s_mat: Vec<f64>,
    /// The model Hessian in use (`jtj` or `jtj + s_mat`).
    h: Vec<f64>,
    /// The trial step `s`.
    step: Vec<f64>,
    /// The step re-solved at radius LMAXS for the singular-convergence test.
    singular_step: Vec<f64>,
    /// Model gradient `g + H s` at a partial step (augmented model).
    g_model: Vec<f64>,
    /// `S s` for the predicted reductions.
    s_step: Vec<f64>,
    /// `H s` of the last accepted step (at the old point), for DG7ITB's gradient tests.
    h_step: Vec<f64>,
    /// `D s` and `R D s` for the predicted reductions.
    d_step: Vec<f64>,
    r_d_step: Vec<f64>,
    /// Variables whose scaled Jacobian column is numerically dead ([`DEAD_COLUMN`]), and the
    /// max-abs entry of each scaled column.
    dead: Vec<bool>,
    /// Hold numerically dead variables ([`Options::hold_dead_columns`]; set by each solve).
    hold_dead: bool,
    /// [`Options::stop_at_minimum_norm_step`] (set by each solve).
    stop_at_min_norm: bool,
    /// [`Options::scaling_decay`] (set by each solve).
    scaling_decay: f64,
    col_max: Vec<f64>,
    /// From one pass over a new Jacobian ([`Workspace::survey_jacobian`]): each column's sum
    /// of squares, its max-abs entry, and `J^T r`.
    col_sq: Vec<f64>,
    col_amax: Vec<f64>,
    jtr: Vec<f64>,
    /// Held variables and the indices of the free ones.
    fixed: Vec<bool>,
    free: Vec<usize>,
    /// Least-squares form of the free-set Gauss-Newton model `0.5 ||u + T z||^2`.
    ls_t: Vec<f64>,
    ls_u: Vec<f64>,
    /// `[R_F | c + R D s]` reduced to `[T | u]` by Householder QR.
    ls_block: Vec<f64>,
    ls_rhs: Vec<f64>,
    /// Factor of the shifted system `[T; sqrt(lambda) I] -> T_lambda`, its right-hand side, and
    /// the Givens scratch rows.
    ls_t_lambda: Vec<f64>,
    ls_u_lambda: Vec<f64>,
    ls_row: Vec<f64>,
    /// With fewer rows `k` than free variables (a subsample smaller than the model): the Gram
    /// matrix `T_k T_k^T` of T's nonzero rows, the Cholesky factor of `T_k T_k^T + lambda I`, and
    /// the dual solution `w` and `(T_k T_k^T + lambda I)^-1 w` ([`WideLeastSquaresModel`]).
    wide_gram: Vec<f64>,
    wide_chol: Vec<f64>,
    wide_w: Vec<f64>,
    wide_v: Vec<f64>,
    /// Normal form of the free-set augmented model `g^T z + 0.5 z^T H z` (scaled) and the
    /// Cholesky factor of `H + lambda I`.
    qd_h: Vec<f64>,
    qd_g: Vec<f64>,
    qd_chol: Vec<f64>,
    /// Scaled free-set step `z`, the best feasible one seen, and scratch for `L^-1 z` (Hebden's
    /// update).
    sub_z: Vec<f64>,
    sub_best: Vec<f64>,
    sub_q: Vec<f64>,
    /// Secant update vectors: gradient change `y`, `y# = (J_new - J_old)^T r_new`, and scratch.
    y: Vec<f64>,
    ysharp: Vec<f64>,
    secant_w: Vec<f64>,
    /// A good trial point, its residuals and step, saved while a longer step is tried.
    x_good: Vec<f64>,
    r_good: Vec<f64>,
    step_good: Vec<f64>,
    /// Second-order correction of a rejected step ([`Options::second_order_correction`]):
    /// the model's error `r(x + s) - r(x) - J s` (length m), the right-hand side and solution
    /// of the shifted system, its matrix and Cholesky factor, and the uncorrected step.
    soc_e: Vec<f64>,
    soc_b: Vec<f64>,
    soc_a: Vec<f64>,
    soc_l: Vec<f64>,
    soc_step: Vec<f64>,
    /// Last Levenberg-Marquardt parameter, a warm start for the next subproblem.
    lambda: f64,
    /// Secant updates of `S` so far in this solve.
    secant_updates: usize,
}

/// What a step computation produced.
#[derive(Clone, Copy, Debug)]
struct StepInfo {
    /// Predicted reduction of the model for the step (PREDUC).
    preduc: f64,
    /// Predicted reduction of the full Gauss-Newton (Newton) step on the first free set
    /// (NREDUC), or negative when that step does not exist (singular model).
    nreduc: f64,
    /// Predicted reduction of the Newton step of the model in use on the first free set (N2FB's
    /// NREDUC: the augmented model's when it is in use, else equal to `nreduc`), negative when
    /// that step does not exist.
    model_nreduc: f64,
    /// Scaled length of the first pass's Newton step (NL2SOL's DST0), negative when it does not
    /// exist.
    newton_norm: f64,
    /// The step is the Newton step (STPPAR = 0; see the crate docs for steps cut at a bound).
    newton: bool,
    /// `||D s||`.
    dnorm: f64,
    /// A variable not held on a bound has a numerically dead column ([`DEAD_COLUMN`]): the
    /// Gauss-Newton model is singular, so (as in N2FB, which gives code 7 for a zero column) there
    /// is no Newton step and NREDUC does not exist, although the step is computed on the live
    /// variables.
    dead_free: bool,
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

fn grow(v: &mut Vec<f64>, n: usize) {
    v.resize(n, 0.0);
}

/// True when the upper-triangular `t` (`n x n`) has no diagonal entry below
/// `QR_RANK_TOL` times the largest (a Gauss-Newton step exists).
fn triangular_full_rank(t: &[f64], n: usize) -> bool {
    let dmax = (0..n).fold(0.0f64, |a, i| a.max(t[i * n + i].abs()));
    dmax > 0.0 && (0..n).all(|i| t[i * n + i].abs() > QR_RANK_TOL * dmax)
}

/// From a Householder QR done in place (column-major, `ld` rows, `n` columns) and its rotated
/// right-hand side `Q^T rhs` (length `ld`): the `n x n` upper triangle `r` and the first `n`
/// entries `c`, zero in the rows from `ld` on (a QR with fewer rows than columns).
fn triangle_of_qr(qr: &[f64], ld: usize, qtr: &[f64], n: usize, r: &mut [f64], c: &mut [f64]) {
    for j in 0..n {
        for i in 0..n {
            r[j * n + i] = if i <= j && i < ld {
                qr[j * ld + i]
            } else {
                0.0
            };
        }
        c[j] = if j < ld { qtr[j] } else { 0.0 };
    }
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
            &mut self.singular_step,
            &mut self.x_good,
            &mut self.step_good,
            &mut self.g_model,
            &mut self.s_step,
            &mut self.h_step,
            &mut self.d_step,
            &mut self.r_d_step,
            &mut self.ls_u,
            &mut self.ls_rhs,
            &mut self.ls_u_lambda,
            &mut self.qd_g,
            &mut self.sub_z,
            &mut self.sub_best,
            &mut self.sub_q,
            &mut self.wide_w,
            &mut self.wide_v,
            &mut self.cvec,
            &mut self.col_scale,
            &mut self.col_max,
            &mut self.col_sq,
            &mut self.col_amax,
            &mut self.jtr,
            &mut self.y,
            &mut self.ysharp,
            &mut self.secant_w,
            &mut self.soc_b,
            &mut self.soc_step,
        ] {
            grow(v, p);
        }
        for v in [
            &mut self.r,
            &mut self.r_trial,
            &mut self.r_prev,
            &mut self.r_good,
            &mut self.rq,
            &mut self.soc_e,
        ] {
            grow(v, m);
        }
        grow(&mut self.jac, m * p);
        grow(&mut self.qr, m * p);
        grow(&mut self.qr_scratch, tall_qr_scratch_len(p));
        grow(&mut self.ls_block, p * (p + 1));
        grow(&mut self.ls_row, shifted_scratch_len(p));
        for v in [
            &mut self.jtj,
            &mut self.rmat,
            &mut self.s_mat,
            &mut self.h,
            &mut self.ls_t,
            &mut self.ls_t_lambda,
            &mut self.qd_h,
            &mut self.qd_chol,
            &mut self.wide_gram,
            &mut self.wide_chol,
            &mut self.soc_a,
            &mut self.soc_l,
        ] {
            grow(v, p * p);
        }
        self.fixed.resize(p, false);
        self.dead.resize(p, false);
        self.free.resize(p, 0);
        self.lambda = 0.0;
        self.secant_updates = 0;
    }

    /// One pass over a new Jacobian, column by column: the sum of squares (for the scaling),
    /// the max-abs entry (for the dead-column test) and `J^T r` (for the secant update), which
    /// were four passes over the `m x p` matrix, counting the finiteness check. The sums are
    /// accumulated exactly as [`dot`] does, so the results are bit for bit those of the
    /// separate passes. Returns whether every entry is finite: a non-finite entry makes its
    /// column's sum of squares non-finite; a finite column can overflow that sum only with
    /// entries above 1e154, and is then checked entry by entry.
    fn survey_jacobian(&mut self) -> bool {
        let (m, p) = (self.m, self.p);
        let (jac, r) = (&self.jac[..m * p], &self.r[..m]);
        survey_columns(
            jac,
            r,
            m,
            p,
            &mut self.col_sq,
            &mut self.jtr,
            &mut self.col_amax,
        );
        (0..p).all(|j| {
            self.col_sq[j].is_finite() || jac[j * m..(j + 1) * m].iter().all(|v| v.is_finite())
        })
    }

    /// Updates the scaling: `D_i = max(DFAC D_i, ||J_i||_2)` with DFAC =
    /// [`Options::scaling_decay`] (N2FB's 0.6 by default; 1 is MINPACK's non-decreasing rule),
    /// the column 2-norm of the original NL2SOL rather than PORT's column max; a column whose
    /// norm is below 1e-6 uses 1 instead, so a dead parameter keeps a sane scale. Measured on
    /// NIST (GN model, default budgets, an earlier version of the solver): DFAC 0.6 50/54,
    /// column max 44/54, MINPACK's rule 49/54; with the solver of 2026-12-03 the default
    /// scores 52/54 with either factor. With `secant` (once `S` has had the delay's updates),
    /// `||J_i||_2` becomes `sqrt(||J_i||^2 + S_ii)` where `S_ii > 0` (NL2SOL's DUPDAT: the
    /// diagonal of the augmented Hessian `J^T J + S`).
    fn update_scaling(&mut self, first: bool, secant: bool) {
        let p = self.p;
        for j in 0..p {
            // The column's 2-norm, from the survey of this Jacobian (the same sum as `norm`).
            let mut cn = self.col_sq[j].sqrt();
            let sii = self.s_mat[j * p + j];
            if secant && sii > 0.0 {
                cn = (cn * cn + sii).sqrt();
            }
            let cand = if cn < 1e-6 { 1.0 } else { cn };
            self.d[j] = if first {
                cand
            } else {
                cand.max(self.scaling_decay * self.d[j])
            };
        }
    }

    /// QR of the scaled Jacobian `J D^-1 = Q R`, `c = Q^T r`, and from them `J^T J` and
    /// `g = J^T r` (unscaled) for the augmented model, the secant update and the active set.
    ///
    /// A numerically dead scaled column ([`DEAD_COLUMN`]) is zeroed and its variable marked
    /// `dead` (held by [`Workspace::hold_active_bounds`]): left in, such a column made `R` so
    /// ill-conditioned that the subproblem moved the dead variables by garbage amounts, and its
    /// squares underflowed in the QR.
    fn factor_jacobian(&mut self) {
        let p = self.p;
        if self.m >= TALL_QR_MIN_ROWS && self.m >= p {
            self.factor_tall();
        } else {
            self.factor_in_place();
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

    /// Tall Jacobians: the blocked [`tall_qr`] reads `J` once, scaling by `D^-1` (0 for a dead
    /// column) on the fly, so neither the `m x p` scaled copy nor the copy of `r` is written.
    fn factor_tall(&mut self) {
        let (m, p) = (self.m, self.p);
        let mut max_scaled = 0.0f64;
        for j in 0..p {
            // max |J_ij| / D_j is exactly max |J_ij / D_j| (rounding is monotone), as below;
            // max |J_ij| comes from the survey of this Jacobian.
            self.col_max[j] = self.col_amax[j] * (1.0 / self.d[j]);
            max_scaled = max_scaled.max(self.col_max[j]);
        }
        for j in 0..p {
            self.dead[j] = self.hold_dead && !(self.col_max[j] > DEAD_COLUMN * max_scaled);
            self.col_scale[j] = if self.dead[j] { 0.0 } else { 1.0 / self.d[j] };
        }
        tall_qr(
            &self.jac[..m * p],
            m,
            p,
            &self.col_scale[..p],
            &self.r[..m],
            &mut self.rmat[..p * p],
            &mut self.cvec[..p],
            &mut self.qr_scratch,
        );
    }

    /// Small Jacobians: scaled copy, in-place [`householder_qr`], `R` and `c` copied out.
    fn factor_in_place(&mut self) {
        let (m, p) = (self.m, self.p);
        let mut max_scaled = 0.0f64;
        for j in 0..p {
            let inv = 1.0 / self.d[j];
            for (q, &v) in self.qr[j * m..(j + 1) * m]
                .iter_mut()
                .zip(&self.jac[j * m..(j + 1) * m])
            {
                *q = v * inv;
            }
            // Dead columns are tiny: their 2-norm via max-abs avoids underflow in the squares.
            let amax = self.qr[j * m..(j + 1) * m]
                .iter()
                .fold(0.0f64, |a, v| a.max(v.abs()));
            self.col_max[j] = amax;
            max_scaled = max_scaled.max(amax);
        }
        for j in 0..p {
            // max-abs is within sqrt(m) of the 2-norm; comparing max-abs values is enough here.
            self.dead[j] = self.hold_dead && !(self.col_max[j] > DEAD_COLUMN * max_scaled);
            if self.dead[j] {
                self.qr[j * m..(j + 1) * m].fill(0.0);
            }
        }
        self.rq[..m].copy_from_slice(&self.r[..m]);
        householder_qr(&mut self.qr[..m * p], m, p, &mut self.rq[..m]);
        triangle_of_qr(
            &self.qr[..m * p],
            m,
            &self.rq[..m],
            p,
            &mut self.rmat[..p * p],
            &mut self.cvec[..p],
        );
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
            self.d_step[i] = self.d[i] * self.step[i];
        }
        for i in 0..p {
            let mut v = 0.0;
            for j in i..p {
                v += self.rmat[j * p + i] * self.d_step[j];
            }
            self.r_d_step[i] = v;
        }
        let pred_gn = -(dot(&self.cvec[..p], &self.r_d_step[..p])
            + 0.5 * dot(&self.r_d_step[..p], &self.r_d_step[..p]));
        sym_mat_vec(&self.s_mat, &self.step, p, &mut self.s_step);
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
    fn hold_active_bounds(&mut self) -> bool {
        let mut dead_free = false;
        for i in 0..self.p {
            let at_lo = self.x[i] <= self.lo[i];
            let at_hi = self.x[i] >= self.hi[i];
            let bound =
                (at_lo && self.g[i] >= 0.0) || (at_hi && self.g[i] <= 0.0) || (at_lo && at_hi);
            dead_free |= self.dead[i] && !bound;
            self.fixed[i] = bound || self.dead[i];
            self.step[i] = 0.0;
        }
        dead_free
    }

    /// Lists the free variables in `free`; returns their number.
    fn collect_free(&mut self) -> usize {
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
    fn build_least_squares_model(&mut self, n: usize, first: bool) {
        let p = self.p;
        if n == p && first {
            // Nothing held and no partial step yet: the free-set model is R itself.
            self.ls_t[..p * p].copy_from_slice(&self.rmat[..p * p]);
            self.ls_u[..p].copy_from_slice(&self.cvec[..p]);
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
            self.ls_block[a * rows..(a + 1) * rows]
                .copy_from_slice(&self.rmat[ia * p..ia * p + rows]);
        }
        for i in 0..rows {
            let mut v = self.cvec[i];
            for j in i..p {
                v += self.rmat[j * p + i] * self.d_step[j];
            }
            self.ls_rhs[i] = v;
        }
        householder_qr(
            &mut self.ls_block[..rows * n],
            rows,
            n,
            &mut self.ls_rhs[..rows],
        );
        triangle_of_qr(
            &self.ls_block[..rows * n],
            rows,
            &self.ls_rhs[..rows],
            n,
            &mut self.ls_t[..n * n],
            &mut self.ls_u[..n],
        );
    }

    /// The free-set model at the partial step `s` in normal form (augmented model): scaled
    /// model gradient `D^-1 (g + H s)` and scaled Hessian `D^-1 H D^-1` of the free variables.
    fn build_quadratic_model(&mut self, n: usize) {
        let p = self.p;
        sym_mat_vec(&self.h, &self.step, p, &mut self.g_model);
        for i in 0..p {
            self.g_model[i] += self.g[i];
        }
        for a in 0..n {
            let ia = self.free[a];
            self.qd_g[a] = self.g_model[ia] / self.d[ia];
            for b in 0..n {
                let ib = self.free[b];
                self.qd_h[a * n + b] = self.h[ia * p + ib] / (self.d[ia] * self.d[ib]);
            }
        }
    }

    /// Largest fraction `alpha <= 1` of the free-set sub-step `z` (scaled) that keeps
    /// `x + s + alpha D^-1 z` in the box, and the variable (and whether its upper bound) that
    /// limits it.
    fn feasible_fraction(&self, n: usize) -> (f64, Option<(usize, bool)>) {
        let mut alpha = 1.0f64;
        let mut hit = None;
        for a in 0..n {
            let i = self.free[a];
            let ds = self.sub_z[a] / self.d[i];
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
    fn solve_subproblem(&mut self, n: usize, radius: f64, augmented: bool) -> TrResult {
        if augmented {
            self.build_quadratic_model(n);
        }
        let lambda = self.lambda;
        let stop_at_min_norm = self.stop_at_min_norm;
        let (z, best, q) = (&mut self.sub_z[..n], &mut self.sub_best, &mut self.sub_q);
        if augmented {
            let mut sub = QuadraticModel {
                n,
                h: &self.qd_h[..n * n],
                g: &self.qd_g[..n],
                chol: &mut self.qd_chol[..n * n],
            };
            trust_region(&mut sub, radius, lambda, stop_at_min_norm, z, best, q)
        } else if self.m < n {
            let k = self.m;
            let mut sub = WideLeastSquaresModel {
                n,
                k,
                t: &self.ls_t[..n * n],
                u: &self.ls_u[..n],
                gram: &mut self.wide_gram[..k * k],
                chol: &mut self.wide_chol[..k * k],
                w: &mut self.wide_w[..k],
                v: &mut self.wide_v[..k],
            }
            .with_gram();
            trust_region(&mut sub, radius, lambda, stop_at_min_norm, z, best, q)
        } else {
            let mut sub = LeastSquaresModel {
                n,
                t: &self.ls_t[..n * n],
                u: &self.ls_u[..n],
                t_lambda: &mut self.ls_t_lambda[..n * n],
                u_lambda: &mut self.ls_u_lambda[..n],
                row: &mut self.ls_row[..shifted_scratch_len(n)],
            };
            trust_region(&mut sub, radius, lambda, stop_at_min_norm, z, best, q)
        }
    }

    /// Computes the bounded step from `x` within scaled radius `radius` into `self.step`.
    ///
    /// Active set: a variable on a bound whose gradient points out of the box is held. The
    /// trust-region subproblem is solved on the free variables; when the step leaves the box it is
    /// cut where it first reaches a bound, that variable is held there, and the rest of the step
    /// is re-solved from the cut point (model gradient `g + H s`, remaining radius).
    fn compute_step(&mut self, radius: f64, augmented: bool) -> StepInfo {
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
                if augmented && triangular_full_rank(&self.ls_t[..n * n], n) {
                    nreduc_gn = 0.5 * dot(&self.ls_u[..n], &self.ls_u[..n]);
                }
            }
            let tr = self.solve_subproblem(n, remaining, augmented);
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
                self.step[i] += alpha * self.sub_z[a] / self.d[i];
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
        if dead_free {
            info.dead_free = true;
            info.nreduc = -1.0;
            info.model_nreduc = -1.0;
            info.newton_norm = -1.0;
            info.newton = false;
        }
        info
    }

    /// N2FB's gradient tests (DG7ITB) after a step accepted with the radius unchanged, with
    /// `h_step` = model Hessian times the step (at the old point), `g_prev` the old gradient and
    /// `g` the new one: the radius may still double when the model predicted the new gradient
    /// well, `||D^-1 (H s + g_old - g_new)|| <= 0.5 ||D^-1 g_new||` (free variables), or when the
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

    /// `||D (x - x_prev)||`: the scaled length of the last accepted step with the current `D`.
    fn scaled_norm_last_step(&self) -> f64 {
        let mut s2 = 0.0;
        for i in 0..self.p {
            let v = self.d[i] * (self.x[i] - self.x_prev[i]);
            s2 += v * v;
        }
        s2.sqrt()
    }

    /// `||D x||`.
    fn scaled_norm_x(&self) -> f64 {
        let mut s = 0.0;
        for i in 0..self.p {
            let v = self.d[i] * self.x[i];
            s += v * v;
        }
        s.sqrt()
    }

    /// Whether the scaled projected gradient at `x` is small enough for relative function
    /// convergence. In exact arithmetic `NREDUC = 0.5 ||c_F||^2 <= rfctol f` implies
    /// `||D_F^-1 g_F|| = ||R_F^T c_F|| <= sqrt(p) ||c_F|| <= sqrt(p rfctol) ||r||` (scaled columns
    /// have norm at most 1), so this gate (with [`REL_CONV_GRADIENT_SLACK`]) never blocks a
    /// correctly computed code 4; it blocks one computed from a broken factorization. `g` is
    /// recomputed as `J^T r` from the Jacobian itself, independently of the QR. The free set
    /// is every variable not held on a bound by the sign of its gradient (the KKT conditions);
    /// dead variables count with their true, negligible gradient.
    fn gradient_permits_rel_conv(&self, rel_tol: f64) -> bool {
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

    /// Second-order correction of the rejected trial step `v` (in `step`, its residuals in
    /// `r_trial`): `c` minimises `||J c + e||^2 + lambda ||D c||^2` with `e = r(x + v) - r(x)
    /// - J v`, the part of the residuals' change the linear model missed, and `lambda` the
    /// step's Levenberg parameter; `step` becomes `v + c` (cut to the box), `x_trial` its point.
    /// Only with every variable free, and only when `||D c|| <= max_ratio ||D v||`; returns
    /// whether the corrected step was set (`soc_step` keeps `v`).
    fn corrected_step(&mut self, max_ratio: f64) -> bool {
        let (m, p) = (self.m, self.p);
        if self.fixed[..p].iter().any(|&f| f) {
            return false;
        }
        for i in 0..m {
            self.soc_e[i] = self.r_trial[i] - self.r[i];
        }
        for j in 0..p {
            let sj = self.step[j];
            for (e, &v) in self.soc_e[..m]
                .iter_mut()
                .zip(&self.jac[j * m..(j + 1) * m])
            {
                *e -= v * sj;
            }
        }
        jt_vec(&self.jac, &self.soc_e, m, p, &mut self.soc_b);
        for j in 0..p {
            self.soc_b[j] = -self.soc_b[j] / self.d[j];
            for k in 0..=j {
                let v = dot(
                    &self.rmat[j * p..(j + 1) * p],
                    &self.rmat[k * p..(k + 1) * p],
                );
                self.soc_a[j * p + k] = v;
                self.soc_a[k * p + j] = v;
            }
        }
        if !cholesky_shifted(
            &self.soc_a[..p * p],
            self.lambda,
            p,
            SHIFTED_TOL,
            &mut self.soc_l[..p * p],
        ) {
            return false;
        }
        forward_solve(&self.soc_l[..p * p], p, &mut self.soc_b[..p]);
        backward_solve(&self.soc_l[..p * p], p, &mut self.soc_b[..p]);
        let vnorm = self.scaled_norm_step();
        let cnorm = norm(&self.soc_b[..p]);
        if !(cnorm <= max_ratio * vnorm) {
            return false;
        }
        self.soc_step[..p].copy_from_slice(&self.step[..p]);
        for i in 0..p {
            let t = (self.x[i] + self.step[i] + self.soc_b[i] / self.d[i])
                .clamp(self.lo[i], self.hi[i]);
            self.step[i] = t - self.x[i];
            self.x_trial[i] = t;
        }
        true
    }

    /// Puts the uncorrected step back after a corrected one failed.
    fn restore_uncorrected_step(&mut self) {
        let p = self.p;
        self.step[..p].copy_from_slice(&self.soc_step[..p]);
    }

    /// The singular-convergence test step (N2FB): PREDUC of the step re-solved at `radius`
    /// (LMAXS) from the same point without evaluating f; the trial step and lambda are kept.
    fn singular_test_reduction(&mut self, radius: f64, augmented: bool) -> f64 {
        std::mem::swap(&mut self.step, &mut self.singular_step);
        let saved_lambda = self.lambda;
        let alt = self.compute_step(radius, augmented);
        self.lambda = saved_lambda;
        std::mem::swap(&mut self.step, &mut self.singular_step);
        alt.preduc
    }

    /// Accepts the trial point: the current point becomes the previous one.
    fn accept_trial(&mut self) {
        let p = self.p;
        self.x_prev[..p].copy_from_slice(&self.x[..p]);
        self.g_prev[..p].copy_from_slice(&self.g[..p]);
        self.x[..p].copy_from_slice(&self.x_trial[..p]);
        // The residual buffers rotate (r -> r_prev, r_trial -> r; the old r_prev becomes the
        // next trial's scratch) instead of copying m values per accepted step.
        std::mem::swap(&mut self.r_prev, &mut self.r);
        std::mem::swap(&mut self.r, &mut self.r_trial);
    }

    /// Returns to the previous point (after a failed Jacobian there).
    fn return_to_previous(&mut self) {
        let (m, p) = (self.m, self.p);
        self.x[..p].copy_from_slice(&self.x_prev[..p]);
        self.r[..m].copy_from_slice(&self.r_prev[..m]);
    }

    /// The secant update after an accepted step from `g` (new gradient), `g_prev` and
    /// `ysharp` holding `J_old^T r_new`: `y = g_new - g_old`, `y# = J_new^T r_new - J_old^T
    /// r_new`.
    fn secant_update_from_gradients(&mut self) {
        for i in 0..self.p {
            self.y[i] = self.g[i] - self.g_prev[i];
            self.ysharp[i] = self.g[i] - self.ysharp[i];
        }
        self.secant_update();
    }

    /// NL2SOL's secant update of `S` after an accepted step (`step` = s, `y` = gradient change,
    /// `ysharp` = `(J_new - J_old)^T r_new`), with Dennis-Gay-Welsch sizing.
    fn secant_update(&mut self) {
        self.secant_updates += 1;
        let p = self.p;
        sym_mat_vec(&self.s_mat, &self.step, p, &mut self.secant_w);
        let sss = dot(&self.step[..p], &self.secant_w[..p]);
        let sy_sharp = dot(&self.step[..p], &self.ysharp[..p]);
        if sss != 0.0 {
            let tau = (sy_sharp / sss).abs().min(1.0);
            for v in self.s_mat[..p * p].iter_mut() {
                *v *= tau;
            }
            for v in self.secant_w[..p].iter_mut() {
                *v *= tau;
            }
        }
        let sy = dot(&self.step[..p], &self.y[..p]);
        // Skip the update when the curvature information is useless (s^T y ~ 0).
        if !(sy.abs() > 1e-30 * norm(&self.step[..p]) * norm(&self.y[..p])) || sy == 0.0 {
            return;
        }
        for i in 0..p {
            self.secant_w[i] = self.ysharp[i] - self.secant_w[i];
        }
        let ws = dot(&self.secant_w[..p], &self.step[..p]);
        for j in 0..p {
            for i in 0..p {
                let v = (self.secant_w[i] * self.y[j] + self.y[i] * self.secant_w[j]) / sy
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

/// A free-set trust-region subproblem in the scaled variables `z = D_F s_F`: what the
/// More-Sorensen/Hebden iteration ([`trust_region`]) needs from a model.
trait Subproblem {
    /// Number of free variables.
    fn n(&self) -> usize;
    /// Newton step into `z` and its predicted reduction, or `None` when the model is singular
    /// (or indefinite).
    fn newton(&mut self, z: &mut [f64]) -> Option<f64>;
    /// Step at `lam > 0` into `z`; false when the shifted system is not positive definite.
    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool;
    /// `||L^-1 z||` where `L L^T = H + lam I` is the last shifted system and `z` its step;
    /// `q` is scratch of length n.
    fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64;
    /// Gradient norm, a bound on `||H||`, and the smallest diagonal entry of `H`.
    fn bracket_data(&self) -> (f64, f64, f64);
    /// The steepest-descent direction `-gradient` into `z`.
    fn steepest_descent(&self, z: &mut [f64]);
}

/// The Gauss-Newton model in least-squares form `0.5 ||u + T z||^2`, `T` upper triangular;
/// shifted systems are factored by Givens rotations of `[T; sqrt(lambda) I]` (MINPACK's
/// qrsolv), so `J^T J` is never formed.
struct LeastSquaresModel<'a> {
    n: usize,
    t: &'a [f64],
    u: &'a [f64],
    /// `T_lambda` with `T_lambda^T T_lambda = T^T T + lambda I`.
    t_lambda: &'a mut [f64],
    /// The rotated right-hand side.
    u_lambda: &'a mut [f64],
    /// Givens scratch rows ([`shifted_scratch_len`]).
    row: &'a mut [f64],
}

impl Subproblem for LeastSquaresModel<'_> {
    fn n(&self) -> usize {
        self.n
    }

    fn newton(&mut self, z: &mut [f64]) -> Option<f64> {
        let n = self.n;
        if !triangular_full_rank(self.t, n) {
            return None;
        }
        for i in 0..n {
            z[i] = -self.u[i];
        }
        upper_solve(self.t, n, z);
        Some(0.5 * dot(self.u, self.u))
    }

    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        let n = self.n;
        shifted_triangular(
            self.t,
            self.u,
            n,
            lam,
            self.t_lambda,
            self.u_lambda,
            self.row,
        );
        if (0..n).any(|i| self.t_lambda[i * n + i] == 0.0) {
            return false;
        }
        for i in 0..n {
            z[i] = -self.u_lambda[i];
        }
        upper_solve(self.t_lambda, n, z);
        true
    }

    fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64 {
        let n = self.n;
        q[..n].copy_from_slice(&z[..n]);
        upper_transpose_solve(self.t_lambda, n, q);
        norm(&q[..n])
    }

    fn bracket_data(&self) -> (f64, f64, f64) {
        least_squares_bracket_data(self.t, self.u, self.n)
    }

    fn steepest_descent(&self, z: &mut [f64]) {
        least_squares_steepest_descent(self.t, self.u, self.n, z);
    }
}

/// Gradient norm `||T^T u||`, the bound `||T^T T|| <= ||T||_F^2` and 0, the smallest possible
/// diagonal entry of the positive semidefinite `T^T T`.
fn least_squares_bracket_data(t: &[f64], u: &[f64], n: usize) -> (f64, f64, f64) {
    let mut g2 = 0.0;
    for j in 0..n {
        let v = dot(&t[j * n..j * n + j + 1], &u[..j + 1]);
        g2 += v * v;
    }
    let f2 = dot(&t[..n * n], &t[..n * n]);
    (g2.sqrt(), f2, 0.0)
}

/// `z = -T^T u`, the negative gradient of `0.5 ||u + T z||^2` at 0.
fn least_squares_steepest_descent(t: &[f64], u: &[f64], n: usize, z: &mut [f64]) {
    for j in 0..n {
        z[j] = -dot(&t[j * n..j * n + j + 1], &u[..j + 1]);
    }
}

/// The Gauss-Newton model `0.5 ||u + T z||^2` when `T` has only `k < n` nonzero rows (fewer
/// residuals than free variables, as in AED's 25-row descents of many-lobe models), solved in
/// its dual form: `(T^T T + lambda I) z = -T^T u` has the solution `z = -T_k^T w` with
/// `(T_k T_k^T + lambda I) w = u_k`, a `k x k` system. The primal Givens factorization costs
/// `O(n^3)` per lambda (0.2 s per step at 16 lobes, seconds at 50, all of it between two calls
/// of the problem, so no CPU cutoff could interrupt it); this costs `O(k^3 + k n)` after the
/// Gram matrix (`O(k^2 n)`, once per model). The model is singular, so there is no Newton step.
struct WideLeastSquaresModel<'a> {
    n: usize,
    k: usize,
    t: &'a [f64],
    u: &'a [f64],
    /// `G = T_k T_k^T` (symmetric, `k x k`, column-major).
    gram: &'a mut [f64],
    /// Lower Cholesky factor of `G + lambda I`.
    chol: &'a mut [f64],
    /// `w = (G + lambda I)^-1 u_k` of the last shifted system.
    w: &'a mut [f64],
    /// Scratch: `(G + lambda I)^-1 w`.
    v: &'a mut [f64],
}

impl WideLeastSquaresModel<'_> {
    /// Forms the Gram matrix; `t` is `n x n` column-major with rows `>= k` zero.
    fn with_gram(self) -> Self {
        let (n, k) = (self.n, self.k);
        debug_assert!(k < n);
        self.gram.fill(0.0);
        // T is upper triangular: T[a, j] = t[j n + a], nonzero only for a <= j and a < k.
        for j in 0..n {
            let col = &self.t[j * n..j * n + (j + 1).min(k)];
            for (b, &tb) in col.iter().enumerate() {
                for (a, &ta) in col[..=b].iter().enumerate() {
                    self.gram[b * k + a] += ta * tb;
                }
            }
        }
        for b in 0..k {
            for a in 0..b {
                self.gram[a * k + b] = self.gram[b * k + a];
            }
        }
        self
    }
}

impl Subproblem for WideLeastSquaresModel<'_> {
    fn n(&self) -> usize {
        self.n
    }

    fn newton(&mut self, _z: &mut [f64]) -> Option<f64> {
        None
    }

    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        let (n, k) = (self.n, self.k);
        if !cholesky_shifted(self.gram, lam, k, SHIFTED_TOL, self.chol) {
            return false;
        }
        self.w.copy_from_slice(&self.u[..k]);
        forward_solve(self.chol, k, self.w);
        backward_solve(self.chol, k, self.w);
        // z = -T_k^T w: z_j = -sum_{a <= min(j, k-1)} T[a, j] w_a.
        for j in 0..n {
            let rows = (j + 1).min(k);
            z[j] = -dot(&self.t[j * n..j * n + rows], &self.w[..rows]);
        }
        true
    }

    /// `z^T (T^T T + lambda I)^-1 z = w^T G (G + lambda I)^-1 w` for `z = -T^T w` (push-through
    /// identity): a sum of positive terms in G's eigenbasis, so no cancellation.
    fn inverse_norm(&mut self, _z: &[f64], _q: &mut [f64]) -> f64 {
        let k = self.k;
        self.v.copy_from_slice(self.w);
        forward_solve(self.chol, k, self.v);
        backward_solve(self.chol, k, self.v);
        let mut s = 0.0;
        for a in 0..k {
            s += self.w[a] * dot(&self.gram[a * k..(a + 1) * k], self.v);
        }
        s.max(0.0).sqrt()
    }

    fn bracket_data(&self) -> (f64, f64, f64) {
        least_squares_bracket_data(self.t, self.u, self.n)
    }

    fn steepest_descent(&self, z: &mut [f64]) {
        least_squares_steepest_descent(self.t, self.u, self.n, z);
    }
}

/// The augmented model in normal form `g^T z + 0.5 z^T H z` (possibly indefinite), factored by
/// Cholesky of `H + lambda I`.
struct QuadraticModel<'a> {
    n: usize,
    h: &'a [f64],
    g: &'a [f64],
    /// Lower Cholesky factor of the last shifted system.
    chol: &'a mut [f64],
}

impl Subproblem for QuadraticModel<'_> {
    fn n(&self) -> usize {
        self.n
    }

    fn newton(&mut self, z: &mut [f64]) -> Option<f64> {
        let n = self.n;
        if !cholesky_shifted(self.h, 0.0, n, RANK_TOL, self.chol) {
            return None;
        }
        for i in 0..n {
            z[i] = -self.g[i];
        }
        forward_solve(self.chol, n, z);
        backward_solve(self.chol, n, z);
        Some(-0.5 * dot(self.g, z))
    }

    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        let n = self.n;
        if !cholesky_shifted(self.h, lam, n, SHIFTED_TOL, self.chol) {
            return false;
        }
        for i in 0..n {
            z[i] = -self.g[i];
        }
        forward_solve(self.chol, n, z);
        backward_solve(self.chol, n, z);
        true
    }

    fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64 {
        let n = self.n;
        q[..n].copy_from_slice(&z[..n]);
        forward_solve(self.chol, n, q);
        norm(&q[..n])
    }

    fn bracket_data(&self) -> (f64, f64, f64) {
        let n = self.n;
        let mut hnorm = 0.0f64;
        let mut min_diag = f64::INFINITY;
        for j in 0..n {
            let col: f64 = self.h[j * n..(j + 1) * n].iter().map(|v| v.abs()).sum();
            hnorm = hnorm.max(col);
            min_diag = min_diag.min(self.h[j * n + j]);
        }
        (norm(self.g), hnorm, min_diag)
    }

    fn steepest_descent(&self, z: &mut [f64]) {
        for (zi, gi) in z.iter_mut().zip(self.g) {
            *zi = -gi;
        }
    }
}

/// Relative growth of the step's norm below which [`reached_minimum_norm_step`] calls the
/// steps converged.
const MIN_NORM_STEP_TOL: f64 = 1e-10;

/// Whether the trust-region iteration has converged to the minimum-norm Gauss-Newton step
/// inside the region, where the boundary is out of reach ([`Options::stop_at_minimum_norm_step`]);
/// `inside_norm` is the norm of the previous step inside, negative before the first.
///
/// Without a Gauss-Newton step (`newton_norm < 0`: the model is singular) and without a
/// positive lower bound on lambda, the steps `z(lambda)` grow as lambda falls towards the
/// minimum-norm minimiser of the model. When that lies inside the region, no lambda puts the
/// step on the boundary, and the iteration divides lambda by 1000 until its 60-step limit
/// (down to lambda ~ 1e-180). MINPACK's `lmpar` stops in this case once the step stops
/// growing (`parl = 0` and `fp <= temp < 0`, Moré 1978); so does this, once the step grew by
/// less than [`MIN_NORM_STEP_TOL`] relative to the step before.
fn reached_minimum_norm_step(lo: f64, newton_norm: f64, nz: f64, inside_norm: f64) -> bool {
    lo == 0.0 && newton_norm < 0.0 && nz <= inside_norm * (1.0 + MIN_NORM_STEP_TOL)
}

/// Minimises the free-set model subject to `||z|| <= radius` (More-Sorensen/Hebden iteration on
/// `lambda`); `z` receives the step; `best` (the best feasible step seen) and `q` are scratch.
/// `stop_at_min_norm` is [`Options::stop_at_minimum_norm_step`].
fn trust_region(
    sub: &mut impl Subproblem,
    radius: f64,
    lambda_guess: f64,
    stop_at_min_norm: bool,
    z: &mut [f64],
    best: &mut [f64],
    q: &mut [f64],
) -> TrResult {
    let n = sub.n();
    let (gnorm, hnorm, min_diag) = sub.bracket_data();
    if gnorm == 0.0 {
        z.fill(0.0);
        return TrResult {
            lambda: 0.0,
            newton_reduction: 0.0,
            newton_norm: 0.0,
            is_newton: true,
        };
    }
    if !gnorm.is_finite() || !hnorm.is_finite() {
        // A broken model (overflow in the factorization): no step, and no claim of
        // stationarity (this once returned a zero "Newton" step, reported as code 4).
        z.fill(0.0);
        return TrResult {
            lambda: lambda_guess,
            newton_reduction: -1.0,
            newton_norm: -1.0,
            is_newton: false,
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
    // The norm of the last step found inside the region (see the minimum-norm test below);
    // -1 before the first, so that the test cannot pass on it.
    let mut inside_norm = -1.0;
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
            if stop_at_min_norm && reached_minimum_norm_step(lo, newton_norm, nz, inside_norm) {
                break;
            }
            inside_norm = nz;
        }
        if hi - lo <= 1e-14 * hi {
            break;
        }
        // Newton step on 1/||z(lambda)|| - 1/radius (Hebden): needs ||L^-1 z||.
        let nq = sub.inverse_norm(z, q);
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
        // No factorization succeeded inside the bracket: fall back to a scaled gradient step.
        sub.steepest_descent(z);
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
        ws.hold_dead = options.hold_dead_columns;
        ws.stop_at_min_norm = options.stop_at_minimum_norm_step;
        ws.scaling_decay = options.scaling_decay;
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

/// Iterations and evaluations so far (N2FB's NITER, NFCALL, NGCALL).
#[derive(Clone, Copy, Debug, Default)]
struct Counts {
    iterations: usize,
    residuals: usize,
    jacobians: usize,
}

/// The trust radius and NL2SOL's bookkeeping for changing it (DA7SST, DG7ITB).
#[derive(Clone, Copy, Debug)]
struct TrustRadius {
    rule: RadiusUpdate,
    /// The radius in the scaled norm `||D s||` (V(RADIUS)).
    radius: f64,
    /// RADFAC of the last accepted step: the radius becomes RADFAC * ||D_new s|| once the new
    /// scaling is known (0: nothing pending).
    pending_factor: f64,
    /// RADINC: radius decreases (negative) and longer steps tried (positive) in this iteration;
    /// after a decrease a good step keeps the radius instead of increasing it.
    radinc: i32,
}

/// How the radius changes after an assessed step ([`TrustRadius::after_step`]).
#[derive(Clone, Copy, Debug)]
struct RadiusChange {
    /// RADFAC (N2FB's rule; 0 for the classic rule, which changes the radius at once).
    factor: f64,
    /// Try the longer step at once from the same point (DA7SST's IRC = 5).
    try_longer: bool,
}

/// One trial step, evaluated or restored from the saved good step.
#[derive(Clone, Copy, Debug)]
struct Trial {
    info: StepInfo,
    /// f at the trial point.
    f: f64,
    /// RELDX of the step.
    reldx: f64,
    /// The saved good step was taken instead of the last one computed (NL2SOL's GOODX false).
    restored: bool,
}

/// DA7SST's judgement of a trial step.
#[derive(Clone, Copy, Debug)]
struct Assessment {
    /// f before the step.
    f0: f64,
    /// Actual reduction `f0 - f`.
    ared: f64,
    /// `ared / PREDUC`.
    ratio: f64,
    accepted: bool,
    /// The other model (adaptive choice) predicted the actual reduction better.
    switch_models: bool,
}

/// What happened to a trial step before it could be assessed.
enum TrialResult {
    /// The solve ends here.
    Stop(Outcome),
    /// The residuals could not be evaluated there: the step was rejected, the radius shrunk.
    Failed,
    /// A step to assess.
    Evaluated(Trial),
}

/// A good step kept while a longer one is tried from the same point (NL2SOL's FLSTGD, PLSTGD,
/// DSTSAV); its point, residuals and step are in the workspace's `*_good` buffers.
#[derive(Clone, Copy, Debug)]
struct Good {
    f: f64,
    info: StepInfo,
    reldx: f64,
}

/// NL2SOL's choice between the Gauss-Newton and the augmented model.
#[derive(Clone, Copy, Debug)]
struct ModelChoice {
    adaptive: bool,
    /// The adaptive choice may switch models in this iteration (`adaptive` and S has had
    /// [`Options::adaptive_delay`] updates per parameter).
    switching: bool,
    augmented: bool,
    /// A failed step was already retried with the other model in this iteration.
    switched_this_iteration: bool,
}

impl TrustRadius {
    /// Starts an iteration: applies the factor of the last accepted step with the new scaling.
    /// N2FB (DG7ITB): `t = RADFAC * ||D_new s||`; the radius becomes t when RADFAC < 1 or t is
    /// larger, so a short step never shrinks it otherwise; RADFAC 1 becomes 2 when the gradient
    /// tests pass.
    fn start_iteration(&mut self, ws: &Workspace) {
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
    fn after_failed_evaluation(&mut self, dnorm: f64) {
        self.radius = 0.5 * dnorm.min(self.radius);
        self.radinc -= 1;
    }

    /// After a failed Jacobian at an accepted point (the solver returns to the previous point).
    fn after_failed_jacobian(&mut self) {
        self.radius *= 0.5;
        self.pending_factor = 0.0;
    }

    /// DA7SST's radius decision for an assessed step; `gts` = `g^T s`. A rejected step changes
    /// the radius at once; an accepted one leaves RADFAC to be applied by
    /// [`TrustRadius::start_iteration`] (N2FB's rule). `switching`: the adaptive model choice
    /// may switch models in this iteration; then no longer step is tried (our departure from
    /// NL2SOL, measured in [`RadiusUpdate::Nl2sol`]'s docs).
    fn after_step(
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
    fn try_longer(&mut self, factor: f64, dnorm: f64) {
        self.radinc += 1;
        self.radius = factor * dnorm;
    }
}

impl ModelChoice {
    /// Retries a failed step from the same point with the other model, once per iteration.
    fn retry_with_other(&mut self, ws: &mut Workspace) {
        if !self.switched_this_iteration {
            self.augmented = !self.augmented;
            self.switched_this_iteration = true;
            ws.build_model(self.augmented);
        }
    }
}

/// The state of one descent between iterations (everything but the workspace buffers).
struct Descent<'o> {
    opt: &'o Options,
    counts: Counts,
    /// f at `x` and at `x_prev`.
    f: f64,
    f_prev: f64,
    radius: TrustRadius,
    model: ModelChoice,
    /// The last step was accepted: the next pass starts a new iteration.
    need_jacobian: bool,
    /// `jac` holds J at `x_prev` (the secant update needs the old Jacobian).
    have_prev_jacobian: bool,
    /// A good step saved while a longer one is tried.
    good: Option<Good>,
}

/// Either the descent, or the report when the start already ends the solve.
enum Start<'o> {
    Descent(Descent<'o>),
    Done(Report),
}

impl<'o> Descent<'o> {
    /// Evaluates the start. Only here is a failed evaluation an error.
    fn start<P: Problem>(
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
                rule: opt.radius_update,
                radius: opt.initial_radius,
                pending_factor: 0.0,
                radinc: 0,
            },
            model: ModelChoice {
                adaptive: opt.model == StepModel::Adaptive,
                switching: opt.model == StepModel::Adaptive && opt.adaptive_delay == 0,
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
        if f < opt.abs_function_tol {
            return Ok(Start::Done(d.report(Outcome::AbsoluteFunctionConvergence)));
        }
        ws.s_mat[..p * p].fill(0.0);
        Ok(Start::Descent(d))
    }

    fn report(&self, outcome: Outcome) -> Report {
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
    fn new_iteration<P: Problem>(
        &mut self,
        ws: &mut Workspace,
        problem: &mut P,
    ) -> Result<Option<Outcome>, SolveError> {
        let (m, p) = (ws.m, ws.p);
        if self.counts.iterations >= self.opt.max_iterations {
            return Ok(Some(Outcome::IterationLimit));
        }
        if problem.should_stop() {
            return Ok(Some(Outcome::Interrupted));
        }
        // S is kept by the secant update for the augmented model and for the scaling.
        let secant_scaling = self.opt.secant_scaling;
        let keep_secant = self.have_prev_jacobian && (self.model.adaptive || secant_scaling);
        if keep_secant {
            // (J_old)^T r_new for y# before J is overwritten.
            jt_vec(&ws.jac, &ws.r, m, p, &mut ws.ysharp);
        }
        self.counts.jacobians += 1;
        let ok = problem.jacobian(&ws.x[..p], &mut ws.jac[..m * p]) && ws.survey_jacobian();
        if !ok {
            if self.counts.iterations == 0 {
                return Err(SolveError::StartNotEvaluable);
            }
            // Treat like a failed evaluation of the step that led here: go back. The
            // factorization, g, J^T J and D still describe x_prev: they are only recomputed
            // after a successful Jacobian.
            ws.return_to_previous();
            self.f = self.f_prev;
            self.have_prev_jacobian = false;
            self.need_jacobian = false;
            self.radius.after_failed_jacobian();
            if self.counts.iterations >= self.opt.max_iterations {
                return Ok(Some(Outcome::IterationLimit));
            }
            return Ok(None);
        }
        self.counts.iterations += 1;
        if keep_secant && secant_scaling {
            // The scaling needs the updated S, so S is updated before the factorization, from
            // g = J^T r computed directly (as in NL2SOL, where DUPDAT follows the secant update).
            ws.g[..p].copy_from_slice(&ws.jtr[..p]);
            ws.secant_update_from_gradients();
        }
        // The secant term enters the scaling once S has had `secant_scaling_delay` updates per
        // parameter (Options::secant_scaling_delay).
        let secant_in_scaling =
            secant_scaling && ws.secant_updates >= self.opt.secant_scaling_delay.saturating_mul(p);
        ws.update_scaling(self.counts.iterations == 1, secant_in_scaling);
        self.model.switching =
            self.model.adaptive && ws.secant_updates >= self.opt.adaptive_delay.saturating_mul(p);
        if self.counts.iterations == 1 {
            // Optionally (Options::lift_round_off_radius), a first step that is a round-off
            // change of x is lifted to sqrt(eps) relative to x in the scaled norm.
            let norm_x = ws.scaled_norm_x();
            if self.opt.lift_round_off_radius && self.radius.radius < ROUND_OFF_STEP * norm_x {
                self.radius.radius = f64::EPSILON.sqrt() * norm_x;
            }
        }
        ws.factor_jacobian();
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

    /// Computes the step in the trust region and evaluates f there, or takes the saved good
    /// step when the longer one is not worth evaluating or does not beat it.
    fn trial_step<P: Problem>(&mut self, ws: &mut Workspace, problem: &mut P) -> TrialResult {
        let p = ws.p;
        let opt = self.opt;
        let info = ws.compute_step(self.radius.radius, self.model.augmented);
        if let Some(good) = self.good {
            // DG7ITB: the longer step is evaluated only if it predicts more than 1.2 times the
            // reduction the saved step achieved (and the budget allows); otherwise the saved
            // step is taken.
            let worthwhile = info.dnorm > 0.0
                && info.preduc > 1.2 * (self.f - good.f)
                && self.counts.residuals < opt.max_evaluations;
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
            let emax = opt.rel_function_tol * self.f.abs();
            let stationary = (info.dnorm == 0.0 || (info.nreduc >= 0.0 && info.nreduc <= emax))
                && !info.dead_free
                && ws.gradient_permits_rel_conv(opt.rel_function_tol);
            return TrialResult::Stop(if stationary {
                Outcome::RelativeFunctionConvergence
            } else {
                Outcome::SingularConvergence
            });
        }
        if self.counts.residuals >= opt.max_evaluations {
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
            if reldx <= opt.false_conv_tol {
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

    /// A rejected trial step gets one second-order correction
    /// ([`Options::second_order_correction`], [`Workspace::corrected_step`]): when the corrected
    /// step is accepted it replaces the trial, judged like any trial but against the uncorrected
    /// step's PREDUC (the model predicted nothing for the correction), else the rejected trial
    /// stands with its step.
    fn correct_if_rejected<P: Problem>(
        &mut self,
        ws: &mut Workspace,
        problem: &mut P,
        trial: Trial,
        assessment: Assessment,
    ) -> (Trial, Assessment) {
        // (No longer step is pending here: `trial_step` clears the saved good step before it
        // returns an evaluated trial.)
        if assessment.accepted
            || !self.opt.second_order_correction
            || trial.restored
            || self.counts.residuals >= self.opt.max_evaluations
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

    /// Evaluates the residuals at `x_trial` into `r_trial` (counted against the budget):
    /// `f` there (NaN when they cannot be evaluated) and the step's RELDX.
    fn evaluate_trial_point<P: Problem>(
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
    fn restore_good(&mut self, ws: &mut Workspace) -> Trial {
        let good = self.good.take().expect("a saved good step");
        ws.swap_good();
        Trial {
            info: good.info,
            f: good.f,
            reldx: good.reldx,
            restored: true,
        }
    }

    /// Keeps a good step and tries the longer one from the same point (same Jacobian).
    fn keep_good(&mut self, ws: &mut Workspace, trial: &Trial) {
        ws.swap_good();
        self.good = Some(Good {
            f: trial.f,
            info: trial.info,
            reldx: trial.reldx,
        });
    }

    /// Accept or reject the step (actual against predicted reduction), and whether the other
    /// model (adaptive choice) would have predicted the actual reduction better.
    fn assess(&self, ws: &mut Workspace, trial: &Trial) -> Assessment {
        let f0 = self.f;
        let ared = f0 - trial.f;
        let ratio = ared / trial.info.preduc;
        let accepted = ared > 0.0 && ratio > ACCEPT_RATIO;
        let mut switch_models = false;
        if self.model.switching && !trial.restored && !(ared > 0.1 * trial.info.preduc) {
            let augmented = self.model.augmented;
            // The augmented model predicts `pred_gn - 0.5 s^T S s` (this sign was reversed
            // before, so the adaptive solver never left the Gauss-Newton model).
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
    fn convergence_test(
        &self,
        ws: &mut Workspace,
        trial: &Trial,
        a: &Assessment,
    ) -> Option<Outcome> {
        let opt = self.opt;
        let info = &trial.info;
        if !(a.ared <= 2.0 * info.preduc) {
            return None;
        }
        let emax = opt.rel_function_tol * a.f0.abs();
        let emaxs = opt.singular_tol * a.f0.abs();
        // The gate on the projected gradient (computed at x0 = ws.x, where NREDUC was) keeps a
        // broken NREDUC from claiming convergence; see `gradient_permits_rel_conv`.
        // N2FB judges by the NREDUC of the model in use. With the augmented model that counts
        // only where the Gauss-Newton step exists too (J nonsingular on the free set), so an
        // augmented model that merely predicts no decrease where J is singular cannot claim
        // convergence; without it, a large-residual minimum approached by augmented Newton steps
        // (whose Gauss-Newton NREDUC shrinks only linearly) ended in singular convergence.
        let within = |reduction: f64| reduction > 0.0 && reduction <= emax;
        let rel = (within(info.nreduc)
            || (info.nreduc >= 0.0 && within(info.model_nreduc))
            || (info.nreduc == 0.0 && info.preduc == 0.0))
            && ws.gradient_permits_rel_conv(opt.rel_function_tol);
        // A restored step is not the last one computed (NL2SOL's GOODX = false).
        let xconv = info.newton && a.accepted && !trial.restored && trial.reldx <= opt.x_tol;
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
            // change, Options::singular_radius_at_least_x; see the crate docs, "Robustness").
            let test_radius = if opt.singular_radius_at_least_x {
                opt.singular_radius.max(ws.scaled_norm_x())
            } else {
                opt.singular_radius
            };
            if info.dnorm > test_radius || info.newton {
                return Some(Outcome::SingularConvergence);
            }
            // Re-solve at the test radius from x0 without evaluating f.
            if ws.singular_test_reduction(test_radius, self.model.augmented) <= emaxs {
                return Some(Outcome::SingularConvergence);
            }
        }
        None
    }

    /// Accepts the trial point; RADFAC is applied at the next iteration.
    fn accept(&mut self, ws: &mut Workspace, trial: &Trial, a: &Assessment, change: &RadiusChange) {
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

    /// The tests after the convergence tests: absolute function convergence after an accepted
    /// step, false convergence after a rejected or poor one whose RELDX is at round-off.
    fn stop_test(&self, trial: &Trial, a: &Assessment) -> Option<Outcome> {
        if a.accepted && self.f < self.opt.abs_function_tol {
            return Some(Outcome::AbsoluteFunctionConvergence);
        }
        if (!a.accepted || a.ratio < 0.1) && trial.reldx <= self.opt.false_conv_tol {
            return Some(Outcome::FalseConvergence);
        }
        None
    }
}

/// The main loop (see the crate docs for the tests and their precedence).
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
        let converged = descent.convergence_test(ws, &trial, &assessment);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic upper-triangular `n x n` matrix whose rows from `k` on are zero (what the
    /// QR of a `k`-row Jacobian gives), and a right-hand side zero from `k` on.
    fn trapezoid(n: usize, k: usize) -> (Vec<f64>, Vec<f64>) {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut t = vec![0.0; n * n];
        for j in 0..n {
            for a in 0..=j.min(k - 1) {
                t[j * n + a] = next() + if a == j { 3.0 } else { 0.0 };
            }
        }
        let u = (0..n).map(|a| if a < k { next() } else { 0.0 }).collect();
        (t, u)
    }

    #[allow(clippy::too_many_arguments)]
    fn wide_model<'a>(
        n: usize,
        k: usize,
        t: &'a [f64],
        u: &'a [f64],
        gram: &'a mut [f64],
        chol: &'a mut [f64],
        w: &'a mut [f64],
        v: &'a mut [f64],
    ) -> WideLeastSquaresModel<'a> {
        WideLeastSquaresModel {
            n,
            k,
            t,
            u,
            gram,
            chol,
            w,
            v,
        }
        .with_gram()
    }

    /// Counts the shifted factorizations of the model it wraps.
    struct Counted<S> {
        sub: S,
        shifted: usize,
    }

    impl<S: Subproblem> Subproblem for Counted<S> {
        fn n(&self) -> usize {
            self.sub.n()
        }
        fn newton(&mut self, z: &mut [f64]) -> Option<f64> {
            self.sub.newton(z)
        }
        fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
            self.shifted += 1;
            self.sub.shifted(lam, z)
        }
        fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64 {
            self.sub.inverse_norm(z, q)
        }
        fn bracket_data(&self) -> (f64, f64, f64) {
            self.sub.bracket_data()
        }
        fn steepest_descent(&self, z: &mut [f64]) {
            self.sub.steepest_descent(z)
        }
    }

    /// A singular model whose minimum-norm step lies inside the region: with
    /// `stop_at_min_norm` the iteration returns that step after a few factorizations; without
    /// it, it runs to its 60-step limit.
    #[test]
    fn singular_model_stops_at_its_minimum_norm_step() {
        // 0.5 ||u + T z||^2 with variable 1 dead: the minimum-norm minimiser solves
        // 2 z0 + z2 = -0.2, 3 z2 = 0.3, z1 = 0, so z = (-0.15, 0, 0.1), of norm 0.18.
        let n = 3;
        let t = [2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 3.0];
        let u = [0.2, 0.0, -0.3];
        let want = [-0.15, 0.0, 0.1];
        let mut counts = vec![];
        for stop in [true, false] {
            let (mut t_lambda, mut u_lambda) = (vec![0.0; n * n], vec![0.0; n]);
            let mut row = vec![0.0; shifted_scratch_len(n)];
            let mut sub = Counted {
                sub: LeastSquaresModel {
                    n,
                    t: &t,
                    u: &u,
                    t_lambda: &mut t_lambda,
                    u_lambda: &mut u_lambda,
                    row: &mut row,
                },
                shifted: 0,
            };
            let (mut z, mut best, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            let tr = trust_region(&mut sub, 1.0, 0.0, stop, &mut z, &mut best, &mut q);
            assert!(
                !tr.is_newton && tr.newton_norm < 0.0,
                "singular: no Newton step"
            );
            for (a, b) in z.iter().zip(&want) {
                assert!((a - b).abs() < 1e-9, "stop {stop}: {z:?}");
            }
            counts.push(sub.shifted);
        }
        assert!(
            counts[0] <= 10,
            "with the stop: {} factorizations",
            counts[0]
        );
        assert_eq!(counts[1], 60, "without it, the 60-step limit");
    }

    /// The dual (wide) model gives the primal Givens model's step and `||L^-1 z||`.
    #[test]
    fn wide_model_matches_the_primal_model() {
        for (n, k) in [(8, 3), (20, 7), (40, 39)] {
            let (t, u) = trapezoid(n, k);
            let mut t_lambda = vec![0.0; n * n];
            let (mut u_lambda, mut row) = (vec![0.0; n], vec![0.0; shifted_scratch_len(n)]);
            let mut primal = LeastSquaresModel {
                n,
                t: &t,
                u: &u,
                t_lambda: &mut t_lambda,
                u_lambda: &mut u_lambda,
                row: &mut row,
            };
            let (mut gram, mut chol) = (vec![0.0; k * k], vec![0.0; k * k]);
            let (mut w, mut v) = (vec![0.0; k], vec![0.0; k]);
            let mut wide = wide_model(n, k, &t, &u, &mut gram, &mut chol, &mut w, &mut v);
            assert_eq!(primal.bracket_data(), wide.bracket_data());
            assert!(wide.newton(&mut vec![0.0; n]).is_none());
            for lam in [1e-3, 0.1, 1.0, 30.0, 1e4] {
                let (mut zp, mut zw, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                assert!(primal.shifted(lam, &mut zp));
                assert!(wide.shifted(lam, &mut zw));
                let scale = norm(&zp);
                for (a, b) in zp.iter().zip(&zw) {
                    assert!(
                        (a - b).abs() <= 1e-11 * scale,
                        "n {n} k {k} lam {lam}: {a} {b}"
                    );
                }
                let np = primal.inverse_norm(&zp, &mut q);
                let nw = wide.inverse_norm(&zw, &mut q);
                assert!(
                    (np - nw).abs() <= 1e-9 * np,
                    "n {n} k {k} lam {lam}: {np} {nw}"
                );
            }
        }
    }

    /// The trust-region iteration ends at the same step with either model.
    #[test]
    fn wide_trust_region_step_matches_the_primal_one() {
        let (n, k) = (30, 6);
        let (t, u) = trapezoid(n, k);
        let mut t_lambda = vec![0.0; n * n];
        let (mut u_lambda, mut row) = (vec![0.0; n], vec![0.0; shifted_scratch_len(n)]);
        let (mut gram, mut chol) = (vec![0.0; k * k], vec![0.0; k * k]);
        let (mut w, mut v) = (vec![0.0; k], vec![0.0; k]);
        let (mut best, mut q) = (vec![0.0; n], vec![0.0; n]);
        for radius in [1e-3, 0.05, 0.5] {
            let mut primal = LeastSquaresModel {
                n,
                t: &t,
                u: &u,
                t_lambda: &mut t_lambda,
                u_lambda: &mut u_lambda,
                row: &mut row,
            };
            let mut zp = vec![0.0; n];
            let rp = trust_region(&mut primal, radius, 0.0, true, &mut zp, &mut best, &mut q);
            let mut wide = wide_model(n, k, &t, &u, &mut gram, &mut chol, &mut w, &mut v);
            let mut zw = vec![0.0; n];
            let rw = trust_region(&mut wide, radius, 0.0, true, &mut zw, &mut best, &mut q);
            // Within the region; on its boundary unless the minimum-norm Gauss-Newton step (the
            // limit lambda -> 0 of the singular model) is shorter.
            assert!(
                norm(&zw) <= radius * (1.0 + RADIUS_SLACK),
                "radius {radius}"
            );
            assert!(
                (rp.lambda - rw.lambda).abs() <= 1e-8 * rp.lambda.max(1e-12),
                "radius {radius}: {} {}",
                rp.lambda,
                rw.lambda
            );
            for (a, b) in zp.iter().zip(&zw) {
                assert!((a - b).abs() <= 1e-8 * radius, "radius {radius}: {a} {b}");
            }
        }
    }
}
