//! Data sets (structure of arrays), synthetic instances, filters and subsampling.

use crate::params::{BrdfParams, ParamError};
use rand::{Rng, RngExt, SeedableRng};
use rand_distr::StandardNormal;
use std::io::Write;

/// BRDF samples stored structure-of-arrays: incident direction `u`, exitant direction `v`
/// (unit vectors pointing away from the surface, z = normal) and the measured value.
///
/// Beside the directions it keeps the products every lobe needs, `P = ux vx`, `Q = uy vy`,
/// `R = ux vy + uy vx` (one rounding, as a fused multiply-add gives) and `S = uz vz`: they are
/// the same for every parameter vector, so the kernels read four columns instead of six and
/// skip recomputing them for each lobe, evaluation and Jacobian column.
#[derive(Clone, Debug, Default)]
pub struct DataSet {
    pub(crate) ux: Vec<f64>,
    pub(crate) uy: Vec<f64>,
    pub(crate) uz: Vec<f64>,
    pub(crate) vx: Vec<f64>,
    pub(crate) vy: Vec<f64>,
    pub(crate) vz: Vec<f64>,
    pub(crate) value: Vec<f64>,
    pub(crate) pxx: Vec<f64>,
    pub(crate) pyy: Vec<f64>,
    pub(crate) pxy: Vec<f64>,
    pub(crate) pzz: Vec<f64>,
    /// Changes (to a value never used before) whenever the samples change, so that an
    /// evaluator can tell that the data behind a cached evaluation are still the same. Clones
    /// share it: their samples are equal. 0 only for a data set never written to.
    pub(crate) stamp: u64,
}

/// Two data sets are equal when their samples are (the stamps do not matter).
impl PartialEq for DataSet {
    fn eq(&self, other: &Self) -> bool {
        self.ux == other.ux
            && self.uy == other.uy
            && self.uz == other.uz
            && self.vx == other.vx
            && self.vy == other.vy
            && self.vz == other.vz
            && self.value == other.value
    }
}

/// Source of [`DataSet::stamp`] values.
static NEXT_STAMP: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

fn fresh_stamp() -> u64 {
    NEXT_STAMP.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// Borrowed columns of a range of samples (what the evaluation kernels read).
#[derive(Clone, Copy, Debug)]
pub(crate) struct View<'a> {
    pub(crate) ux: &'a [f64],
    pub(crate) uy: &'a [f64],
    pub(crate) uz: &'a [f64],
    pub(crate) vx: &'a [f64],
    pub(crate) vy: &'a [f64],
    pub(crate) vz: &'a [f64],
    pub(crate) value: &'a [f64],
    pub(crate) pxx: &'a [f64],
    pub(crate) pyy: &'a [f64],
    pub(crate) pxy: &'a [f64],
    pub(crate) pzz: &'a [f64],
}

/// The direction products `[P, Q, R, S]` of one sample (see [`DataSet`]).
#[inline]
fn products(u: [f64; 3], v: [f64; 3]) -> [f64; 4] {
    [
        u[0] * v[0],
        u[1] * v[1],
        u[0].mul_add(v[1], u[1] * v[0]),
        u[2] * v[2],
    ]
}

impl DataSet {
    /// An empty data set.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty data set with room for `n` samples.
    pub fn with_capacity(n: usize) -> Self {
        let v = || Vec::with_capacity(n);
        DataSet {
            ux: v(),
            uy: v(),
            uz: v(),
            vx: v(),
            vy: v(),
            vz: v(),
            value: v(),
            pxx: v(),
            pyy: v(),
            pxy: v(),
            pzz: v(),
            stamp: 0,
        }
    }

    /// Builds a data set from its columns `[ux, uy, uz, vx, vy, vz, value]` (stored as given);
    /// `None` when the lengths differ.
    pub fn from_columns(cols: [Vec<f64>; 7]) -> Option<Self> {
        let n = cols[0].len();
        if cols.iter().any(|c| c.len() != n) {
            return None;
        }
        let [ux, uy, uz, vx, vy, vz, value] = cols;
        let mut d = DataSet {
            ux,
            uy,
            uz,
            vx,
            vy,
            vz,
            value,
            ..DataSet::default()
        };
        d.fill_products();
        Some(d)
    }

