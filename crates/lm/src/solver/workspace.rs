//! The buffers of a solve, grouped by concern: the iterate and its trial, the factorisation of
//! the scaled Jacobian, the subproblem's models, the secant term, the saved good step and the
//! second-order correction. [`Workspace::required`] gives every buffer's length for `m`
//! residuals and `p` parameters; [`Workspace::prepare`] sets the lengths (allocating only when
//! a buffer must grow past its capacity), so repeated solves of the same or a smaller size
//! allocate nothing.

use crate::linalg::shifted_scratch_len;
use crate::qr::tall_qr_scratch_len;

/// Every buffer length of a solve with `m` residuals and `p` parameters (a size query: the
/// workspace is sized from it once and then reused).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Required {
    /// Residuals.
    pub m: usize,
    /// Parameters.
    pub p: usize,
    /// Scratch of the blocked tall QR.
    pub qr_scratch: usize,
    /// `[R_F | c + R D s]`, `p x (p + 1)`.
    pub ls_block: usize,
    /// Givens scratch rows of the shifted least-squares solve.
    pub ls_row: usize,
}

#[cfg(test)]
impl Required {
    /// Number of `f64` values the workspace holds at these sizes.
    pub fn values(&self) -> usize {
        let (m, p) = (self.m, self.p);
        P_VECTORS * p
            + M_VECTORS * m
            + 2 * m * p
            + P_MATRICES * p * p
            + self.qr_scratch
            + self.ls_block
            + self.ls_row
    }
}

/// Vectors of length `p`, `m` and matrices `p x p` in the workspace.
const P_VECTORS: usize = 38;
const M_VECTORS: usize = 6;
const P_MATRICES: usize = 12;

/// The QR of the scaled Jacobian `J D^-1 = Q R` and what is derived from it.
#[derive(Clone, Debug, Default)]
pub(super) struct Factorisation {
    /// Copy of `J D^-1` reduced in place by Householder QR (small Jacobians).
    pub(super) qr: Vec<f64>,
    /// `Q^T r` work vector (length m).
    pub(super) rq: Vec<f64>,
    /// `R` (p x p upper, rows beyond m zero).
    pub(super) r: Vec<f64>,
    /// First p entries of `Q^T r`.
    pub(super) c: Vec<f64>,
    /// `D^-1` with 0 for dead columns (tall Jacobians) and the tall QR's row block.
    pub(super) col_scale: Vec<f64>,
    pub(super) scratch: Vec<f64>,
    /// Max-abs entry of each scaled column, and which columns are numerically dead and held
    /// (`dead`, only with `Safeguards::hold_dead_columns`).
    pub(super) col_max: Vec<f64>,
    pub(super) dead: Vec<bool>,
    /// Which columns are numerically dead whether or not they are held: the convergence
    /// verdict needs it in every preset, because a free dead column makes the Gauss-Newton
    /// model singular, and a singular model's zero NREDUC does not show a minimum.
    pub(super) dead_seen: Vec<bool>,
    /// `J^T r` at the factored point, recomputed from the Jacobian ([`JacobianSurvey::jtr`]):
    /// a held dead column's `g` is exactly 0, so the active set reads its bound from this.
    pub(super) jtr: Vec<f64>,
    /// `J^T J` (unscaled).
    pub(super) jtj: Vec<f64>,
}

/// From one pass over a new Jacobian ([`Workspace::survey_jacobian`]): each column's sum of
/// squares, its max-abs entry, and `J^T r`.
#[derive(Clone, Debug, Default)]
pub(super) struct JacobianSurvey {
    pub(super) col_sq: Vec<f64>,
    pub(super) col_amax: Vec<f64>,
    pub(super) jtr: Vec<f64>,
}

/// The free-set models of the trust-region subproblem.
#[derive(Clone, Debug, Default)]
pub(super) struct SubproblemBuffers {
    /// Least-squares form of the Gauss-Newton model `0.5 ||u + T z||^2`.
    pub(super) t: Vec<f64>,
    pub(super) u: Vec<f64>,
    /// `[R_F | c + R D s]` reduced to `[T | u]` by Householder QR.
    pub(super) block: Vec<f64>,
    pub(super) rhs: Vec<f64>,
    /// Factor of `[T; sqrt(lambda) I] -> T_lambda`, its right-hand side, the Givens scratch.
    pub(super) t_lambda: Vec<f64>,
    pub(super) u_lambda: Vec<f64>,
    pub(super) row: Vec<f64>,
    /// Dual (wide) form: Gram matrix `T_k T_k^T`, the Cholesky factor of `T_k T_k^T +
    /// lambda I`, the dual solution `w` and `(T_k T_k^T + lambda I)^-1 w`.
    pub(super) gram: Vec<f64>,
    pub(super) wide_chol: Vec<f64>,
    pub(super) w: Vec<f64>,
    pub(super) v: Vec<f64>,
    /// Normal form of the augmented model `g^T z + 0.5 z^T H z` (scaled) and the Cholesky
    /// factor of `H + lambda I`.
    pub(super) h: Vec<f64>,
    pub(super) g: Vec<f64>,
    pub(super) chol: Vec<f64>,
    /// Scaled free-set step `z`, the best feasible one seen, and scratch for `L^-1 z`.
    pub(super) z: Vec<f64>,
    pub(super) best: Vec<f64>,
    pub(super) q: Vec<f64>,
}

