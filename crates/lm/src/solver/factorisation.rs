//! The QR of the scaled Jacobian `J D^-1 = Q R`, with numerically dead columns zeroed, and
//! `J^T J` and `g = J^T r` from it.

use super::workspace::Workspace;
use crate::linalg::dot;
use crate::qr::{TALL_QR_MIN_ROWS, householder_qr, tall_qr};

/// Relative size of a diagonal entry of the triangular factor of the scaled free Jacobian below
/// which the Gauss-Newton model counts as singular (no Gauss-Newton step).
pub(super) const QR_RANK_TOL: f64 = 1e-13;

/// A column of the scaled Jacobian `J D^-1` whose norm is at most this fraction of the largest
/// is numerically dead (a BRDF lobe with `d^n ~ 1e-150`): moving its variable across the whole
/// trust region changes `J s` by less than the rounding of the live columns. It is zeroed before
/// the QR and its variable held, like a variable on a bound.
pub(super) const DEAD_COLUMN: f64 = f64::EPSILON;

/// True when the upper-triangular `t` (`n x n`) has no diagonal entry below
/// `QR_RANK_TOL` times the largest (a Gauss-Newton step exists).
pub(super) fn triangular_full_rank(t: &[f64], n: usize) -> bool {
    let dmax = (0..n).fold(0.0f64, |a, i| a.max(t[i * n + i].abs()));
    dmax > 0.0 && (0..n).all(|i| t[i * n + i].abs() > QR_RANK_TOL * dmax)
}

/// From a Householder QR done in place (column-major, `ld` rows, `n` columns) and its rotated
/// right-hand side `Q^T rhs` (length `ld`): the `n x n` upper triangle `r` and the first `n`
/// entries `c`, zero in the rows from `ld` on (a QR with fewer rows than columns).
pub(super) fn triangle_of_qr(
    qr: &[f64],
    ld: usize,
    qtr: &[f64],
    n: usize,
    r: &mut [f64],
    c: &mut [f64],
) {
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
    /// QR of the scaled Jacobian `J D^-1 = Q R`, `c = Q^T r`, and from them `J^T J` and
    /// `g = J^T r` (unscaled) for the augmented model, the secant update and the active set.
    ///
    /// A numerically dead scaled column ([`DEAD_COLUMN`]) is zeroed and its variable marked
    /// `dead` (held by [`Workspace::hold_active_bounds`]): left in, such a column made `R` so
    /// ill-conditioned that the subproblem moved the dead variables by garbage amounts, and its
    /// squares underflowed in the QR.
    pub(super) fn factor_jacobian(&mut self, hold_dead: bool) {
        let p = self.p;
        if self.m >= TALL_QR_MIN_ROWS && self.m >= p {
            self.factor_tall(hold_dead);
        } else {
            self.factor_in_place(hold_dead);
        }
        if hold_dead {
            // A held column's g below is exactly 0; the active set needs its true sign.
            self.factors.jtr[..p].copy_from_slice(&self.survey.jtr[..p]);
        }
        for j in 0..p {
            let cj = &self.factors.r[j * p..(j + 1) * p];
            self.g[j] = self.d[j] * dot(cj, &self.factors.c[..p]);
            for k in 0..=j {
                let v = self.d[j] * self.d[k] * dot(cj, &self.factors.r[k * p..(k + 1) * p]);
                self.factors.jtj[j * p + k] = v;
                self.factors.jtj[k * p + j] = v;
            }
        }
    }

    /// Tall Jacobians: the blocked [`tall_qr`] reads `J` once, scaling by `D^-1` (0 for a dead
    /// column) on the fly, so neither the `m x p` scaled copy nor the copy of `r` is written.
    pub(super) fn factor_tall(&mut self, hold_dead: bool) {
        let (m, p) = (self.m, self.p);
        let mut max_scaled = 0.0f64;
        for j in 0..p {
            // max |J_ij| / D_j is exactly max |J_ij / D_j| (rounding is monotone), as below;
            // max |J_ij| comes from the survey of this Jacobian.
            self.factors.col_max[j] = self.survey.col_amax[j] * (1.0 / self.d[j]);
            max_scaled = max_scaled.max(self.factors.col_max[j]);
        }
        for j in 0..p {
            let dead = !(self.factors.col_max[j] > DEAD_COLUMN * max_scaled);
            self.factors.dead_seen[j] = dead;
            self.factors.dead[j] = hold_dead && dead;
            self.factors.col_scale[j] = if self.factors.dead[j] {
                0.0
            } else {
                1.0 / self.d[j]
            };
        }
        tall_qr(
            &self.jac[..m * p],
            m,
            p,
            &self.factors.col_scale[..p],
            &self.r[..m],
            &mut self.factors.r[..p * p],
            &mut self.factors.c[..p],
            &mut self.factors.scratch,
        );
    }

    /// Small Jacobians: scaled copy, in-place [`householder_qr`], `R` and `c` copied out.
    pub(super) fn factor_in_place(&mut self, hold_dead: bool) {
        let (m, p) = (self.m, self.p);
        let mut max_scaled = 0.0f64;
        for j in 0..p {
            let inv = 1.0 / self.d[j];
            for (q, &v) in self.factors.qr[j * m..(j + 1) * m]
                .iter_mut()
                .zip(&self.jac[j * m..(j + 1) * m])
            {
                *q = v * inv;
            }
            // Dead columns are tiny: their 2-norm via max-abs avoids underflow in the squares.
            let amax = self.factors.qr[j * m..(j + 1) * m]
                .iter()
                .fold(0.0f64, |a, v| a.max(v.abs()));
            self.factors.col_max[j] = amax;
            max_scaled = max_scaled.max(amax);
        }
        for j in 0..p {
            // max-abs is within sqrt(m) of the 2-norm; comparing max-abs values is enough here.
            let dead = !(self.factors.col_max[j] > DEAD_COLUMN * max_scaled);
            self.factors.dead_seen[j] = dead;
            self.factors.dead[j] = hold_dead && dead;
            if self.factors.dead[j] {
                self.factors.qr[j * m..(j + 1) * m].fill(0.0);
            }
        }
        self.factors.rq[..m].copy_from_slice(&self.r[..m]);
        householder_qr(
            &mut self.factors.qr[..m * p],
            m,
            p,
            &mut self.factors.rq[..m],
        );
        triangle_of_qr(
            &self.factors.qr[..m * p],
            m,
            &self.factors.rq[..m],
            p,
            &mut self.factors.r[..p * p],
            &mut self.factors.c[..p],
        );
    }
}
