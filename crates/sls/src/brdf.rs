//! [`BrdfObjective`]: the BRDF fitting problem (brdf-model) as an [`Objective`].

use crate::SearchRng;
use crate::objective::{Objective, Rows};
use brdf_model::{DataSet, Evaluator, Layout, Subsampler};
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
    /// The problem of fitting `layout` to `data`.
    pub fn new(data: Arc<DataSet>, layout: Layout) -> Self {
        Self { data, layout }
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
            evaluator: Evaluator::new(&self.layout),
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
