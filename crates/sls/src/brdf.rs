//! [`BrdfObjective`]: fitting any brdf-model family to a data set, as an [`Objective`].

use crate::SearchRng;
use crate::objective::{Objective, Rows};
use brdf_model::{
    DataSet, Evaluator, ExponentCoord, Kernel, KernelError, Layout, Samples, Subsampler,
};
use rand::RngExt;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Fitting a BRDF model ([`Layout`], of any family) to a data set by RMSE, in the layout's
/// internal coordinates. The family's per-sample columns ([`Samples`]) are prepared once and
/// shared by every trial; subsamples are gathered from them.
///
/// [`Objective::random_pick`] is uniform in those coordinates: with the default
/// `ExponentCoord::Log1p` a Lafortune exponent is drawn as `u = ln(1 + n)` uniform in
/// `[0, ln(1 + n_max)]`, so most picks have moderate `n` and can be evaluated (uniform `n` in
/// `[0, 10000]` leaves about half the picks unevaluable on the tuning instance: `d^n`
/// overflows for `d > 1`). With `ExponentCoord::Raw` the pick is uniform in `n`, as in the paper.
/// [`BrdfObjective::with_starts`] chooses the exponent's start distribution independently of
/// the coordinate the descent works in (the ablation of coordinates against starts).
#[derive(Clone, Debug)]
pub struct BrdfObjective {
    data: Arc<DataSet>,
    samples: Arc<Samples>,
    layout: Layout,
    /// The concrete evaluation kernel every workspace uses.
    kernel: Kernel,
    /// How random picks draw each exponent.
    starts: StartDist,
}

/// The distribution of the shape parameters (a Lafortune exponent `n`, a roughness) in random
/// picks (starts); every other parameter is uniform in its bounds whatever this says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StartDist {
    /// Uniform in the optimiser's coordinate: log-uniform (the family's log coordinate,
    /// Lafortune's `ln(1 + n)`, uniform) with `ExponentCoord::Log1p`, uniform in the parameter
    /// with `ExponentCoord::Raw`.
    #[default]
    Coordinate,
    /// Uniform in the parameter's own units within its bounds (the paper's starts for `n`),
    /// whatever the coordinate.
    Uniform,
    /// Uniform in the family's log coordinate of the parameter (Lafortune: `ln(1 + n)`) over
    /// the image of the bounds, whatever the coordinate.
    LogUniform,
}

impl StartDist {
    /// The same distribution spelled as the explicit choice it is under `coord`
    /// (`Coordinate` becomes `Uniform` or `LogUniform`).
    pub fn resolve(self, coord: ExponentCoord) -> StartDist {
        match (self, coord) {
            (StartDist::Coordinate, ExponentCoord::Raw) => StartDist::Uniform,
            (StartDist::Coordinate, ExponentCoord::Log1p) => StartDist::LogUniform,
            (other, _) => other,
        }
    }

    /// The name used in specs and notes (`"uniform"`, `"log-uniform"`, `"coordinate"`).
    pub fn name(self) -> &'static str {
        match self {
            StartDist::Coordinate => "coordinate",
            StartDist::Uniform => "uniform",
            StartDist::LogUniform => "log-uniform",
        }
    }
}

/// Per-trial scratch of a [`BrdfObjective`].
#[derive(Debug)]
pub struct BrdfWorkspace {
    evaluator: Evaluator,
    subsampler: Subsampler,
    subsample: Samples,
    full: bool,
}

impl BrdfObjective {
    /// The problem of fitting `layout` to `data`, evaluated with the fastest kernel the CPU
    /// has ([`Kernel::Auto`]).
    pub fn new(data: Arc<DataSet>, layout: Layout) -> Self {
        let samples = Arc::new(layout.prepare(&data));
        Self::with_samples(data, samples, layout)
    }