/// The secant approximation `S` of the second-order term and its update vectors.
#[derive(Clone, Debug, Default)]
pub(super) struct Secant {
    /// `S` (p x p).
    pub(super) s: Vec<f64>,
    /// Gradient change `y`, `y# = (J_new - J_old)^T r_new`, and scratch.
    pub(super) y: Vec<f64>,
    pub(super) ysharp: Vec<f64>,
    pub(super) w: Vec<f64>,
    /// Updates of `S` so far in this solve.
    pub(super) updates: usize,
}

/// A good trial point, its residuals and step, saved while a longer step is tried.
#[derive(Clone, Debug, Default)]
pub(super) struct SavedStep {
    pub(super) x: Vec<f64>,
    pub(super) r: Vec<f64>,
    pub(super) step: Vec<f64>,
}

/// Second-order correction of a rejected step: the model's error `r(x + s) - r(x) - J s`
/// (length m), the right-hand side and solution, the matrix and its Cholesky factor, and the
/// uncorrected step.
#[derive(Clone, Debug, Default)]
pub(super) struct CorrectionBuffers {
    pub(super) e: Vec<f64>,
    pub(super) b: Vec<f64>,
    pub(super) a: Vec<f64>,
    pub(super) l: Vec<f64>,
    pub(super) step: Vec<f64>,
}

/// All buffers of a solve. Each buffer has one meaning.
#[derive(Clone, Debug, Default)]
pub(super) struct Workspace {
    pub(super) m: usize,
    pub(super) p: usize,
    /// Current iterate, trial point, and the point before the last accepted step.
    pub(super) x: Vec<f64>,
    pub(super) x_trial: Vec<f64>,
    pub(super) x_prev: Vec<f64>,
    /// The box.
    pub(super) lo: Vec<f64>,
    pub(super) hi: Vec<f64>,
    /// Residuals at `x`, `x_trial` and `x_prev`.
    pub(super) r: Vec<f64>,
    pub(super) r_trial: Vec<f64>,
    pub(super) r_prev: Vec<f64>,
    /// Jacobian at `x` (column-major).
    pub(super) jac: Vec<f64>,
    /// Scaling `D`.
    pub(super) d: Vec<f64>,
    /// Gradient `g = J^T r` at `x` and at `x_prev`.
    pub(super) g: Vec<f64>,
    pub(super) g_prev: Vec<f64>,
    /// The model Hessian in use (`J^T J` or `J^T J + S`).
    pub(super) h: Vec<f64>,
    /// The trial step `s`.
    pub(super) step: Vec<f64>,
    /// The step re-solved at radius LMAXS for the singular-convergence test.
    pub(super) singular_step: Vec<f64>,
    /// Model gradient `g + H s` at a partial step (augmented model).
    pub(super) g_model: Vec<f64>,
    /// `S s` for the predicted reductions.
    pub(super) s_step: Vec<f64>,
    /// `H s` of the last accepted step (at the old point), for DG7ITB's gradient tests.
    pub(super) h_step: Vec<f64>,
    /// `D s` and `R D s` for the predicted reductions.
    pub(super) d_step: Vec<f64>,
    pub(super) r_d_step: Vec<f64>,
    /// Held variables and the indices of the free ones.
    pub(super) fixed: Vec<bool>,
    pub(super) free: Vec<usize>,
    /// Last Levenberg-Marquardt parameter, a warm start for the next subproblem.
    pub(super) lambda: f64,
    pub(super) survey: JacobianSurvey,
    pub(super) factors: Factorisation,
    pub(super) sub: SubproblemBuffers,
    pub(super) secant: Secant,
    pub(super) saved: SavedStep,
    pub(super) correction: CorrectionBuffers,
}

fn set_len(v: &mut Vec<f64>, n: usize) {
    v.resize(n, 0.0);
}

impl Workspace {
    /// The buffer lengths of a solve with `m` residuals and `p` parameters.
    pub(super) fn required(m: usize, p: usize) -> Required {
        Required {
            m,
            p,
            qr_scratch: tall_qr_scratch_len(p),
            ls_block: p * (p + 1),
            ls_row: shifted_scratch_len(p),
        }
    }