    /// Computes the product columns from the directions.
    fn fill_products(&mut self) {
        self.stamp = fresh_stamp();
        let n = self.len();
        for c in [&mut self.pxx, &mut self.pyy, &mut self.pxy, &mut self.pzz] {
            c.clear();
            c.reserve(n);
        }
        for i in 0..n {
            self.push_products(self.u(i), self.v(i));
        }
    }

    fn push_products(&mut self, u: [f64; 3], v: [f64; 3]) {
        let [p, q, r, s] = products(u, v);
        self.pxx.push(p);
        self.pyy.push(q);
        self.pxy.push(r);
        self.pzz.push(s);
    }

    /// Samples `lo..hi` as borrowed columns.
    pub(crate) fn view(&self, lo: usize, hi: usize) -> View<'_> {
        View {
            ux: &self.ux[lo..hi],
            uy: &self.uy[lo..hi],
            uz: &self.uz[lo..hi],
            vx: &self.vx[lo..hi],
            vy: &self.vy[lo..hi],
            vz: &self.vz[lo..hi],
            value: &self.value[lo..hi],
            pxx: &self.pxx[lo..hi],
            pyy: &self.pyy[lo..hi],
            pxy: &self.pxy[lo..hi],
            pzz: &self.pzz[lo..hi],
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.value.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.value.is_empty()
    }

    /// Appends one sample (directions are stored as given).
    pub fn push(&mut self, u: [f64; 3], v: [f64; 3], value: f64) {
        self.ux.push(u[0]);
        self.uy.push(u[1]);
        self.uz.push(u[2]);
        self.vx.push(v[0]);
        self.vy.push(v[1]);
        self.vz.push(v[2]);
        self.value.push(value);
        self.push_products(u, v);
        self.stamp = fresh_stamp();
    }

    /// Removes all samples, keeping the capacity.
    pub fn clear(&mut self) {
        self.stamp = fresh_stamp();
        for c in [
            &mut self.ux,
            &mut self.uy,
            &mut self.uz,
            &mut self.vx,
            &mut self.vy,
            &mut self.vz,
            &mut self.value,
            &mut self.pxx,
            &mut self.pyy,
            &mut self.pxy,
            &mut self.pzz,
        ] {
            c.clear();
        }
    }

    /// Incident direction of sample `i`.
    pub fn u(&self, i: usize) -> [f64; 3] {
        [self.ux[i], self.uy[i], self.uz[i]]
    }
    /// Exitant direction of sample `i`.
    pub fn v(&self, i: usize) -> [f64; 3] {
        [self.vx[i], self.vy[i], self.vz[i]]
    }
    /// Measured value of sample `i`.
    pub fn value(&self, i: usize) -> f64 {
        self.value[i]
    }
    /// All measured values.
    pub fn values(&self) -> &[f64] {
        &self.value
    }
    /// x components of the incident directions.
    pub fn u_x(&self) -> &[f64] {
        &self.ux
    }
    /// y components of the incident directions.
    pub fn u_y(&self) -> &[f64] {
        &self.uy
    }
    /// z components (cosines) of the incident directions.
    pub fn u_z(&self) -> &[f64] {
        &self.uz
    }
    /// x components of the exitant directions.
    pub fn v_x(&self) -> &[f64] {
        &self.vx
    }
    /// y components of the exitant directions.
    pub fn v_y(&self) -> &[f64] {
        &self.vy
    }
    /// z components (cosines) of the exitant directions.
    pub fn v_z(&self) -> &[f64] {
        &self.vz
    }

