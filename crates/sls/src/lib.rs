//! Stochastic local search for bounded least-squares fitting (BRDF fitting in particular).
//!
//! The algorithms of Backer, Kimberley and Skrypnyk, "Stochastic Local Search for BRDF
//! Parameterization" (AED, AERS, RPLS, SALS, AVG, DS, ASA) run over a generic [`Objective`]. A
//! trial (one seeded run of one algorithm until a target RMSE or a budget) is the unit the
//! harness schedules; its result ([`TrialResult`]) carries the anytime trace from which RTDs for
//! any target can be derived afterwards.
//!
//! Layers:
//! - [`Objective`]: the instance (box, full-data RMSE, least-squares problems over subsamples);
//!   [`BrdfObjective`] implements it for any brdf-model family on a data set.
//! - [`Search`]: what an algorithm may do (random pick, evaluate, descend), implemented by
//!   [`TrialContext`], which counts sample-evaluations, checks the target and the budget, and
//!   keeps the best candidate and the anytime trace.
//! - [`algorithms`]: one file per algorithm, selected by [`AlgorithmConfig`]; [`registry`]
//!   holds the kinds, built-in and user-registered ([`registry::register`]).
//! - [`run_trial`]: one trial, start to finish, on the calling thread.
//!
//! ```
//! use brdf_model::{Layout, LobeKind, named_params, synthetic};
//! use sls::{AlgorithmConfig, Budget, BrdfObjective, StopReason, run_trial};
//! use std::sync::Arc;
//!
//! // 300 noiseless samples of the paper's tuning BRDF (Table 2), one anisotropic lobe.
//! let data = synthetic(&named_params("tuning").unwrap(), 300, 0.0, 1);
//! let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
//! let objective = BrdfObjective::new(Arc::new(data), layout);
//! let aed: AlgorithmConfig = serde_json::from_str(r#"{"kind": "aed"}"#).unwrap();
//! let budget = Budget { cpu_seconds: Some(10.0), sample_evaluations: None };
//! let result = run_trial(&objective, &aed, 42, budget, 0.01);
//! assert_eq!(result.stop, StopReason::Target);
//! let fitted = objective.layout().decode(&result.best_x);
//! assert!((fitted.get("kd").unwrap() - 0.15).abs() < 0.02);
//! ```

#![warn(missing_docs)]

pub mod algorithms;
mod brdf;
mod config;
mod context;
mod descent_model;
mod objective;
pub mod registry;
pub mod schema;
mod search;
pub mod trial;
mod validate;
mod value;

pub use algorithms::{
    AedConfig, AersConfig, AsaConfig, AvgConfig, DsConfig, Perturbation, RplsConfig, SaConfig,
    SalsConfig,
};
pub use brdf::{BrdfObjective, BrdfWorkspace, StartDist};
pub use config::AlgorithmConfig;
pub use context::{
    TrialContext, TrialSettings, run_trial, run_trial_interruptible, run_trial_with,
};
pub use descent_model::DescentModel;
pub use objective::{Objective, Rows};
pub use search::{Descent, DescentEnd, DescentLimits, Search, Stop};
pub use trial::{Budget, BudgetState, EvalCounts, Stamp, StopReason, TracePoint, TrialResult};
pub use validate::ConfigError;

/// The guide docs/own-algorithm.md, whose Rust example runs as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/own-algorithm.md")]
pub struct OwnAlgorithmGuide;

/// The random number generator of a trial, seeded with `SeedableRng::seed_from_u64(seed)`.
pub type SearchRng = rand_pcg::Pcg64Mcg;
