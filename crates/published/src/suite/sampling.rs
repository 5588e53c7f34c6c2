//! The sampling patterns of suite instances ([`Sampling`]) and their generation with stated,
//! seeded noise ([`Noise`], [`generate`]).
//!
//! Every pattern gives pairs of unit directions `(u, v)` (incident, exitant), both pointing
//! away from the surface, `z` the normal, as everywhere in `brdf-model`.
//!
//! - **`cornell`**: the direction pairs of the Cornell gonioreflectometer measurements in
//!   `experiments/data/krylon_blue.brdf` (and `acryl_blue.brdf`), generated procedurally: 8
//!   incident directions in the plane `phi_i = 0` at `theta_i` = 10, 20, ..., 80 degrees; the
//!   exitant directions on 10 rings equally spaced in the Lambert equal-area radius,
//!   `theta_k = 2 asin(k / (10 sqrt 2))` (0, 8.11, 16.26, ..., 79.05 degrees), ring `k` holding
//!   `8k` azimuths of which the half circle `phi_s` in [-180, 0] degrees is measured (`4k + 1`
//!   azimuths, one for the normal): 190 exitant directions per incident one; the pairs whose
//!   exitant direction lies within [`CORNELL_RETRO_EXCLUSION_DEG`] degrees of the incident one
//!   are left out (there the detector would block the source): 1440 pairs
//!   ([`CORNELL_PAIRS`]). The measured files hold 1439 of them: they also lack
//!   `(80, 79.05, -175)` degrees, 5 degrees from the mirror direction (a test checks the rest
//!   match the file to its 6 decimals).
//! - **`merl`**: the cells of MERL's 90 x 90 x 180 table in the half/difference angles, each at
//!   its centre as `brdf_io::MerlBrdf::sample_grid` places it (`theta_h = ((i + 0.5) / 90)^2
//!   90` degrees on MERL's square-root grid, `theta_d = (j + 0.5)` degrees, `phi_d = (k + 0.5)`
//!   degrees in [0, 180), `phi_h = 0`); of the 1,458,000 cells, the [`MERL_CELLS`] whose two
//!   directions lie above the horizon; a seeded draw of distinct cells. Reciprocity-symmetric:
//!   swapping `u` and `v` turns `phi_d` by 180 degrees, which MERL's table folds onto the same
//!   cell.
//! - **`uniform`**: incident and exitant directions drawn independently and uniformly by solid
//!   angle (`brdf_model::uniform_hemisphere`), as the paper's synthetic instances.
//!
//! A subset of a fixed grid (`cornell` below 1440 pairs, `merl` always) is drawn without
//! replacement from a PCG64-MCG seeded with the instance seed and kept in grid order.

use brdf_model::{DataSet, Params, Reflectance, uniform_hemisphere};
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};

use super::SuiteError;

/// A direction pair `(u, v)`: incident and exitant unit vectors, both pointing away from the
/// surface.
pub type Pair = ([f64; 3], [f64; 3]);

/// Direction pairs of the `cornell` pattern.
pub const CORNELL_PAIRS: usize = 1440;

/// The `cornell` pattern leaves out exitant directions closer than this (degrees) to the
/// incident one: in the measured files the nearest pair kept is 17.04 degrees from
/// retro-reflection and the farthest left out 16.74.
pub const CORNELL_RETRO_EXCLUSION_DEG: f64 = 17.0;

/// Cells of MERL's 90 x 90 x 180 table whose centre directions both lie above the horizon.
pub const MERL_CELLS: usize = 1_096_216;

/// MERL's table dimensions `(theta_h, theta_d, phi_d)`.
const MERL_DIMS: (usize, usize, usize) = (90, 90, 180);

/// Most samples of a `uniform` instance (`brdf_model::MAX_SAMPLES`).
const UNIFORM_MAX: usize = brdf_model::MAX_SAMPLES;

/// A sampling pattern of suite instances (the module documentation gives each one's geometry).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampling {
    /// The Cornell gonioreflectometer's 1440 direction pairs.
    Cornell,
    /// Cells of MERL's half/difference-angle table.
    Merl,
    /// Uniform by solid angle, as the paper's synthetic instances.
    Uniform,
}

impl Sampling {
    /// Every pattern.
    pub const ALL: [Sampling; 3] = [Sampling::Cornell, Sampling::Merl, Sampling::Uniform];

