//! Data sets (structure of arrays), synthetic instances, filters and subsampling.

use rand::{Rng, RngExt};
use std::io::Write;

/// BRDF samples stored structure-of-arrays: incident direction `u`, exitant direction `v`
/// (unit vectors pointing away from the surface, z = normal) and the measured value. What a
/// model computes from the directions once per data set belongs to the model family
/// ([`crate::Family::prepare`] makes its [`crate::Samples`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DataSet {
    ux: Vec<f64>,
    uy: Vec<f64>,
    uz: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    vz: Vec<f64>,
    value: Vec<f64>,
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
        Some(DataSet {
            ux,
            uy,
            uz,
            vx,
            vy,
            vz,
            value,
        })
    }

    fn columns_mut(&mut self) -> [&mut Vec<f64>; 7] {
        [
            &mut self.ux,
            &mut self.uy,
            &mut self.uz,
            &mut self.vx,
            &mut self.vy,
            &mut self.vz,
            &mut self.value,
        ]
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
    }

    /// Removes all samples, keeping the capacity.
    pub fn clear(&mut self) {
        for c in self.columns_mut() {
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

    /// Copies the samples `rows` into `out`, replacing its contents and reusing its capacity.
    /// Rows out of range are skipped.
    pub fn gather_into(&self, rows: &[u32], out: &mut DataSet) {
        let n = self.len();
        let kept = || rows.iter().filter(|&&r| (r as usize) < n);
        let from = [
            &self.ux,
            &self.uy,
            &self.uz,
            &self.vx,
            &self.vy,
            &self.vz,
            &self.value,
        ];
        for (dst, src) in out.columns_mut().into_iter().zip(from) {
            dst.clear();
            dst.extend(kept().map(|&r| src[r as usize]));
        }
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

/// Most samples of a data set built by [`try_synthetic`](crate::try_synthetic) or read by the readers in
/// the readers of the `brdf-io` crate: 10,000,000 (about 560 MB of [`DataSet`]).
pub const MAX_SAMPLES: usize = 10_000_000;

/// Largest noise standard deviation [`try_synthetic`](crate::try_synthetic) accepts: 1000 (model values are of
/// order 0.1 to 100; the paper uses 0.1).
pub const MAX_SIGMA: f64 = 1000.0;

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
    pub fn admit_marked(
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

    #[test]
    fn gather_copies_every_column_and_skips_rows_out_of_range() {
        let mut a = DataSet::new();
        for i in 0..50 {
            let t = f64::from(i) * 0.1;
            a.push([t.cos(), t.sin(), 0.5], [0.1 * t, -t, 0.9], t * t);
        }
        let rows = [7u32, 49, 7, 50, 0, u32::MAX, 23];
        let mut sub = DataSet::default();
        a.gather_into(&rows, &mut sub);
        let kept = [7usize, 49, 7, 0, 23];
        assert_eq!(sub.len(), kept.len());
        for (j, &i) in kept.iter().enumerate() {
            assert_eq!(
                (sub.u(j), sub.v(j), sub.value[j]),
                (a.u(i), a.v(i), a.value[i])
            );
        }
        for c in [&sub.ux, &sub.vz, &sub.value] {
            assert_eq!(c.len(), kept.len());
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
        let mut rng = <rand_pcg::Pcg64Mcg as rand::SeedableRng>::seed_from_u64(3);
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

        let mut d = DataSet::new();
        for i in 0..50 {
            let t = f64::from(i) * 0.05;
            d.push([t.sin(), 0.2, t.cos()], [-0.3, t.cos(), t.sin()], t);
        }
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