    /// Copies the samples `rows` into `out`, replacing its contents and reusing its capacity
    /// (no allocation once `out` has grown to `rows.len()`). Rows out of range are skipped.
    ///
    /// Column by column, with one fresh stamp for the whole gather: row by row, with a stamp
    /// from the shared atomic counter per row, this was 8% of AED's CPU time on the tuning
    /// instance (perf), where every descent gathers its 25-sample subsample.
    pub fn gather_into(&self, rows: &[u32], out: &mut DataSet) {
        out.clear();
        let n = self.len();
        let cols = [
            (&mut out.ux, &self.ux),
            (&mut out.uy, &self.uy),
            (&mut out.uz, &self.uz),
            (&mut out.vx, &self.vx),
            (&mut out.vy, &self.vy),
            (&mut out.vz, &self.vz),
            (&mut out.value, &self.value),
            (&mut out.pxx, &self.pxx),
            (&mut out.pyy, &self.pyy),
            (&mut out.pxy, &self.pxy),
            (&mut out.pzz, &self.pzz),
        ];
        if rows.iter().all(|&r| (r as usize) < n) {
            // The usual case: a map over the slice has an exact length, so `extend` writes
            // without a capacity check per element (the filtered form below was 3.9% of
            // AED's CPU time on the tuning instance, perf).
            for (dst, from) in cols {
                dst.extend(rows.iter().map(|&r| from[r as usize]));
            }
        } else {
            for (dst, from) in cols {
                let kept = rows.iter().filter(|&&r| (r as usize) < n);
                dst.extend(kept.map(|&r| from[r as usize]));
            }
        }
    }

    /// RMSE of `params` (scalar reference evaluation) against the values.
    pub fn rmse_of(&self, params: &BrdfParams) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let ss: f64 = (0..self.len())
            .map(|i| {
                let e = params.value(self.u(i), self.v(i)) - self.value[i];
                e * e
            })
            .sum();
        (ss / self.len() as f64).sqrt()
    }

    /// Minimum and maximum value (`None` when empty).
    pub fn value_range(&self) -> Option<(f64, f64)> {
        let mut it = self.value.iter().copied();
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), v| (lo.min(v), hi.max(v))))
    }

    /// Writes the data set as CSV with header `ux,uy,uz,vx,vy,vz,value` (shortest round-trip
    /// decimal representation, so reading it back gives the same numbers).
    pub fn write_csv<W: Write>(&self, mut w: W) -> std::io::Result<()> {
        writeln!(w, "ux,uy,uz,vx,vy,vz,value")?;
        for i in 0..self.len() {
            let (u, v) = (self.u(i), self.v(i));
            writeln!(
                w,
                "{},{},{},{},{},{},{}",
                u[0], u[1], u[2], v[0], v[1], v[2], self.value[i]
            )?;
        }
        Ok(())
    }
}

/// A direction uniform by solid angle on the upper hemisphere: `cos theta = xi1`,
/// `phi = 2 pi xi2`.
pub fn uniform_hemisphere<R: Rng + ?Sized>(rng: &mut R) -> [f64; 3] {
    let z: f64 = rng.random::<f64>();
    let phi = std::f64::consts::TAU * rng.random::<f64>();
    let r = (1.0 - z * z).max(0.0).sqrt();
    [r * phi.cos(), r * phi.sin(), z]
}

/// Most samples of a data set built by [`try_synthetic`] or read by the readers in
/// [`crate::io`]: 10,000,000 (about 560 MB of [`DataSet`]).
pub const MAX_SAMPLES: usize = 10_000_000;

/// Largest noise standard deviation [`try_synthetic`] accepts: 1000 (model values are of
/// order 0.1 to 100; the paper uses 0.1).
pub const MAX_SIGMA: f64 = 1000.0;

/// A synthetic instance as in the paper: `count` samples with incident and exitant directions
/// drawn independently and uniformly by solid angle over the hemisphere, value
/// `f(u, v) + sigma * N(0, 1)` (no noise when `sigma == 0`). Seeded: the same `seed` always
/// gives the same data (PCG64-MCG).
///
/// Unchecked, kept for compatibility: a huge `count` aborts on allocation and bad parameters
/// or `sigma` give NaN or infinite values. Prefer [`try_synthetic`], which gives the same data
/// when its checks pass.
pub fn synthetic(params: &BrdfParams, count: usize, sigma: f64, seed: u64) -> DataSet {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    let mut d = DataSet::with_capacity(count);
    for _ in 0..count {
        let u = uniform_hemisphere(&mut rng);
        let v = uniform_hemisphere(&mut rng);
        let mut y = params.value(u, v);
        if sigma != 0.0 {
            let z: f64 = rng.sample(StandardNormal);
            y += sigma * z;
        }
        d.push(u, v, y);
    }
    d
}