    /// A workspace allocated for `req`.
    pub(super) fn with_required(req: &Required) -> Self {
        let mut ws = Self::default();
        ws.prepare(req);
        ws
    }

    /// Sets every buffer to its length in `req` and resets the per-solve state.
    pub(super) fn prepare(&mut self, req: &Required) {
        let (m, p) = (req.m, req.p);
        self.m = m;
        self.p = p;
        for v in self.p_vectors() {
            set_len(v, p);
        }
        for v in self.m_vectors() {
            set_len(v, m);
        }
        set_len(&mut self.jac, m * p);
        set_len(&mut self.factors.qr, m * p);
        set_len(&mut self.factors.scratch, req.qr_scratch);
        set_len(&mut self.sub.block, req.ls_block);
        set_len(&mut self.sub.row, req.ls_row);
        for v in self.p_matrices() {
            set_len(v, p * p);
        }
        self.fixed.resize(p, false);
        self.factors.dead.resize(p, false);
        self.factors.dead_seen.resize(p, false);
        self.free.resize(p, 0);
        self.lambda = 0.0;
        self.secant.updates = 0;
    }

    fn p_vectors(&mut self) -> [&mut Vec<f64>; P_VECTORS] {
        [
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
            &mut self.saved.x,
            &mut self.saved.step,
            &mut self.g_model,
            &mut self.s_step,
            &mut self.h_step,
            &mut self.d_step,
            &mut self.r_d_step,
            &mut self.sub.u,
            &mut self.sub.rhs,
            &mut self.sub.u_lambda,
            &mut self.sub.g,
            &mut self.sub.z,
            &mut self.sub.best,
            &mut self.sub.q,
            &mut self.sub.w,
            &mut self.sub.v,
            &mut self.factors.c,
            &mut self.factors.col_scale,
            &mut self.factors.col_max,
            &mut self.factors.jtr,
            &mut self.survey.col_sq,
            &mut self.survey.col_amax,
            &mut self.survey.jtr,
            &mut self.secant.y,
            &mut self.secant.ysharp,
            &mut self.secant.w,
            &mut self.correction.b,
            &mut self.correction.step,
        ]
    }

    fn m_vectors(&mut self) -> [&mut Vec<f64>; M_VECTORS] {
        [
            &mut self.r,
            &mut self.r_trial,
            &mut self.r_prev,
            &mut self.saved.r,
            &mut self.factors.rq,
            &mut self.correction.e,
        ]
    }

    fn p_matrices(&mut self) -> [&mut Vec<f64>; P_MATRICES] {
        [
            &mut self.factors.jtj,
            &mut self.factors.r,
            &mut self.secant.s,
            &mut self.h,
            &mut self.sub.t,
            &mut self.sub.t_lambda,
            &mut self.sub.h,
            &mut self.sub.chol,
            &mut self.sub.gram,
            &mut self.sub.wide_chol,
            &mut self.correction.a,
            &mut self.correction.l,
        ]
    }

    /// Swaps the trial point, its residuals and the step with the saved good ones (saving one,
    /// or restoring it; buffers are swapped, not copied).
    pub(super) fn swap_saved(&mut self) {
        std::mem::swap(&mut self.x_trial, &mut self.saved.x);
        std::mem::swap(&mut self.r_trial, &mut self.saved.r);
        std::mem::swap(&mut self.step, &mut self.saved.step);
    }

    /// Accepts the trial point: the current point becomes the previous one.
    pub(super) fn accept_trial(&mut self) {
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
    pub(super) fn return_to_previous(&mut self) {
        let (m, p) = (self.m, self.p);
        self.x[..p].copy_from_slice(&self.x_prev[..p]);
        self.r[..m].copy_from_slice(&self.r_prev[..m]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every buffer gets its length, and a second prepare at the same size keeps the storage.
    #[test]
    fn prepare_sizes_every_buffer_and_reuses_it() {
        let req = Workspace::required(30, 7);
        let mut ws = Workspace::with_required(&req);
        let lens: usize = ws.p_vectors().iter().map(|v| v.len()).sum::<usize>()
            + ws.m_vectors().iter().map(|v| v.len()).sum::<usize>()
            + ws.p_matrices().iter().map(|v| v.len()).sum::<usize>()
            + ws.jac.len()
            + ws.factors.qr.len()
            + ws.factors.scratch.len()
            + ws.sub.block.len()
            + ws.sub.row.len();
        assert_eq!(lens, req.values());
        let before = ws.x.as_ptr();
        ws.prepare(&Workspace::required(20, 5));
        ws.prepare(&req);
        assert_eq!(ws.x.as_ptr(), before);
        assert_eq!((ws.x.len(), ws.r.len(), ws.secant.s.len()), (7, 30, 49));
    }
}
