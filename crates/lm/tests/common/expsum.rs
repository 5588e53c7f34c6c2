//! Synthetic exponential-sum fitting problem (shared by tests and benches).

#![allow(dead_code)]

use bounded_lm::{Problem, ResidualsOnly};

/// Sum of `p / 2` exponentials fitted to `m` synthetic points (no allocation in evaluation).
pub struct ExpSum {
    t: Vec<f64>,
    y: Vec<f64>,
    p: usize,
}

impl ExpSum {
    pub fn new(m: usize, p: usize) -> Self {
        let t: Vec<f64> = (0..m).map(|i| 4.0 * i as f64 / m as f64).collect();
        let y = t
            .iter()
            .map(|&t| 2.0 * (-0.5 * t).exp() + (-2.0 * t).exp() + 0.5 * (-5.0 * t).exp())
            .collect();
        Self { t, y, p }
    }
}

impl ResidualsOnly for ExpSum {
    fn residual_count(&self) -> usize {
        self.t.len()
    }
    fn parameter_count(&self) -> usize {
        self.p
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        for ((ri, &t), &y) in r.iter_mut().zip(&self.t).zip(&self.y) {
            let mut v = 0.0;
            for k in 0..self.p / 2 {
                v += x[2 * k] * (-x[2 * k + 1] * t).exp();
            }
            *ri = v - y;
        }
        true
    }
}

impl Problem for ExpSum {
    fn residual_count(&self) -> usize {
        self.t.len()
    }
    fn parameter_count(&self) -> usize {
        self.p
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        ResidualsOnly::residuals(self, x, r)
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        let m = self.t.len();
        for (i, &t) in self.t.iter().enumerate() {
            for k in 0..self.p / 2 {
                let e = (-x[2 * k + 1] * t).exp();
                jac[2 * k * m + i] = e;
                jac[(2 * k + 1) * m + i] = -x[2 * k] * t * e;
            }
        }
        true
    }
}
