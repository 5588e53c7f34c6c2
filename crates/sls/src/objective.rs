//! The problem the search algorithms see: a box, a full-data RMSE, and bounded least-squares
//! problems over subsamples for the descent.
//!
//! The trait is deliberately small (argmin's `CostFunction`/`Jacobian` split, merged): every
//! evaluation goes through [`crate::TrialContext`], which counts it, so an implementation never
//! counts anything itself.

use crate::SearchRng;
use rand::RngExt;

/// Which rows of the data set a least-squares problem covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rows {
    /// Every sample, in data-set order.
    Full,
    /// A fresh subsample of this many distinct samples, drawn without replacement (the paper's
    /// `Subsample(S, rho)`); a size at or above the data size means [`Rows::Full`].
    Subsample(usize),
}

impl Rows {
    /// The rows for subsample size `rho` (a real number in AED) on `n` samples: `rho` rounded to
    /// the nearest integer (at least 1), [`Rows::Full`] once it reaches `n`.
    pub fn sized(rho: f64, n: usize) -> Rows {
        let k = rho.round().max(1.0);
        if k >= n as f64 {
            Rows::Full
        } else {
            Rows::Subsample(k as usize)
        }
    }

    /// Number of rows selected out of `n` samples.
    pub fn count(self, n: usize) -> usize {
        match self {
            Rows::Full => n,
            Rows::Subsample(k) => k.min(n),
        }
    }
}

/// An instance as the search algorithms see it: minimise the RMSE over a data set within a box.
///
/// Coordinates are the optimiser's ("internal") coordinates: whatever transformation the
/// implementation applies (e.g. brdf-model's `ln(1 + n)` exponent coordinate) is invisible here.
/// All evaluation methods take the per-trial [`Objective::Workspace`] so that nothing allocates
/// inside the search loop; the objective itself is shared (read-only) between trials running on
/// different threads.
pub trait Objective: Sync {
    /// Per-trial scratch: evaluator buffers, the current row selection, gathered subsamples.
    type Workspace: Send;

    /// A fresh workspace (allocated once per trial).
    fn workspace(&self) -> Self::Workspace;

    /// Number of free parameters.
    fn dim(&self) -> usize;

    /// Lower bounds of the box (length [`Objective::dim`]).
    fn lower(&self) -> &[f64];

    /// Upper bounds of the box (length [`Objective::dim`]).
    fn upper(&self) -> &[f64];

    /// Number of samples in the full data set.
    fn sample_count(&self) -> usize;

    /// The paper's `RandomPick`: a candidate drawn uniformly in the box, in the optimiser's
    /// coordinates, written into `x`.
    ///
    /// Uniform in optimiser coordinates is the default on purpose: when an exponent is held as
    /// `u = ln(1 + n)` this draws `u` uniformly, i.e. `n` log-uniformly-ish, instead of `n`
    /// uniformly in `[0, 10000]`, which makes about half of all picks unevaluable (`d^n`
    /// overflows when `d > 1`).
    fn random_pick(&self, rng: &mut SearchRng, x: &mut [f64]) {
        for ((xi, &lo), &hi) in x.iter_mut().zip(self.lower()).zip(self.upper()) {
            *xi = if hi > lo {
                rng.random_range(lo..=hi)
            } else {
                lo
            };
        }
    }

    /// RMSE of `x` over the full data set; `+inf` when it cannot be evaluated (overflow,
    /// non-finite values).
    fn rmse(&self, ws: &mut Self::Workspace, x: &[f64]) -> f64;

    /// [`Objective::rmse`] for a caller that only needs it when it is at most `bound`:
    /// returns `(Some(rmse), rows)` with the exact RMSE (equal bit for bit to
    /// [`Objective::rmse`]), or `(None, rows)` only when the RMSE is certainly above `bound`;
    /// `rows` is how many samples were actually evaluated. The default evaluates everything.
    fn rmse_below(&self, ws: &mut Self::Workspace, x: &[f64], bound: f64) -> (Option<f64>, usize) {
        let _ = bound;
        (Some(self.rmse(ws, x)), self.sample_count())
    }

    /// Selects the rows later [`Objective::residuals`] and [`Objective::jacobian`] calls cover
    /// (drawing a subsample with `rng` if asked) and returns how many were selected.
    fn select(&self, ws: &mut Self::Workspace, rows: Rows, rng: &mut SearchRng) -> usize;

    /// Residuals `model_i(x) - y_i` over the selected rows into `r`; `false` when they cannot be
    /// computed.
    fn residuals(&self, ws: &mut Self::Workspace, x: &[f64], r: &mut [f64]) -> bool;

