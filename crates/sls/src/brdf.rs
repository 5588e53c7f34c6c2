//! [`BrdfObjective`]: the BRDF fitting problem (brdf-model) as an [`Objective`].

use crate::SearchRng;
use crate::objective::{Objective, Rows};
use brdf_model::{DataSet, Evaluator, Kernel, KernelError, Layout, Subsampler};
use std::sync::Arc;

/// Fitting a Lafortune BRDF ([`Layout`]) to a data set by RMSE, in the layout's internal
/// coordinates.
///
/// [`Objective::random_pick`] is uniform in those coordinates: with the default
/// `ExponentCoord::Log1p` the exponent is drawn as `u = ln(1 + n)` uniform in
/// `[0, ln(1 + n_max)]`, so most picks have moderate `n` and can be evaluated (uniform `n` in
/// `[0, 10000]` leaves about half the picks unevaluable on the tuning instance: `d^n`
/// overflows for `d > 1`). With `ExponentCoord::Raw` the pick is uniform in `n`, as in the paper.
#[derive(Clone, Debug)]
pub struct BrdfObjective {
    data: Arc<DataSet>,
    layout: Layout,
    /// The concrete evaluation kernel every workspace uses.
    kernel: Kernel,
}

/// Per-trial scratch of a [`BrdfObjective`].
#[derive(Clone, Debug)]
pub struct BrdfWorkspace {
    evaluator: Evaluator,
    subsampler: Subsampler,
    subsample: DataSet,
    full: bool,
}

impl BrdfObjective {
    /// The problem of fitting `layout` to `data`, evaluated with the fastest kernel the CPU
    /// has ([`Kernel::Auto`]).
    pub fn new(data: Arc<DataSet>, layout: Layout) -> Self {
        Self {
            data,
            layout,
            kernel: Kernel::Auto.resolve().unwrap_or(Kernel::Portable),
        }
    }

    /// [`BrdfObjective::new`] with the evaluation kernel `kernel` (resolved here: every trial's
    /// workspace uses the same concrete kernel).
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the CPU lacks the requested kernel.
    pub fn with_kernel(
        data: Arc<DataSet>,
        layout: Layout,
        kernel: Kernel,
    ) -> Result<Self, KernelError> {
        Ok(Self {
            data,
            layout,
            kernel: kernel.resolve()?,
        })
    }

    /// The concrete kernel in use (never [`Kernel::Auto`]); `kernel().name()` (`"avx512"`,
    /// `"avx2"`, `"portable"`, `"scalar"`) is what to record next to results.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// The parameter layout (decode `TrialResult::best_x` with `layout().decode`).
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The full data set.
    pub fn data(&self) -> &DataSet {
        &self.data
    }
}

impl Objective for BrdfObjective {
    type Workspace = BrdfWorkspace;

    fn workspace(&self) -> BrdfWorkspace {
        BrdfWorkspace {
            evaluator: Evaluator::with_kernel(&self.layout, self.kernel)
                .expect("the kernel was resolved on this CPU when the objective was built"),
            subsampler: Subsampler::new(self.data.len()),
            subsample: DataSet::new(),
            full: true,
        }
    }

    fn dim(&self) -> usize {
        self.layout.dim()
    }

    fn lower(&self) -> &[f64] {
        self.layout.lower()
    }

    fn upper(&self) -> &[f64] {
        self.layout.upper()
    }

    fn sample_count(&self) -> usize {
        self.data.len()
    }

    fn rmse(&self, ws: &mut BrdfWorkspace, x: &[f64]) -> f64 {
        ws.evaluator.rmse(x, &self.data)
    }

    fn rmse_below(&self, ws: &mut BrdfWorkspace, x: &[f64], bound: f64) -> (Option<f64>, usize) {
        let n = self.data.len();
        if n == 0 || bound == f64::INFINITY {
            return (Some(ws.evaluator.rmse(x, &self.data)), n);
        }
        // The sum-of-squares bound, widened by 1e-12 relative so that `None` means the RMSE is
        // above `bound` beyond any rounding of the square root and division.
        let ss_bound = bound.max(0.0).powi(2) * n as f64 * (1.0 + 1e-12);
        let s = ws.evaluator.sum_squares_below(x, &self.data, ss_bound);
        // The same arithmetic as `Evaluator::rmse`, so an exact result is identical to it.
        let rmse = s.sum_squares.map(|ss| (ss / n as f64).sqrt());
        (rmse, s.samples)
    }

    fn select(&self, ws: &mut BrdfWorkspace, rows: Rows, rng: &mut SearchRng) -> usize {
        let n = self.data.len();
        match rows {
            Rows::Subsample(k) if k < n => {
                let drawn = ws.subsampler.draw(k, rng);
                self.data.gather_into(drawn, &mut ws.subsample);
                ws.full = false;
                k
            }
            _ => {
                ws.full = true;
                n
            }
        }
    }

    fn residuals(&self, ws: &mut BrdfWorkspace, x: &[f64], r: &mut [f64]) -> bool {
        let data = if ws.full { &self.data } else { &ws.subsample };
        ws.evaluator.residuals(x, data, r)
    }

    fn jacobian(&self, ws: &mut BrdfWorkspace, x: &[f64], jac: &mut [f64]) -> bool {
        let data = if ws.full { &self.data } else { &ws.subsample };
        ws.evaluator.jacobian(x, data, jac)
    }

    /// The exponent's physical `n`; every other coordinate is its own natural value.
    fn natural_value(&self, i: usize, x: f64) -> f64 {
        if self.layout.is_exponent(i) {
            self.layout.exponent_coord().to_physical(x)
        } else {
            x
        }
    }

    fn optimiser_value(&self, i: usize, v: f64) -> f64 {
        if self.layout.is_exponent(i) {
            self.layout.exponent_coord().to_internal(v)
        } else {
            v
        }
    }
}