    /// The name in specs: `cornell`, `merl`, `uniform`.
    pub fn name(self) -> &'static str {
        match self {
            Sampling::Cornell => "cornell",
            Sampling::Merl => "merl",
            Sampling::Uniform => "uniform",
        }
    }

    /// The pattern called `name`; an unknown name is an error listing the names.
    pub fn from_name(name: &str) -> Result<Sampling, SuiteError> {
        Sampling::ALL
            .into_iter()
            .find(|s| s.name() == name)
            .ok_or_else(|| SuiteError::UnknownSampling {
                name: name.to_string(),
            })
    }

    /// The sample count when none is given: every Cornell pair, 10,000 otherwise.
    pub fn default_samples(self) -> usize {
        match self {
            Sampling::Cornell => CORNELL_PAIRS,
            Sampling::Merl | Sampling::Uniform => 10_000,
        }
    }

    /// The most samples the pattern has: [`CORNELL_PAIRS`], [`MERL_CELLS`], or
    /// `brdf_model::MAX_SAMPLES` for `uniform`.
    pub fn max_samples(self) -> usize {
        match self {
            Sampling::Cornell => CORNELL_PAIRS,
            Sampling::Merl => MERL_CELLS,
            Sampling::Uniform => UNIFORM_MAX,
        }
    }

    /// One line on the geometry, for listings.
    pub fn summary(self) -> &'static str {
        match self {
            Sampling::Cornell => {
                "the Cornell gonioreflectometer's 1440 pairs: theta_i 10..80 deg in steps of 10, \
                 exitant directions on 10 equal-area rings (half circle), none within 17 deg of \
                 retro-reflection"
            }
            Sampling::Merl => {
                "cell centres of MERL's 90 x 90 x 180 (theta_h, theta_d, phi_d) table, theta_h \
                 on its square-root grid, 1,096,216 cells above the horizon, a seeded draw"
            }
            Sampling::Uniform => {
                "incident and exitant directions uniform by solid angle, drawn independently"
            }
        }
    }

    /// `samples` direction pairs of this pattern drawn with `seed` (see the module
    /// documentation); an error when `samples` is 0 or above [`Sampling::max_samples`].
    pub fn directions(self, samples: usize, seed: u64) -> Result<Vec<Pair>, SuiteError> {
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        self.directions_with(samples, &mut rng)
    }

    fn directions_with(self, samples: usize, rng: &mut Pcg64Mcg) -> Result<Vec<Pair>, SuiteError> {
        if !(1..=self.max_samples()).contains(&samples) {
            return Err(SuiteError::SampleCount {
                sampling: self.name(),
                samples,
                max: self.max_samples(),
            });
        }
        Ok(match self {
            Sampling::Uniform => (0..samples)
                .map(|_| {
                    let u = uniform_hemisphere(rng);
                    (u, uniform_hemisphere(rng))
                })
                .collect(),
            Sampling::Cornell => {
                let grid = cornell_pairs();
                if samples == grid.len() {
                    grid
                } else {
                    let picked = distinct(grid.len(), samples, rng, |_| true);
                    picked.into_iter().map(|i| grid[i]).collect()
                }
            }
            Sampling::Merl => {
                let (a, b, c) = MERL_DIMS;
                distinct(a * b * c, samples, rng, |i| merl_cell(i).is_some())
                    .into_iter()
                    .filter_map(merl_cell)
                    .collect()
            }
        })
    }
}

