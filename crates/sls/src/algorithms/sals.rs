//! SALS, simulated annealing alternated with local search (section 2.3, Figure 6).
//!
//! ```text
//! loop                                            (until target or budget)
//!   s := RandomPick; s := SA(s, first schedule)   (more, hotter temperatures)
//!   repeat
//!     s := N2FB(s)                                (full data or a subsample: `descent_sample_size`)
//!     s := SA(s, later schedule)                  (a short, cooler SA to escape the minimum)
//!   until `stagnation_rounds` rounds in a row without a relative improvement of
//!         STAGNATION_TOLERANCE of the best RMSE since the random pick
//! ```
//!
//! Choices where the paper is ambiguous:
//! - Figure 6's `terminate2` ("no improvement in solution quality for a long time") is counted
//!   in rounds (one descent plus one SA), so that trials stay deterministic; a round improves
//!   when the best full-data RMSE seen after its descent or during its SA falls by a relative
//!   [`STAGNATION_TOLERANCE`].
//! - Figure 6 draws a second random pick right after the first; one pick per restart is made.
//! - The paper does not give its final schedules, only Table 4's ranges. The defaults are
//!   inside them: first SA `T` 0.5 -> 0.05 over 10 temperatures of 40 iterations, later SA
//!   0.05 -> 0.005 over 3 temperatures of 40 iterations, both Metropolis with `r = 1`.
//! - The descent result is evaluated on the full data (free after a full-data descent) before
//!   the SA starts from it.

use crate::algorithms::sa::{Annealer, SaConfig};
use crate::objective::Rows;
use crate::registry::Algorithm;
use crate::search::{DescentLimits, Search, Stop};
use crate::validate::{ConfigError, check_count};
use serde::{Deserialize, Serialize};

/// Relative improvement of the best RMSE since the last random pick that resets the
/// stagnation count of SALS.
pub const STAGNATION_TOLERANCE: f64 = 1e-3;

/// SALS's parameters.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SalsConfig {
    /// The first SA after each random pick (more and hotter temperatures; default 0.5 -> 0.05,
    /// 10 temperatures of 40 iterations). A table given in a configuration replaces the whole
    /// schedule: its missing fields take [`SaConfig`]'s defaults, not these.
    pub first: SaConfig,
    /// The SA after each descent (few, cool temperatures; default 0.05 -> 0.005, 3
    /// temperatures of 40 iterations). Same replacement rule as `first`.
    pub later: SaConfig,
    /// Descent sample size: 0 (the default) for the full data set, else a fresh random
    /// subsample of this many samples per descent.
    pub descent_sample_size: usize,
    /// Per-call iteration limit of the descent (PORT's default 150).
    pub descent_iterations: usize,
    /// Per-call residual-evaluation limit of the descent (PORT's default 200).
    pub descent_evaluations: usize,
    /// Restart after this many rounds (descent + later SA) in a row without improvement.
    pub stagnation_rounds: usize,
}

impl Default for SalsConfig {
    fn default() -> Self {
        Self {
            first: SaConfig {
                t_start: 0.5,
                t_stop: 0.05,
                temperatures: 10,
                iterations: 40,
                ..SaConfig::default()
            },
            later: SaConfig {
                t_start: 0.05,
                t_stop: 0.005,
                temperatures: 3,
                iterations: 40,
                ..SaConfig::default()
            },
            descent_sample_size: 0,
            descent_iterations: 150,
            descent_evaluations: 200,
            stagnation_rounds: 3,
        }
    }
}

impl SalsConfig {
    /// Checks the parameters; the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.first.validate_as("sals.first")?;
        self.later.validate_as("sals.later")?;
        check_count("sals", "descent_iterations", self.descent_iterations, 1)?;
        check_count("sals", "descent_evaluations", self.descent_evaluations, 1)?;
        check_count("sals", "stagnation_rounds", self.stagnation_rounds, 1)
    }

    /// The rows of each descent on `n` samples.
    pub(crate) fn rows(&self, n: usize) -> Rows {
        descent_rows(self.descent_sample_size, n)
    }
}

/// `0` means the full data set; a size at or above `n` too.
pub(crate) fn descent_rows(sample_size: usize, n: usize) -> Rows {
    if sample_size == 0 || sample_size >= n {
        Rows::Full
    } else {
        Rows::Subsample(sample_size)
    }
}

impl Algorithm for SalsConfig {
    const KIND: &'static str = "sals";

    fn validate(&self) -> Result<(), ConfigError> {
        SalsConfig::validate(self)
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        run(self, search)
    }
}

/// Runs SALS.
pub fn run<S: Search + ?Sized>(config: &SalsConfig, search: &mut S) -> Result<(), Stop> {
    let mut annealer = Annealer::new(search);
    let mut s = vec![0.0; search.dim()];
    let rows = config.rows(search.sample_count());
    let limits = DescentLimits {
        iterations: config.descent_iterations,
        evaluations: config.descent_evaluations,
    };
    loop {
        search.count("restarts");
        search.random_pick(&mut s);
        let f = search.evaluate(&s)?;
        let mut best = annealer.anneal(&config.first, search, &mut s, f)?.min(f);
        let mut stale = 0;
        while stale < config.stagnation_rounds {
            search.descend(&mut s, rows, limits)?;
            let f_descent = search.evaluate(&s)?;
            let f_sa = annealer.anneal(&config.later, search, &mut s, f_descent)?;
            let round_best = f_descent.min(f_sa);
            if round_best < best * (1.0 - STAGNATION_TOLERANCE) {
                stale = 0;
            } else {
                stale += 1;
            }
            best = best.min(round_best);
        }
        search.count("stagnation_restarts");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::sa::tests::Bowl;

    #[test]
    fn restarts_after_stagnation_and_stops_on_the_budget() {
        // The bowl's descent jumps to the minimum at once, so every round after the first
        // stagnates: one restart costs 1 + 400 (first SA) + 3 rounds of (1 + 120) evaluations
        // (the evaluation after a descent is at a new point each time on this fake).
        let config = SalsConfig::default();
        let per_restart = 1 + 400 + (config.stagnation_rounds + 1) * (1 + 120);
        let mut b = Bowl::new(2 * per_restart + 5);
        assert_eq!(run(&config, &mut b), Err(Stop::EvaluationBudget));
        // Each restart begins with the random pick (0.9, 1.0).
        assert_eq!(b.evaluated[0], vec![0.9, 1.0]);
        assert_eq!(b.evaluated[per_restart], vec![0.9, 1.0]);
        assert_eq!(b.evaluated[2 * per_restart], vec![0.9, 1.0]);
        // After each descent the candidate is the descent's result.
        assert_eq!(b.evaluated[401], vec![0.0, 3.0]);
    }

    #[test]
    fn descent_rows_and_validation() {
        assert_eq!(descent_rows(0, 100), Rows::Full);
        assert_eq!(descent_rows(100, 100), Rows::Full);
        assert_eq!(descent_rows(25, 100), Rows::Subsample(25));
        let mut c = SalsConfig::default();
        assert!(c.validate().is_ok());
        c.later.t_stop = 1.0;
        let e = c.validate().unwrap_err();
        assert_eq!((e.algorithm, e.field), ("sals.later", "t_stop"));
        let c = SalsConfig {
            stagnation_rounds: 0,
            ..SalsConfig::default()
        };
        assert_eq!(c.validate().unwrap_err().field, "stagnation_rounds");
    }
}
