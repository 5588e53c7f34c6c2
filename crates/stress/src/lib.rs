//! Numerical-stability stress testing for brdf-sls.
//!
//! [`run`] executes three sections and returns a [`StressReport`] whose [`StressReport::passed`]
//! says whether every check held (the `stress` command exits non-zero otherwise):
//! 1. [`kernels`]: every evaluation kernel the CPU runs against a double-double reference
//!    ([`dd`], [`reference`](mod@reference)) over the whole Table 1 box, its edges and the overflow boundary:
//!    value errors in ulps, Jacobian column errors, NaN/inf and overflow-flag mismatches;
//!    and [`families`]: every other model family against a double-double reference of its
//!    own formula.
//! 2. [`suite`]: the solver on problems with known answers: NIST StRD ([`nist`]), the
//!    Moré-Garbow-Hillstrom hook, and hostile BRDF fits.
//! 3. [`diagnose`](mod@diagnose): diagnostics of a fit (singular values, standard errors, correlations,
//!    identifiability warnings, bootstrap intervals, sensitivity to perturbed data), also
//!    usable on its own (`fit --diagnose`).
//!
//! [`StressReport::from_json`] reads a report back ([`json`]: `null` numbers as NaN).
//!
//! Every random draw comes from a seed derived from [`StressOptions::seed`] ([`derive_seed`]),
//! so a report can be reproduced exactly.

#![warn(missing_docs)]

pub mod dd;
pub mod diagnose;
pub mod families;
pub mod json;
pub mod kernels;
pub mod nist;
pub mod reference;
pub mod report;
pub mod suite;
mod svd;

pub use diagnose::{DiagnoseOptions, Diagnosis, diagnose};
pub use report::{Check, NamedDiagnosis, Sizes, StressReport};

use brdf_model::DataSet;

/// Errors of a stress run.
#[derive(Debug, thiserror::Error)]
pub enum StressError {
    /// The thread pool could not be built.
    #[error("thread pool: {0}")]
    ThreadPool(String),
    /// A layout could not be built.
    #[error("layout: {0}")]
    Layout(#[from] brdf_model::ModelError),
    /// A solve could not start.
    #[error("solver: {0}")]
    Solve(#[from] bounded_lm::SolveError),
    /// Input that cannot be diagnosed (empty data, wrong vector length, ...).
    #[error("invalid input: {0}")]
    Invalid(String),
    /// Writing the report failed.
    #[error("writing {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The error.
        source: std::io::Error,
    },
}

/// A data set with the name it is reported under.
#[derive(Clone, Debug)]
pub struct NamedData {
    /// Name used in the report (e.g. the file name).
    pub name: String,
    /// The samples (already read and filtered by the caller).
    pub data: DataSet,
}

/// What [`run`] does.
#[derive(Clone, Debug)]
pub struct StressOptions {
    /// Smaller sample counts (under 60 s on 2 cores in release mode).
    pub quick: bool,
    /// Measured data sets: their directions join the kernel sweep and each is fitted and
    /// diagnosed in section 3.
    pub data: Vec<NamedData>,
    /// Master seed; every draw derives from it.
    pub seed: u64,
    /// Worker threads (`None`: rayon's default, all CPUs).
    pub threads: Option<usize>,
    /// Overrides the sizes that `quick` selects (for tests and custom runs).
    pub sizes: Option<Sizes>,
    /// Called with one line after each check group (kernels; the NIST, MGH and BRDF solver
    /// groups; diagnostics) with its time and the time elapsed, so a long run is not silent.
    pub progress: Option<fn(&str)>,
}

impl Default for StressOptions {
    fn default() -> Self {
        StressOptions {
            quick: true,
            data: Vec::new(),
            seed: 1,
            threads: None,
            sizes: None,
            progress: None,
        }
    }
}

/// Runs all three sections in a thread pool of `options.threads` threads.
pub fn run(options: &StressOptions) -> Result<StressReport, StressError> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(t) = options.threads {
        builder = builder.num_threads(t.max(1));
    }
    let pool = builder
        .build()
        .map_err(|e| StressError::ThreadPool(e.to_string()))?;
    pool.install(|| report::run_all(options))
}

/// A seed for stream `tag`, item `index`, derived from `seed` by SplitMix64 so that nearby
/// inputs give unrelated seeds.
pub fn derive_seed(seed: u64, tag: u64, index: u64) -> u64 {
    let mut z = seed
        .wrapping_add(tag.wrapping_mul(0x9E37_79B9_7F4A_7C15))
        .wrapping_add(index.wrapping_mul(0xD1B5_4A32_D192_ED03));
    for _ in 0..2 {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
    }
    z
}

/// The `q` quantile (0..=1) of `v` (sorted in place; NaN-free input), by statrs' order
/// statistics; 0 for an empty slice.
pub fn percentile(v: &mut [f64], q: f64) -> f64 {
    use statrs::statistics::{Data, OrderStatistics};
    if v.is_empty() {
        return 0.0;
    }
    let mut d = Data::new(v);
    d.quantile(q)
}
