//! AERS, Adaptive Evaluation with Restarts (section 2.2): AED without the decrease.
//!
//! Identical to AED (same restart loop, same growth of the subsample by `phi` on an iteration
//! limit) except that a descent that fails to stop on its iteration limit restarts the search at
//! once. The tuned `phi = 1.0` (section 3.1.2) keeps the subsample at `rho0`: AERS is then random
//! picking followed by descents on fresh `rho0`-subsamples for as long as they keep hitting the
//! iteration limit.

use super::aed::{AdaptiveEvaluation, DEFAULT_DESCENT_ITERATIONS, DEFAULT_STALL_LIMIT, OnFailure};
use crate::registry::Algorithm;
use crate::search::{DescentLimits, Search, Stop};
use crate::validate::{ConfigError, check_at_least, check_count};
use serde::{Deserialize, Serialize};

/// AERS's parameters (defaults from section 3.1.2: `phi = 1.0`, `rho0 = 25`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct AersConfig {
    /// Growth of the subsample size after an iteration limit (`phi >= 1`).
    pub phi: f64,
    /// Initial subsample size (`rho0 >= 1`).
    pub rho0: usize,
    /// Per-call iteration limit of the descent.
    pub descent_iterations: usize,
    /// Per-call residual-evaluation limit of the descent (PORT's default 200).
    pub descent_evaluations: usize,
    /// Restart after this many consecutive descents without a relative improvement of
    /// [`super::aed::STALL_TOLERANCE`] of the candidate's full-data RMSE (0: never, as in the paper; see
    /// AED).
    pub stall_limit: usize,
}

impl Default for AersConfig {
    fn default() -> Self {
        Self {
            phi: 1.0,
            rho0: 25,
            descent_iterations: DEFAULT_DESCENT_ITERATIONS,
            descent_evaluations: 200,
            stall_limit: DEFAULT_STALL_LIMIT,
        }
    }
}

impl AersConfig {
    /// Checks the parameters; the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_at_least("aers", "phi", self.phi, 1.0)?;
        check_count("aers", "rho0", self.rho0, 1)?;
        check_count("aers", "descent_iterations", self.descent_iterations, 1)?;
        check_count("aers", "descent_evaluations", self.descent_evaluations, 1)
    }
}

impl Algorithm for AersConfig {
    const KIND: &'static str = "aers";

    fn validate(&self) -> Result<(), ConfigError> {
        AersConfig::validate(self)
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        run(self, search)
    }
}

/// Runs AERS.
pub fn run<S: Search + ?Sized>(config: &AersConfig, search: &mut S) -> Result<(), Stop> {
    AdaptiveEvaluation {
        phi: config.phi,
        rho0: config.rho0,
        limits: DescentLimits {
            iterations: config.descent_iterations,
            evaluations: config.descent_evaluations,
        },
        on_failure: OnFailure::Restart,
        stall_limit: config.stall_limit,
    }
    .run(search)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rows;
    use crate::algorithms::script::Script;
    use bounded_lm::Outcome::{IterationLimit as It, SingularConvergence as Sc};

    #[test]
    fn failure_restarts_and_phi_one_keeps_rho0() {
        let mut script = Script::new(1000, vec![Sc, It, It, It, Sc, It, Sc]);
        assert_eq!(
            run(&AersConfig::default(), &mut script),
            Err(Stop::EvaluationBudget)
        );
        // pick 1 fails, pick 2 promising; two accepted descents at rho0 (phi = 1); a failure
        // restarts: pick 3 promising, then a failure restarts again.
        assert!(script.rows.iter().all(|&r| r == Rows::Subsample(25)));
        assert_eq!(script.rows.len(), 7);
        assert_eq!(script.picks, 4);
    }

    #[test]
    fn validate_names_the_field() {
        let bad = AersConfig {
            rho0: 0,
            ..AersConfig::default()
        };
        assert_eq!(bad.validate().unwrap_err().field, "rho0");
    }
}
