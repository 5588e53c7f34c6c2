//! Synthetic instances: samples of a model at random directions, with optional noise.

use crate::data::{DataSet, MAX_SAMPLES, MAX_SIGMA, uniform_hemisphere};
use crate::params::{ParamError, Reflectance};
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;

/// A synthetic instance as in the paper: `count` samples with incident and exitant directions
/// drawn independently and uniformly by solid angle over the hemisphere, value
/// `f(u, v) + sigma * N(0, 1)` (no noise when `sigma == 0`). Seeded: the same `seed` always
/// gives the same data (PCG64-MCG).
///
/// Unchecked, kept for compatibility: a huge `count` aborts on allocation and bad parameters
/// or `sigma` give NaN or infinite values. Prefer [`try_synthetic`], which gives the same data
/// when its checks pass.
pub fn synthetic(
    params: &(impl Reflectance + ?Sized),
    count: usize,
    sigma: f64,
    seed: u64,
) -> DataSet {
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

/// [`synthetic`] with its inputs checked first: `params` by [`Reflectance::check`] (finite,
/// inside the family's bounds, at most [`crate::MAX_LOBES`] lobes), `count` in
/// `1..=`[`MAX_SAMPLES`], `sigma` finite in `[0, `[`MAX_SIGMA`]`]`; and every generated value
/// must be finite (in-box parameters can still overflow, e.g. `cz = 1.5, n = 10000`).
/// The data are identical to `synthetic(params, count, sigma, seed)`.
pub fn try_synthetic(
    params: &(impl Reflectance + ?Sized),
    count: usize,
    sigma: f64,
    seed: u64,
) -> Result<DataSet, ParamError> {
    params.check()?;
    if !(1..=MAX_SAMPLES).contains(&count) {
        return Err(ParamError::SampleCount { count });
    }
    if !(sigma.is_finite() && (0.0..=MAX_SIGMA).contains(&sigma)) {
        return Err(ParamError::Sigma { sigma });
    }
    let d = synthetic(params, count, sigma, seed);
    if let Some(i) = d.values().iter().position(|y| !y.is_finite()) {
        return Err(ParamError::NonFiniteValue {
            index: i,
            value: d.value(i),
        });
    }
    Ok(d)
}
