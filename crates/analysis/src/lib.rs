//! The analysis of brdf-sls's results: run-time distribution statistics, the figures and pages
//! of results folders, before-and-after comparisons and exports. It reads what
//! `brdf_experiment` writes and runs no trials.
//!
//! - [`analysis`]: one analysis of a run (statistics, tests, charts' data), computed once
//!   and rendered by the files, the table, the page, `compare` and the Python package.
//! - [`stats`]: run-time distributions (Kaplan-Meier), quantiles, ERT with bootstrap, pairwise
//!   tests (Mann-Whitney, KS, log-rank) with Holm's correction, tables.
//! - [`figures`]: RTD, sweep, trace, scatter, error-time and COCO-style ECDF charts built from
//!   the statistics (drawn by `brdf_graphics`).
//! - [`report`]: statistics and plots for a finished (or partial) results directory.
//! - [`export`]: results in IOHprofiler's format (IOHanalyzer, iohinspector).
//! - [`errors`]: which errors are bad input (exit status 2, Python's `InputError`) and which
//!   are failures while running, for the command line and the Python package alike.
//! - [`folder`]: a results folder read whole (records, stored spec, notes) for pages and
//!   comparisons.
//! - [`html`]: self-contained HTML pages: the report of results folders, a comparison, the
//!   stress page, and the blocks the bench page is built from.
//! - [`stress_charts`]: the charts of a stress report (files and page alike).
//! - [`pipeline`]: one run of an experiment as a library call (prepare, execute with the
//!   caller's executor, statistics, plots and the report page), for `brdf-sls run` and
//!   `brdf_sls.run`.
//! - [`compare`]: before and after: matched results of two folders judged faster, slower, not
//!   significantly different or not comparable (and why).
#![warn(missing_docs)]

pub mod analysis;
pub mod compare;
pub mod errors;
pub mod export;
pub mod figures;
pub mod folder;
pub mod html;
pub mod pipeline;
pub mod report;
/// The statistics (the `brdf-stats` crate), under the path they have always had here.
pub use brdf_stats as stats;
pub mod stress_charts;