impl std::fmt::Display for Sampling {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// `count` distinct indices in `0..n` that pass `keep`, in ascending order: the first ones of
/// a random permutation (Fisher-Yates, swaps kept in a map so nothing of size `n` is
/// allocated) that pass, so every subset of the kept indices is equally likely. The caller
/// makes sure `count` kept indices exist.
fn distinct(
    n: usize,
    count: usize,
    rng: &mut Pcg64Mcg,
    keep: impl Fn(usize) -> bool,
) -> Vec<usize> {
    let mut swaps: HashMap<usize, usize> = HashMap::new();
    let mut out = Vec::with_capacity(count);
    for i in 0..n {
        if out.len() == count {
            break;
        }
        let j = rng.random_range(i..n);
        let at_j = swaps.get(&j).copied().unwrap_or(j);
        let at_i = swaps.get(&i).copied().unwrap_or(i);
        swaps.insert(j, at_i);
        if keep(at_j) {
            out.push(at_j);
        }
    }
    out.sort_unstable();
    out
}

/// `[sin t cos p, sin t sin p, cos t]`.
fn dir(theta: f64, phi: f64) -> [f64; 3] {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    [st * cp, st * sp, ct]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Every pair of the `cornell` pattern, in order: incident angle, then ring, then azimuth from
/// -180 degrees.
pub fn cornell_pairs() -> Vec<Pair> {
    let cos_min = CORNELL_RETRO_EXCLUSION_DEG.to_radians().cos();
    let mut out = Vec::with_capacity(CORNELL_PAIRS);
    for i in 1..=8 {
        let u = dir(f64::from(i) * 10f64.to_radians(), 0.0);
        for k in 0..10u32 {
            let theta = 2.0 * (f64::from(k) / (10.0 * 2f64.sqrt())).asin();
            let azimuths = if k == 0 { 1 } else { 4 * k + 1 };
            for j in 0..azimuths {
                let phi = if k == 0 {
                    0.0
                } else {
                    -PI + f64::from(j) * 2.0 * PI / f64::from(8 * k)
                };
                let v = dir(theta, phi);
                if dot(u, v) < cos_min {
                    out.push((u, v));
                }
            }
        }
    }
    out
}

/// The directions at the centre of MERL cell `index` (`phi_d + 180 (theta_d + 90 theta_h)`
/// in cell units, as `brdf_io::MerlBrdf::index`), or `None` when one lies on or below the
/// horizon or the index is past the table.
pub fn merl_cell(index: usize) -> Option<Pair> {
    let (nth, ntd, npd) = MERL_DIMS;
    let (ip, rest) = (index % npd, index / npd);
    let (id, ih) = (rest % ntd, rest / ntd);
    if ih >= nth {
        return None;
    }
    let s = (ih as f64 + 0.5) / nth as f64;
    let theta_h = s * s * FRAC_PI_2;
    let theta_d = (id as f64 + 0.5) / ntd as f64 * FRAC_PI_2;
    let phi_d = (ip as f64 + 0.5) / npd as f64 * PI;
    // The difference vector turned by theta_h about y (the half vector is in the x-z plane).
    let d = dir(theta_d, phi_d);
    let (sh, ch) = theta_h.sin_cos();
    let u = [d[0] * ch + d[2] * sh, d[1], d[2] * ch - d[0] * sh];
    let h = [sh, 0.0, ch];
    let uh = dot(u, h);
    let v = [2.0 * uh * h[0] - u[0], -u[1], 2.0 * uh * h[2] - u[2]];
    (u[2] > 0.0 && v[2] > 0.0).then_some((u, v))
}

/// The noise added to each value `f` of a suite instance: Gaussian with standard deviation
/// `sqrt((relative f)^2 + absolute^2)`, one standard normal draw per sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// Standard deviation relative to each value (`0.01` is 1% of the value); in [0, 10].
    pub relative: f64,
    /// Absolute standard deviation; in [0, `brdf_model::MAX_SIGMA`].
    pub absolute: f64,
}

impl Noise {
    /// Checks both parts are finite and in range.
    pub fn check(&self) -> Result<(), SuiteError> {
        let ok = |v: f64, hi: f64| v.is_finite() && (0.0..=hi).contains(&v);
        if ok(self.relative, 10.0) && ok(self.absolute, brdf_model::MAX_SIGMA) {
            Ok(())
        } else {
            Err(SuiteError::Noise {
                relative: self.relative,
                absolute: self.absolute,
            })
        }
    }
}

/// A suite instance's data: `samples` direction pairs of `sampling`, each valued by `params`'
/// family's scalar reference plus [`Noise`]. Seeded: the directions come first from a
/// PCG64-MCG seeded with `seed`, then one normal draw per sample from the same generator (none
/// when both noise parts are 0), so the directions do not depend on the noise. `params` are
/// not checked against bounds here (the caller knows which bounds apply); every value must be
/// finite.
pub fn generate(
    params: &Params,
    sampling: Sampling,
    samples: usize,
    noise: Noise,
    seed: u64,
) -> Result<DataSet, SuiteError> {
    noise.check()?;
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let dirs = sampling.directions_with(samples, &mut rng)?;
    let mut data = DataSet::with_capacity(dirs.len());
    let noisy = noise.relative != 0.0 || noise.absolute != 0.0;
    for (i, (u, v)) in dirs.into_iter().enumerate() {
        let f = Reflectance::value(params, u, v);
        let mut y = f;
        if noisy {
            let z: f64 = rng.sample(StandardNormal);
            y += z * (noise.relative * f).hypot(noise.absolute);
        }
        if !y.is_finite() {
            return Err(SuiteError::NonFinite { index: i, value: y });
        }
        data.push(u, v, y);
    }
    Ok(data)
}
