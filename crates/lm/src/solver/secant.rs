//! NL2SOL's secant approximation `S` of the second-order term `sum_i r_i H_i`: the sized
//! Dennis-Gay-Welsch update after each accepted step.

use super::workspace::Workspace;
use crate::linalg::{dot, norm, sym_mat_vec};

impl Workspace {
    /// The secant update after an accepted step from `g` (new gradient), `g_prev` and
    /// `ysharp` holding `J_old^T r_new`: `y = g_new - g_old`, `y# = J_new^T r_new - J_old^T
    /// r_new`.
    pub(super) fn secant_update_from_gradients(&mut self) {
        for i in 0..self.p {
            self.secant.y[i] = self.g[i] - self.g_prev[i];
            self.secant.ysharp[i] = self.g[i] - self.secant.ysharp[i];
        }
        self.secant_update();
    }

    /// NL2SOL's secant update of `S` after an accepted step (`step` = s, `y` = gradient change,
    /// `ysharp` = `(J_new - J_old)^T r_new`), with Dennis-Gay-Welsch sizing.
    pub(super) fn secant_update(&mut self) {
        self.secant.updates += 1;
        let p = self.p;
        sym_mat_vec(&self.secant.s, &self.step, p, &mut self.secant.w);
        let sss = dot(&self.step[..p], &self.secant.w[..p]);
        let sy_sharp = dot(&self.step[..p], &self.secant.ysharp[..p]);
        if sss != 0.0 {
            let tau = (sy_sharp / sss).abs().min(1.0);
            for v in self.secant.s[..p * p].iter_mut() {
                *v *= tau;
            }
            for v in self.secant.w[..p].iter_mut() {
                *v *= tau;
            }
        }
        let sy = dot(&self.step[..p], &self.secant.y[..p]);
        // Skip the update when the curvature information is useless (s^T y ~ 0).
        if !(sy.abs() > 1e-30 * norm(&self.step[..p]) * norm(&self.secant.y[..p])) || sy == 0.0 {
            return;
        }
        for i in 0..p {
            self.secant.w[i] = self.secant.ysharp[i] - self.secant.w[i];
        }
        let ws = dot(&self.secant.w[..p], &self.step[..p]);
        for j in 0..p {
            for i in 0..p {
                let v = (self.secant.w[i] * self.secant.y[j] + self.secant.y[i] * self.secant.w[j])
                    / sy
                    - ws * self.secant.y[i] * self.secant.y[j] / (sy * sy);
                self.secant.s[j * p + i] += v;
            }
        }
        if self.secant.s[..p * p].iter().any(|v| !v.is_finite()) {
            self.secant.s[..p * p].fill(0.0);
        }
    }
}
