//! What each lobe of a parameter set does on a data set: how many samples it covers and whether
//! it is dead. `fit` says when a lobe is dead, and `check` says how many samples the best-known
//! fit's lobes cover.
//!
//! A lobe's *contribution* at a sample is the model's value with the shared terms and that lobe
//! alone minus its value with the shared terms alone (the family's scalar reference), so it is
//! the lobe's own term for every family that sums its lobes.
//!
//! - A lobe is **dead** when its contribution is at most [`DEAD_LOBE`] times the RMS of the data
//!   values on every sample: removing it changes no residual by more than a millionth of the
//!   data's scale, so the fit has one lobe fewer than asked (a search left it where `d <= 0`
//!   everywhere, or where `d^n` underflows).
//! - A lobe **covers** a sample when its contribution there is at least [`COVER`] of its
//!   largest contribution: its footprint, which for a sharp lobe may be a few samples only.

use brdf_model::{DataSet, Params};

/// A lobe whose contribution is at most this fraction of the RMS of the data values on every
/// sample is dead.
pub const DEAD_LOBE: f64 = 1e-6;

/// A lobe covers a sample where its contribution is at least this fraction of its largest.
pub const COVER: f64 = 0.01;

/// What one lobe does on a data set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeUse {
    /// The largest absolute contribution over the samples.
    pub largest: f64,
    /// Samples where the contribution is at least [`COVER`] of `largest` (0 when `largest` is
    /// 0).
    pub covered: usize,
    /// The contribution is at most [`DEAD_LOBE`] times the RMS of the data values everywhere.
    pub dead: bool,
}

/// Each lobe's use of `data` under `params` (in lobe order).
pub fn lobe_use(params: &Params, data: &DataSet) -> Vec<LobeUse> {
    let family = params.family();
    let shared = params.shared();
    let m = data.len();
    let base: Vec<f64> = (0..m)
        .map(|i| family.value(shared, &[], data.u(i), data.v(i)))
        .collect();
    let rms = if m == 0 {
        0.0
    } else {
        (data.values().iter().map(|y| y * y).sum::<f64>() / m as f64).sqrt()
    };
    params
        .lobes()
        .iter()
        .map(|lobe| {
            let one = std::slice::from_ref(lobe);
            let contribution: Vec<f64> = (0..m)
                .map(|i| (family.value(shared, one, data.u(i), data.v(i)) - base[i]).abs())
                .collect();
            // NaN (an overflowing lobe) counts as large: such a lobe is not dead.
            let largest =
                contribution.iter().fold(
                    0.0f64,
                    |a, &c| if c.is_nan() { f64::INFINITY } else { a.max(c) },
                );
            let covered = if largest > 0.0 {
                contribution
                    .iter()
                    .filter(|&&c| c.is_nan() || c >= COVER * largest)
                    .count()
            } else {
                0
            };
            LobeUse {
                largest,
                covered,
                dead: largest <= DEAD_LOBE * rms,
            }
        })
        .collect()
}

/// `lobe1 on 2 of 3000 samples, lobe2 dead`: what `fit` and `check` print.
pub fn describe(uses: &[LobeUse], samples: usize) -> String {
    uses.iter()
        .enumerate()
        .map(|(k, l)| {
            if l.dead {
                format!("lobe{} dead", k + 1)
            } else {
                format!("lobe{} on {} of {samples} samples", k + 1, l.covered)
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_model::{BrdfParams, Lobe, synthetic};

    fn params(lobes: Vec<Lobe>) -> Params {
        BrdfParams { kd: 0.1, lobes }.into()
    }

    /// A lobe with `cz = -1.5` and small `cx`, `cy` has `d < 0` on every sample of the upper
    /// hemisphere: dead. A lobe whose `d^n` underflows is dead too; a lobe worth a millionth of
    /// the data's scale somewhere is not.
    #[test]
    fn dead_lobes_contribute_nothing_anywhere() {
        let truth = params(vec![Lobe::isotropic(-1.0, 1.0, 20.0)]);
        let data = synthetic(&truth, 2000, 0.0, 1);
        let fitted = params(vec![
            Lobe::isotropic(-1.0, 1.0, 20.0),
            Lobe::isotropic(0.2, -1.5, 30.0),
            Lobe::isotropic(0.5, 0.5, 9000.0),
        ]);
        let used = lobe_use(&fitted, &data);
        assert!(!used[0].dead && used[0].covered > 100, "{used:?}");
        assert!(
            used[1].dead && used[1].largest == 0.0 && used[1].covered == 0,
            "{used:?}"
        );
        assert!(used[2].dead && used[2].largest < 1e-100, "{used:?}");
        // Dead is relative to the data's scale: a lobe at a millionth of it is on the edge.
        let rms = (data.values().iter().map(|y| y * y).sum::<f64>() / data.len() as f64).sqrt();
        assert!(used[0].largest > 1e3 * DEAD_LOBE * rms);
    }

    /// A sharp lobe covers few samples: its footprint is where it reaches 1% of its peak.
    #[test]
    fn a_sharp_lobe_covers_few_samples() {
        let sharp = params(vec![Lobe::isotropic(-1.0, 1.0, 5000.0)]);
        let broad = params(vec![Lobe::isotropic(-1.0, 1.0, 5.0)]);
        let data = synthetic(&broad, 3000, 0.0, 2);
        let s = lobe_use(&sharp, &data)[0];
        let b = lobe_use(&broad, &data)[0];
        assert!(!s.dead && s.covered < 30, "{s:?}");
        assert!(b.covered > 1000, "{b:?}");
    }
}