/// [`synthetic`] with its inputs checked first: `params` by [`BrdfParams::validate`] (finite,
/// inside the Table 1 box, at most [`crate::params::MAX_LOBES`] lobes), `count` in
/// `1..=`[`MAX_SAMPLES`], `sigma` finite in `[0, `[`MAX_SIGMA`]`]`; and every generated value
/// must be finite (in-box parameters can still overflow, e.g. `cz = 1.5, n = 10000`).
/// The data are identical to `synthetic(params, count, sigma, seed)`.
pub fn try_synthetic(
    params: &BrdfParams,
    count: usize,
    sigma: f64,
    seed: u64,
) -> Result<DataSet, ParamError> {
    params.validate()?;
    if !(1..=MAX_SAMPLES).contains(&count) {
        return Err(ParamError::SampleCount { count });
    }
    if !(sigma.is_finite() && (0.0..=MAX_SIGMA).contains(&sigma)) {
        return Err(ParamError::Sigma { sigma });
    }
    let d = synthetic(params, count, sigma, seed);
    if let Some(i) = d.value.iter().position(|y| !y.is_finite()) {
        return Err(ParamError::NonFiniteValue {
            index: i,
            value: d.value[i],
        });
    }
    Ok(d)
}

/// Which samples a reader drops. A sample is counted under the first reason that applies, in
/// the order: not finite, below the horizon, negative, above the maximum.
///
/// **One data policy:** [`Filters::default`] is the policy for every command and reader:
/// drop non-finite samples and samples below the horizon, keep negative values (noisy data,
/// e.g. a synthetic instance with noise written to CSV, legitimately has them; dropping them
/// biases the fit upward) and set no maximum. [`Filters::paper`] is the paper's filtering of
/// the measured Cornell data; [`Filters::none`] keeps everything (non-finite values included:
/// the caller then asked for them).
#[derive(Clone, Debug, PartialEq)]
pub struct Filters {
    /// Drop values strictly above this (the paper dropped values > 1). `None`: keep all.
    pub max_value: Option<f64>,
    /// Drop negative values (default: false, keep them).
    pub drop_negative: bool,
    /// Drop NaN and infinite values (and non-finite direction components) (default: true).
    pub drop_non_finite: bool,
    /// Drop samples whose incident or exitant direction has `z < 0`, and MERL entries marked
    /// below the horizon (negative) (default: true).
    pub drop_below_horizon: bool,
}

impl Default for Filters {
    /// The one default policy: drops non-finite and below-horizon samples, keeps negative
    /// values, no maximum.
    fn default() -> Self {
        Filters {
            max_value: None,
            drop_negative: false,
            drop_non_finite: true,
            drop_below_horizon: true,
        }
    }
}

impl Filters {
    /// The paper's filtering of measured data: the default plus dropping negative values and
    /// values above 1.
    pub fn paper() -> Self {
        Filters {
            max_value: Some(1.0),
            drop_negative: true,
            ..Filters::default()
        }
    }

    /// Keeps nothing out: every sample passes (also NaN and infinite ones).
    pub fn none() -> Self {
        Filters {
            max_value: None,
            drop_negative: false,
            drop_non_finite: false,
            drop_below_horizon: false,
        }
    }

    /// Classifies one sample, updating `report`; returns true when it is kept.
    pub fn admit(&self, u: [f64; 3], v: [f64; 3], value: f64, report: &mut FilterReport) -> bool {
        self.admit_marked(u, v, value, false, report)
    }

    /// [`Filters::admit`] for a sample that the source itself may mark as below the horizon
    /// (MERL's negative entries): `below_mark` counts as a direction below the horizon.
    pub(crate) fn admit_marked(
        &self,
        u: [f64; 3],
        v: [f64; 3],
        value: f64,
        below_mark: bool,
        report: &mut FilterReport,
    ) -> bool {
        report.read += 1;
        let finite = value.is_finite() && u.iter().chain(v.iter()).all(|c| c.is_finite());
        if self.drop_non_finite && !finite {
            report.non_finite += 1;
        } else if self.drop_below_horizon && (below_mark || u[2] < 0.0 || v[2] < 0.0) {
            report.below_horizon += 1;
        } else if self.drop_negative && value < 0.0 {
            report.negative += 1;
        } else if self.max_value.is_some_and(|m| value > m) {
            report.above_max += 1;
        } else {
            report.kept += 1;
            return true;
        }
        false
    }

