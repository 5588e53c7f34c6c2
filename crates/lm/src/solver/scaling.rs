//! The scaling `D`: one survey pass over each new Jacobian, NL2SOL's update of `D` from the
//! column norms (and the secant term), and the scaled norms and RELDX measured with it.

use super::workspace::Workspace;
use crate::linalg::survey_columns;

impl Workspace {
    /// One pass over a new Jacobian, column by column: the sum of squares (for the scaling),
    /// the max-abs entry (for the dead-column test) and `J^T r` (for the secant update), which
    /// were four passes over the `m x p` matrix, counting the finiteness check. The sums are
    /// accumulated exactly as [`dot`] does, so the results are bit for bit those of the
    /// separate passes. Returns whether every entry is finite: a non-finite entry makes its
    /// column's sum of squares non-finite; a finite column can overflow that sum only with
    /// entries above 1e154, and is then checked entry by entry.
    pub(super) fn survey_jacobian(&mut self) -> bool {
        let (m, p) = (self.m, self.p);
        let (jac, r) = (&self.jac[..m * p], &self.r[..m]);
        survey_columns(
            jac,
            r,
            m,
            p,
            &mut self.survey.col_sq,
            &mut self.survey.jtr,
            &mut self.survey.col_amax,
        );
        (0..p).all(|j| {
            self.survey.col_sq[j].is_finite()
                || jac[j * m..(j + 1) * m].iter().all(|v| v.is_finite())
        })
    }

    /// Updates the scaling: `D_i = max(DFAC D_i, ||J_i||_2)` with DFAC = `decay`
    /// ([`Scaling::decay`](crate::Scaling::decay); 1 is MINPACK's non-decreasing rule), the
    /// column 2-norm of the original NL2SOL rather than PORT's column max (which scored lower
    /// on NIST, `docs/solver.md`); a column whose norm is below 1e-6 uses 1 instead, so a dead
    /// parameter keeps a sane scale. With `secant` (once `S` has had the delay's updates),
    /// `||J_i||_2` becomes `sqrt(||J_i||^2 + S_ii)` where `S_ii > 0` (NL2SOL's DUPDAT: the
    /// diagonal of the augmented Hessian `J^T J + S`).
    pub(super) fn update_scaling(&mut self, first: bool, secant: bool, decay: f64) {
        let p = self.p;
        for j in 0..p {
            // The column's 2-norm, from the survey of this Jacobian (the same sum as `norm`).
            let mut cn = self.survey.col_sq[j].sqrt();
            let sii = self.secant.s[j * p + j];
            if secant && sii > 0.0 {
                cn = (cn * cn + sii).sqrt();
            }
            let cand = if cn < 1e-6 { 1.0 } else { cn };
            self.d[j] = if first {
                cand
            } else {
                cand.max(decay * self.d[j])
            };
        }
    }

    /// `RELDX = max_i D_i |a_i - b_i| / max_i D_i (|a_i| + |b_i|)`.
    pub(super) fn reldx(&self, a: &[f64], b: &[f64]) -> f64 {
        let mut num = 0.0f64;
        let mut den = 0.0f64;
        for i in 0..self.p {
            num = num.max(self.d[i] * (a[i] - b[i]).abs());
            den = den.max(self.d[i] * (a[i].abs() + b[i].abs()));
        }
        if den > 0.0 { num / den } else { 0.0 }
    }

    pub(super) fn scaled_norm_step(&self) -> f64 {
        let mut s = 0.0;
        for i in 0..self.p {
            let v = self.d[i] * self.step[i];
            s += v * v;
        }
        s.sqrt()
    }

    /// `||D x||`.
    pub(super) fn scaled_norm_x(&self) -> f64 {
        let mut s = 0.0;
        for i in 0..self.p {
            let v = self.d[i] * self.x[i];
            s += v * v;
        }
        s.sqrt()
    }

    /// `||D (x - x_prev)||`: the scaled length of the last accepted step with the current `D`.
    pub(super) fn scaled_norm_last_step(&self) -> f64 {
        let mut s2 = 0.0;
        for i in 0..self.p {
            let v = self.d[i] * (self.x[i] - self.x_prev[i]);
            s2 += v * v;
        }
        s2.sqrt()
    }
}
