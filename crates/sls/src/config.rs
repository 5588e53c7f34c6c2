//! Algorithm selection: [`AlgorithmConfig`], deserialised from the harness's TOML/JSON with
//! `kind = "aed"` etc. (validation errors are [`ConfigError`], defined in `validate.rs`).

use crate::algorithms::{
    AedConfig, AersConfig, AsaConfig, AvgConfig, DsConfig, RplsConfig, SaConfig, SalsConfig,
};
use crate::search::{Search, Stop};
use crate::validate::ConfigError;
use serde::{Deserialize, Serialize};

/// Which algorithm a trial runs, with its parameters. Serialised with a `kind` tag:
/// `{"kind": "aed", "phi": 1.4}`; missing fields take the paper's defaults, unknown fields are
/// rejected.
///
/// To add an algorithm: a file under `src/algorithms/` with its config struct (`validate`,
/// defaults) and `run`, one variant here and one arm in each `match` of this file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum AlgorithmConfig {
    /// Adaptive Evaluation with Decreasing subsample size (section 2.1, Figure 3).
    Aed(AedConfig),
    /// Adaptive Evaluation with Restarts: AED without the decrease (section 2.2).
    Aers(AersConfig),
    /// Random Picking with Local Search: random pick, descent on the full data set, repeat.
    Rpls(RplsConfig),
    /// Downhill simplex (Nelder-Mead, Numerical Recipes' amoeba) with restarts (section 2.5).
    Ds(DsConfig),
    /// The paper's basic simulated annealing on its own, restarted from random picks
    /// (section 2.3, Figures 4 and 5).
    Sa(SaConfig),
    /// Simulated annealing alternated with descents (section 2.3, Figure 6).
    Sals(SalsConfig),
    /// Averaging simulated annealing and descent results (section 2.4, Figure 7).
    Avg(AvgConfig),
    /// Ingber's Adaptive Simulated Annealing (section 3.1.3).
    Asa(AsaConfig),
}

impl AlgorithmConfig {
    /// Checks every parameter; the error names the offending field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        match self {
            AlgorithmConfig::Aed(c) => c.validate(),
            AlgorithmConfig::Aers(c) => c.validate(),
            AlgorithmConfig::Rpls(c) => c.validate(),
            AlgorithmConfig::Ds(c) => c.validate(),
            AlgorithmConfig::Sa(c) => c.validate(),
            AlgorithmConfig::Sals(c) => c.validate(),
            AlgorithmConfig::Avg(c) => c.validate(),
            AlgorithmConfig::Asa(c) => c.validate(),
        }
    }

    /// The `kind` tag: `"aed"`, `"aers"`, `"rpls"`, `"ds"`, `"sa"`, `"sals"`, `"avg"`, `"asa"`.
    pub fn kind_name(&self) -> &'static str {
        match self {
            AlgorithmConfig::Aed(_) => "aed",
            AlgorithmConfig::Aers(_) => "aers",
            AlgorithmConfig::Rpls(_) => "rpls",
            AlgorithmConfig::Ds(_) => "ds",
            AlgorithmConfig::Sa(_) => "sa",
            AlgorithmConfig::Sals(_) => "sals",
            AlgorithmConfig::Avg(_) => "avg",
            AlgorithmConfig::Asa(_) => "asa",
        }
    }

    /// The default configuration of the algorithm named `kind`, if there is one.
    pub fn default_for(kind: &str) -> Option<Self> {
        Some(match kind {
            "aed" => AlgorithmConfig::Aed(AedConfig::default()),
            "aers" => AlgorithmConfig::Aers(AersConfig::default()),
            "rpls" => AlgorithmConfig::Rpls(RplsConfig::default()),
            "ds" => AlgorithmConfig::Ds(DsConfig::default()),
            "sa" => AlgorithmConfig::Sa(SaConfig::default()),
            "sals" => AlgorithmConfig::Sals(SalsConfig::default()),
            "avg" => AlgorithmConfig::Avg(AvgConfig::default()),
            "asa" => AlgorithmConfig::Asa(AsaConfig::default()),
            _ => return None,
        })
    }

    /// Runs the algorithm until it stops (`Err`) or finishes by itself (`Ok`).
    pub fn run<S: Search>(&self, search: &mut S) -> Result<(), Stop> {
        match self {
            AlgorithmConfig::Aed(c) => crate::algorithms::aed::run(c, search),
            AlgorithmConfig::Aers(c) => crate::algorithms::aers::run(c, search),
            AlgorithmConfig::Rpls(c) => crate::algorithms::rpls::run(c, search),
            AlgorithmConfig::Ds(c) => crate::algorithms::ds::run(c, search),
            AlgorithmConfig::Sa(c) => crate::algorithms::sa::run(c, search),
            AlgorithmConfig::Sals(c) => crate::algorithms::sals::run(c, search),
            AlgorithmConfig::Avg(c) => crate::algorithms::avg::run(c, search),
            AlgorithmConfig::Asa(c) => crate::algorithms::asa::run(c, search),
        }
    }
}