    /// [`BrdfObjective::new`] with the family's samples of `data` already prepared
    /// ([`Layout::prepare`]), so that several objectives on one data set share them.
    pub fn with_samples(data: Arc<DataSet>, samples: Arc<Samples>, layout: Layout) -> Self {
        Self {
            data,
            samples,
            layout,
            kernel: Kernel::Auto.resolve().unwrap_or(Kernel::Portable),
            starts: StartDist::Coordinate,
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
            kernel: kernel.resolve()?,
            ..Self::new(data, layout)
        })
    }

    /// [`BrdfObjective::with_samples`] with the evaluation kernel `kernel`.
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the CPU lacks the requested kernel.
    pub fn with_samples_and_kernel(
        data: Arc<DataSet>,
        samples: Arc<Samples>,
        layout: Layout,
        kernel: Kernel,
    ) -> Result<Self, KernelError> {
        Ok(Self {
            kernel: kernel.resolve()?,
            ..Self::with_samples(data, samples, layout)
        })
    }

    /// The same problem with exponents in random picks drawn from `starts` (the descent's
    /// coordinate is the layout's and does not change).
    pub fn with_starts(mut self, starts: StartDist) -> Self {
        self.starts = starts;
        self
    }

    /// The start distribution of the exponents.
    pub fn starts(&self) -> StartDist {
        self.starts
    }

    /// Free shape parameter `i` in the optimiser's coordinate, drawn from `dist` (resolved, so
    /// `Uniform` or `LogUniform`) between the internal bounds `lo..=hi`. One draw per call
    /// either way, so the random stream stays aligned with the other parameters'.
    fn pick_shape(&self, i: usize, dist: StartDist, rng: &mut SearchRng, lo: f64, hi: f64) -> f64 {
        let Some(p) = self.layout.free_param(i) else {
            return lo;
        };
        let (coord, log) = (p.coord, p.def.coord);
        let (plo, phi) = (coord.to_physical(lo), coord.to_physical(hi));
        let v = match dist {
            StartDist::LogUniform => {
                log.to_physical(rng.random_range(log.to_internal(plo)..=log.to_internal(phi)))
            }
            _ => rng.random_range(plo..=phi),
        };
        coord.to_internal(v).clamp(lo, hi)
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

    /// The family's prepared samples of the full data set.
    pub fn samples(&self) -> &Samples {
        &self.samples
    }
}

impl Objective for BrdfObjective {
    type Workspace = BrdfWorkspace;

