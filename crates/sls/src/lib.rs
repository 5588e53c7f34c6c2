//! Stochastic local search for bounded least-squares fitting (BRDF fitting in particular).
//!
//! The algorithms of Backer, Kimberley and Skrypnyk, "Stochastic Local Search for BRDF
//! Parameterization" (AED, AERS, RPLS, SALS, AVG, DS, ASA) run over a generic [`Objective`]. A
//! trial (one seeded run of one algorithm until a target RMSE or a budget) is the unit the
//! harness schedules; its result ([`TrialResult`]) carries the anytime trace from which RTDs for
//! any target can be derived afterwards.

pub mod trial;

pub use trial::{Budget, EvalCounts, Stamp, StopReason, TracePoint, TrialResult};
