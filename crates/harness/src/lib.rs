//! The brdf-sls experiment harness: TOML experiment specs, parallel seeded trials, a
//! crash-safe results store, run-time distribution statistics and plots.
//!
//! - [`spec`]: the experiment format (documented there), sweep expansion, the trial plan.
//! - [`seed`]: stable per-trial seeds and spec fingerprints.
//! - [`store`]: `trials.jsonl` (append per line, resume, torn-line recovery, refusal of a
//!   different spec) and atomic writes of derived files.
//! - [`run`]: the parallel runner (rayon), data sets built once and shared.
//! - [`stats`]: success rates, quantiles, ERT with bootstrap, Mann-Whitney, KS, Holm, KM.
//! - [`plot`]: RTD, sweep, trace, scatter, error-time and COCO-style ECDF plots (PNG + SVG).
//! - [`report`]: statistics and plots for a finished (or partial) results directory.
//! - [`progress`]: progress bars or plain progress lines.
//! - [`machine`]: CPU model and thread count recorded with results.
//! - [`instance`]: building an experiment's data sets and layouts.
//! - [`render`]: the small CPU renderer of a lit flat surface (`brdf-sls render`, Figures 8, 12).
//! - [`polar`]: polar plots in the plane of incidence (`brdf-sls polar`, Figure 18).

pub mod instance;
pub mod machine;
pub mod plot;
pub mod polar;
pub mod progress;
pub mod render;
pub mod report;
pub mod run;
pub mod seed;
pub mod spec;
pub mod stats;
pub mod store;