    /// Applies the filters to a data set, returning the kept samples and the account.
    pub fn apply(&self, data: &DataSet) -> (DataSet, FilterReport) {
        let mut rep = FilterReport::default();
        let mut out = DataSet::with_capacity(data.len());
        for i in 0..data.len() {
            if self.admit(data.u(i), data.v(i), data.value[i], &mut rep) {
                out.push(data.u(i), data.v(i), data.value[i]);
            }
        }
        (out, rep)
    }
}

/// What the filters dropped and why.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FilterReport {
    /// Samples read.
    pub read: usize,
    /// Samples kept.
    pub kept: usize,
    /// Dropped: value above the maximum.
    pub above_max: usize,
    /// Dropped: negative value.
    pub negative: usize,
    /// Dropped: NaN or infinite value or direction.
    pub non_finite: usize,
    /// Dropped: a direction below the horizon.
    pub below_horizon: usize,
}

impl FilterReport {
    /// Total dropped.
    pub fn dropped(&self) -> usize {
        self.above_max + self.negative + self.non_finite + self.below_horizon
    }
}

impl std::fmt::Display for FilterReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "read {}, kept {}, dropped {} (above max {}, negative {}, non-finite {}, below horizon {})",
            self.read,
            self.kept,
            self.dropped(),
            self.above_max,
            self.negative,
            self.non_finite,
            self.below_horizon
        )
    }
}

/// Draws subsamples of `k` distinct row indices out of `n` without replacement, by a partial
/// Fisher-Yates shuffle of a permutation kept between draws: no allocation per draw.
#[derive(Clone, Debug)]
pub struct Subsampler {
    perm: Vec<u32>,
}

impl Subsampler {
    /// A subsampler over rows `0..n` (`n` must fit in `u32`; larger `n` is truncated).
    pub fn new(n: usize) -> Self {
        let n = n.min(u32::MAX as usize) as u32;
        Subsampler {
            perm: (0..n).collect(),
        }
    }

    /// Number of rows drawn from.
    pub fn population(&self) -> usize {
        self.perm.len()
    }