    /// Column-major Jacobian (`jac[j * m + i] = d r_i / d x_j`) over the selected rows; `false`
    /// when it cannot be computed.
    fn jacobian(&self, ws: &mut Self::Workspace, x: &[f64], jac: &mut [f64]) -> bool;

    /// Coordinate `i` in the problem's natural units (monotone increasing in `x`); the identity
    /// unless the implementation reparameterises (brdf-model's `ln(1 + n)` exponent).
    fn natural_value(&self, i: usize, x: f64) -> f64 {
        let _ = i;
        x
    }

    /// Inverse of [`Objective::natural_value`].
    fn optimiser_value(&self, i: usize, v: f64) -> f64 {
        let _ = i;
        v
    }
}

#[cfg(test)]
pub(crate) mod toy {
    //! A small exponential-decay fit used by the unit tests before (and besides) the BRDF model:
    //! `y = a * exp(-b t) + c` on `t` in `[0, 4]`, box `[0, 5] x [0, 5] x [-1, 1]`.

    use super::{Objective, Rows};
    use crate::SearchRng;
    use rand::RngExt;

    /// The toy instance.
    pub struct Toy {
        t: Vec<f64>,
        y: Vec<f64>,
        lower: [f64; 3],
        upper: [f64; 3],
    }

    /// Scratch: the selected rows.
    pub struct ToyWork {
        rows: Vec<usize>,
        perm: Vec<usize>,
    }

    impl Toy {
        /// `n` samples of `2 exp(-1.5 t) + 0.3`, plus uniform noise of half-width `noise`.
        pub fn new(n: usize, noise: f64, seed: u64) -> Self {
            use rand::SeedableRng;
            let mut rng = SearchRng::seed_from_u64(seed);
            let t: Vec<f64> = (0..n).map(|i| 4.0 * i as f64 / n as f64).collect();
            let y = t
                .iter()
                .map(|&t| {
                    let e = if noise > 0.0 {
                        rng.random_range(-noise..noise)
                    } else {
                        0.0
                    };
                    2.0 * (-1.5 * t).exp() + 0.3 + e
                })
                .collect();
            Self {
                t,
                y,
                lower: [0.0, 0.0, -1.0],
                upper: [5.0, 5.0, 1.0],
            }
        }
    }

    impl Objective for Toy {
        type Workspace = ToyWork;
        fn workspace(&self) -> ToyWork {
            ToyWork {
                rows: (0..self.t.len()).collect(),
                perm: (0..self.t.len()).collect(),
            }
        }
        fn dim(&self) -> usize {
            3
        }
        fn lower(&self) -> &[f64] {
            &self.lower
        }
        fn upper(&self) -> &[f64] {
            &self.upper
        }
        fn sample_count(&self) -> usize {
            self.t.len()
        }
        fn rmse(&self, _ws: &mut ToyWork, x: &[f64]) -> f64 {
            let s: f64 = self
                .t
                .iter()
                .zip(&self.y)
                .map(|(&t, &y)| (x[0] * (-x[1] * t).exp() + x[2] - y).powi(2))
                .sum();
            (s / self.t.len() as f64).sqrt()
        }
        fn select(&self, ws: &mut ToyWork, rows: Rows, rng: &mut SearchRng) -> usize {
            let n = self.t.len();
            let k = rows.count(n);
            ws.rows.clear();
            match rows {
                Rows::Full => ws.rows.extend(0..n),
                Rows::Subsample(_) => {
                    // Partial Fisher-Yates over a persistent permutation.
                    for i in 0..k {
                        let j = rng.random_range(i..n);
                        ws.perm.swap(i, j);
                    }
                    ws.rows.extend_from_slice(&ws.perm[..k]);
                }
            }
            k
        }
        fn residuals(&self, ws: &mut ToyWork, x: &[f64], r: &mut [f64]) -> bool {
            for (ri, &i) in r.iter_mut().zip(&ws.rows) {
                *ri = x[0] * (-x[1] * self.t[i]).exp() + x[2] - self.y[i];
            }
            r.iter().all(|v| v.is_finite())
        }
        fn jacobian(&self, ws: &mut ToyWork, x: &[f64], jac: &mut [f64]) -> bool {
            let m = ws.rows.len();
            for (k, &i) in ws.rows.iter().enumerate() {
                let e = (-x[1] * self.t[i]).exp();
                jac[k] = e;
                jac[m + k] = -x[0] * self.t[i] * e;
                jac[2 * m + k] = 1.0;
            }
            true
        }
    }
}