    fn workspace(&self) -> BrdfWorkspace {
        BrdfWorkspace {
            evaluator: Evaluator::with_kernel(&self.layout, self.kernel)
                .expect("the kernel was resolved on this CPU when the objective was built"),
            subsampler: Subsampler::new(self.data.len()),
            subsample: Samples::empty(self.samples.family(), self.samples.column_count()),
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

    fn random_pick(&self, rng: &mut SearchRng, x: &mut [f64]) {
        let dist = self.starts.resolve(self.layout.exponent_coord());
        let native = StartDist::Coordinate.resolve(self.layout.exponent_coord());
        let (lower, upper) = (self.layout.lower(), self.layout.upper());
        for (i, xi) in x.iter_mut().enumerate() {
            let (lo, hi) = (lower[i], upper[i]);
            *xi = if hi <= lo {
                lo
            } else if dist != native && self.layout.is_exponent(i) {
                self.pick_shape(i, dist, rng, lo, hi)
            } else {
                // The default path draws exactly as `Objective::random_pick` does, so seeded
                // results of existing experiments do not change.
                rng.random_range(lo..=hi)
            };
        }
    }

    fn rmse(&self, ws: &mut BrdfWorkspace, x: &[f64]) -> f64 {
        ws.evaluator.rmse(x, &self.samples)
    }

    fn rmse_below(&self, ws: &mut BrdfWorkspace, x: &[f64], bound: f64) -> (Option<f64>, usize) {
        let n = self.data.len();
        if n == 0 || bound == f64::INFINITY {
            return (Some(ws.evaluator.rmse(x, &self.samples)), n);
        }
        // The sum-of-squares bound, widened by 1e-12 relative so that `None` means the RMSE is
        // above `bound` beyond any rounding of the square root and division.
        let ss_bound = bound.max(0.0).powi(2) * n as f64 * (1.0 + 1e-12);
        let s = ws.evaluator.sum_squares_below(x, &self.samples, ss_bound);
        // The same arithmetic as `Evaluator::rmse`, so an exact result is identical to it.
        let rmse = s.sum_squares.map(|ss| (ss / n as f64).sqrt());
        (rmse, s.samples)
    }

    fn select(&self, ws: &mut BrdfWorkspace, rows: Rows, rng: &mut SearchRng) -> usize {
        let n = self.data.len();
        match rows {
            Rows::Subsample(k) if k < n => {
                let drawn = ws.subsampler.draw(k, rng);
                self.samples.gather_into(drawn, &mut ws.subsample);
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
        let data = if ws.full {
            &self.samples
        } else {
            &ws.subsample
        };
        ws.evaluator.residuals(x, data, r)
    }

    fn jacobian(&self, ws: &mut BrdfWorkspace, x: &[f64], jac: &mut [f64]) -> bool {
        let data = if ws.full {
            &self.samples
        } else {
            &ws.subsample
        };
        ws.evaluator.jacobian(x, data, jac)
    }

    /// The parameter's physical value (a Lafortune exponent's `n`; a coordinate without a
    /// transformation is its own natural value).
    fn natural_value(&self, i: usize, x: f64) -> f64 {
        self.layout.coord(i).to_physical(x)
    }

    fn optimiser_value(&self, i: usize, v: f64) -> f64 {
        self.layout.coord(i).to_internal(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_model::{ExponentCoord, LobeKind};
    use rand::SeedableRng;

    /// Median of the exponent `n` over many picks of a one-lobe objective.
    fn median_n(coord: ExponentCoord, starts: StartDist) -> f64 {
        let layout = Layout::builder(&[LobeKind::Isotropic])
            .exponent_coord(coord)
            .build()
            .unwrap();
        let data = Arc::new(brdf_model::synthetic(
            &brdf_model::named_params("paper-bluepaint").unwrap(),
            10,
            0.0,
            1,
        ));
        let obj = BrdfObjective::new(data, layout.clone()).with_starts(starts);
        let mut rng = SearchRng::seed_from_u64(5);
        let mut x = vec![0.0; obj.dim()];
        let mut ns: Vec<f64> = (0..2001)
            .map(|_| {
                obj.random_pick(&mut rng, &mut x);
                let n = layout.decode(&x).get("lobe1.n").unwrap();
                assert!((0.0..=10_000.0).contains(&n), "{n}");
                n
            })
            .collect();
        ns.sort_by(f64::total_cmp);
        ns[1000]
    }

    #[test]
    fn starts_are_independent_of_the_coordinate() {
        // Uniform n in [0, 10000] has median 5000; log-uniform has median e^(ln 10001 / 2) - 1
        // = 99. Each distribution must come out the same in both coordinates.
        for coord in [ExponentCoord::Raw, ExponentCoord::Log1p] {
            let u = median_n(coord, StartDist::Uniform);
            let l = median_n(coord, StartDist::LogUniform);
            assert!(
                (4500.0..5500.0).contains(&u),
                "{coord:?} uniform median {u}"
            );
            assert!(
                (70.0..140.0).contains(&l),
                "{coord:?} log-uniform median {l}"
            );
        }
        let raw_native = median_n(ExponentCoord::Raw, StartDist::Coordinate);
        assert_eq!(raw_native, median_n(ExponentCoord::Raw, StartDist::Uniform));
        let log_native = median_n(ExponentCoord::Log1p, StartDist::Coordinate);
        assert!((70.0..140.0).contains(&log_native), "{log_native}");
    }

    #[test]
    fn resolve_names_the_native_distribution() {
        assert_eq!(
            StartDist::Coordinate.resolve(ExponentCoord::Raw),
            StartDist::Uniform
        );
        assert_eq!(
            StartDist::Coordinate.resolve(ExponentCoord::Log1p),
            StartDist::LogUniform
        );
        assert_eq!(
            StartDist::Uniform.resolve(ExponentCoord::Log1p),
            StartDist::Uniform
        );
    }
}
