//! The best-known RMSE of an instance as recorded with results: a plain record shared by the
//! spec (resolved targets), the results store (header and session lines) and
//! `brdf_best_known`, which computes it. A leaf: it imports nothing of the crate.

use serde::{Deserialize, Serialize};

/// The best-known RMSE of one instance and how it was found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BestKnown {
    /// The lowest full-data RMSE found.
    pub rmse: f64,
    /// The RMSE reached from the generating parameters (synthetic instances only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from_truth: Option<f64>,
    /// Random starts descended from.
    pub starts: usize,
    /// Their seed.
    pub seed: u64,
    /// How the lowest RMSE was obtained: which start led to it (the truth, a random start, the
    /// optimum of a nested layout) and what was tried (absent in records written before it was
    /// recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<String>,
}
