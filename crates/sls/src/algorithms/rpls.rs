//! RPLS, Random Picking with Local Search (section 3): the paper's naive baseline.
//!
//! ```text
//! repeat
//!   s := RandomPick
//!   s := N2FB(full data, s)        (the solver's default limits)
//! until RMSE(full data, s) <= e
//! ```
//!
//! The full-data RMSE after the descent costs nothing: the descent's final f is over the full
//! data set (see [`crate::Search::evaluate`]).

use crate::objective::Rows;
use crate::registry::Algorithm;
use crate::search::{DescentEnd, DescentLimits, Search, Stop};
use crate::validate::{ConfigError, check_count};
use serde::{Deserialize, Serialize};

/// RPLS's parameters: the descent's limits (PORT's defaults).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct RplsConfig {
    /// Iteration limit of each descent (PORT default 150).
    pub descent_iterations: usize,
    /// Residual-evaluation limit of each descent (PORT default 200).
    pub descent_evaluations: usize,
}

impl Default for RplsConfig {
    fn default() -> Self {
        let limits = DescentLimits::default();
        Self {
            descent_iterations: limits.iterations,
            descent_evaluations: limits.evaluations,
        }
    }
}

impl RplsConfig {
    /// Checks the parameters; the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_count("rpls", "descent_iterations", self.descent_iterations, 1)?;
        check_count("rpls", "descent_evaluations", self.descent_evaluations, 1)
    }
}

impl Algorithm for RplsConfig {
    const KIND: &'static str = "rpls";

    fn validate(&self) -> Result<(), ConfigError> {
        RplsConfig::validate(self)
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        run(self, search)
    }
}

/// Runs RPLS.
pub fn run<S: Search + ?Sized>(config: &RplsConfig, search: &mut S) -> Result<(), Stop> {
    let limits = DescentLimits {
        iterations: config.descent_iterations,
        evaluations: config.descent_evaluations,
    };
    let mut s = vec![0.0; search.dim()];
    loop {
        search.random_pick(&mut s);
        let descent = search.descend(&mut s, Rows::Full, limits)?;
        // An unevaluable pick is known to be +inf on the full data already.
        if descent.end != DescentEnd::StartNotEvaluable {
            search.evaluate_below(&s, f64::NEG_INFINITY)?;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::script::Script;
    use bounded_lm::Outcome::{IterationLimit as It, SingularConvergence as Sc};

    #[test]
    fn every_descent_is_on_the_full_data_and_followed_by_an_evaluation() {
        let mut script = Script::new(1000, vec![Sc, It, Sc]);
        assert_eq!(
            run(&RplsConfig::default(), &mut script),
            Err(Stop::EvaluationBudget)
        );
        assert_eq!(script.rows, vec![Rows::Full; 3]);
        assert_eq!(script.picks, 4);
        assert_eq!(script.evaluated, vec![1001.0, 2001.0, 3001.0]);
    }
}