    /// `min(k, n)` distinct indices, uniformly among all subsets, in random order. The slice
    /// borrows an internal buffer that the next draw overwrites. (The permutation is not
    /// reset: Fisher-Yates steps applied to any permutation still give uniform subsets.)
    pub fn draw<R: Rng + ?Sized>(&mut self, k: usize, rng: &mut R) -> &[u32] {
        let n = self.perm.len();
        let k = k.min(n);
        for i in 0..k {
            let j = rng.random_range(i..n);
            self.perm.swap(i, j);
        }
        &self.perm[..k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::named_params;

    #[test]
    fn product_columns_follow_every_way_of_building_a_data_set() {
        let a = synthetic(&named_params("cross").unwrap(), 300, 0.1, 3);
        let cols = [
            a.ux.clone(),
            a.uy.clone(),
            a.uz.clone(),
            a.vx.clone(),
            a.vy.clone(),
            a.vz.clone(),
            a.value.clone(),
        ];
        let b = DataSet::from_columns(cols).unwrap();
        assert_eq!(a, b);
        let mut c = b.clone();
        c.clear();
        let rows: Vec<u32> = (0..300).rev().collect();
        a.gather_into(&rows, &mut c);
        for (j, i) in (0..300).rev().enumerate() {
            let (u, v) = (a.u(i), a.v(i));
            assert_eq!(c.pxx[j], u[0] * v[0]);
            assert_eq!(c.pyy[j], u[1] * v[1]);
            assert_eq!(c.pxy[j], u[0].mul_add(v[1], u[1] * v[0]));
            assert_eq!(c.pzz[j], u[2] * v[2]);
        }
        assert_eq!(c.pxx.len(), c.len());
    }

    /// Every column follows the rows (repeats kept, out-of-range rows skipped in all columns
    /// alike), and the gathered set gets a new stamp each time, so kept powers are never
    /// reused across two gathers.
    #[test]
    fn gather_copies_every_column_and_skips_rows_out_of_range() {
        let a = synthetic(&named_params("cross").unwrap(), 50, 0.1, 5);
        let rows = [7u32, 49, 7, 50, 0, u32::MAX, 23];
        let mut sub = DataSet::default();
        a.gather_into(&rows, &mut sub);
        let first_stamp = sub.stamp;
        let kept = [7usize, 49, 7, 0, 23];
        assert_eq!(sub.len(), kept.len());
        for (j, &i) in kept.iter().enumerate() {
            assert_eq!(
                (sub.u(j), sub.v(j), sub.value[j]),
                (a.u(i), a.v(i), a.value[i])
            );
            let got = [sub.pxx[j], sub.pyy[j], sub.pxy[j], sub.pzz[j]];
            assert_eq!(got, [a.pxx[i], a.pyy[i], a.pxy[i], a.pzz[i]]);
        }
        for c in [&sub.pxx, &sub.pyy, &sub.pxy, &sub.pzz, &sub.value] {
            assert_eq!(c.len(), kept.len());
        }
        a.gather_into(&rows, &mut sub);
        assert_ne!(sub.stamp, first_stamp);
    }

    #[test]
    fn synthetic_is_seeded_and_uniform() {
        let p = named_params("tuning").unwrap();
        let a = synthetic(&p, 20000, 0.1, 7);
        assert_eq!(a, synthetic(&p, 20000, 0.1, 7));
        assert_ne!(a, synthetic(&p, 20000, 0.1, 8));
        // cos theta is uniform in [0, 1]: mean 1/2, and the noise has the asked sigma.
        let mean_z = a.u_z().iter().sum::<f64>() / a.len() as f64;
        assert!((mean_z - 0.5).abs() < 0.01, "{mean_z}");
        let rmse = a.rmse_of(&p);
        assert!((rmse - 0.1).abs() < 0.003, "{rmse}");
        let clean = synthetic(&p, 100, 0.0, 7);
        assert_eq!(clean.rmse_of(&p), 0.0);
        for i in 0..a.len() {
            let u = a.u(i);
            assert!(u[2] >= 0.0 && ((u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn filters_count_reasons() {
        let mut d = DataSet::new();
        let up = [0.0, 0.0, 1.0];
        d.push(up, up, 0.5);
        d.push(up, up, 2.0);
        d.push(up, up, -0.1);
        d.push(up, up, f64::NAN);
        d.push(up, [0.0, 0.6, -0.8], 0.3);
        d.push(up, up, f64::INFINITY);
        let (kept, rep) = Filters::paper().apply(&d);
        assert_eq!(kept.len(), 1);
        assert_eq!(
            rep,
            FilterReport {
                read: 6,
                kept: 1,
                above_max: 1,
                negative: 1,
                non_finite: 2,
                below_horizon: 1
            }
        );
        assert_eq!(rep.dropped(), 5);
        assert!(rep.to_string().contains("below horizon 1"));
        assert_eq!(Filters::none().apply(&d).0.len(), 6);
    }

    #[test]
    fn subsampler_draws_distinct_rows_without_allocating() {
        let mut s = Subsampler::new(100);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let mut counts = [0usize; 100];
        let ptr = s.perm.as_ptr();
        for _ in 0..2000 {
            let rows = s.draw(10, &mut rng);
            let mut seen = [false; 100];
            for &r in rows {
                assert!(!seen[r as usize]);
                seen[r as usize] = true;
                counts[r as usize] += 1;
            }
        }
        assert_eq!(ptr, s.perm.as_ptr());
        // Each row is drawn with probability 1/10: 200 expected per row.
        assert!(
            counts.iter().all(|&c| (120..290).contains(&c)),
            "{counts:?}"
        );
        assert_eq!(s.draw(1000, &mut rng).len(), 100);

        let p = named_params("tuning").unwrap();
        let d = synthetic(&p, 50, 0.0, 1);
        let mut out = DataSet::with_capacity(10);
        let cap = out.value.capacity();
        d.gather_into(&[3, 1, 4, 99], &mut out);
        assert_eq!(out.len(), 3);
        assert_eq!(out.u(0), d.u(3));
        assert_eq!(out.value(2), d.value(4));
        assert_eq!(out.value.capacity(), cap);

        let cols = [
            d.u_x().to_vec(),
            d.u_y().to_vec(),
            d.u_z().to_vec(),
            d.v_x().to_vec(),
            d.v_y().to_vec(),
            d.v_z().to_vec(),
            d.values().to_vec(),
        ];
        assert_eq!(DataSet::from_columns(cols.clone()), Some(d.clone()));
        let mut bad = cols;
        bad[6].pop();
        assert_eq!(DataSet::from_columns(bad), None);
    }
}
