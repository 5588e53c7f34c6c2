//! Size limits of a spec, checked before anything is allocated or generated. Each is far above
//! what the paper's experiments need and well below what would exhaust a 24 GiB machine or hang
//! `check`; errors quote them.

/// Samples of a synthetic instance (a data set holds 7 numbers of 8 bytes per sample).
pub const MAX_SAMPLES: usize = brdf_model::MAX_SAMPLES;

/// CPU-time cutoff of one trial, in seconds (115 days: beyond it a cutoff is a typo, and a
/// plan's work estimate overflows into nonsense).
pub const MAX_CPU_SECONDS: f64 = 1e7;

/// Lobes of a model.
pub const MAX_LOBES: usize = 64;

/// Samples x free parameters: the full-data Jacobian each worker thread holds (8 bytes each,
/// so 1.6 GB at this limit).
pub const MAX_SAMPLE_PARAMS: usize = 200_000_000;

/// Values of one swept key (a list, or a range's `steps`).
pub const MAX_SWEEP_STEPS: usize = 10_000;

/// Configurations of a spec after sweep expansion.
pub const MAX_CONFIGURATIONS: usize = 10_000;

/// Trials of the whole plan (trials x instances x configurations).
pub const MAX_PLANNED_TRIALS: u64 = 10_000_000;

/// Targets of one instance.
pub const MAX_TARGETS: usize = 1_000;

/// Bootstrap resamples of the ERT intervals.
pub const MAX_BOOTSTRAP: usize = 100_000;

/// Target steps of the error-time and ECDF plots.
pub const MAX_ERROR_STEPS: usize = 10_000;

/// Trials per configuration drawn in the trace plot.
pub const MAX_TRACE_TRIALS: usize = 1_000;

/// Characters of a configuration label (an `[[algorithm]]`'s `label` with its swept values).
/// Specs given to `check` and `run` are held to it; stored specs of existing results are read
/// without it, so older folders stay readable.
pub const MAX_LABEL_CHARS: usize = 1_000;
