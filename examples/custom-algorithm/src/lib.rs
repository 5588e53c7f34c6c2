//! A search algorithm defined outside the brdf-sls workspace, registered so that the brdf-sls
//! harness benchmarks it exactly like a built-in algorithm (`src/main.rs` is the whole
//! command line with it).
//!
//! [`CoordinateSearch`] is a compass search: from a random start it tries a step up and down
//! each coordinate, keeps the first move that lowers the full-data RMSE, halves the step when
//! no move does, and restarts once the step is below `min_step`, optionally polishing each
//! local optimum with a short least-squares descent first. Every evaluation goes through
//! [`sls::Search`], so the harness counts sample-evaluations, enforces the budget, stops at the
//! target and records the anytime trace.

use serde::{Deserialize, Serialize};
use sls::registry::{self, Algorithm, RegistryError};
use sls::{ConfigError, DescentLimits, Rows, Search, Stop};

/// The `coordinate-search` algorithm's parameters, read from an experiment's `[[algorithm]]`
/// table (missing keys take the defaults, unknown keys are errors).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CoordinateSearch {
    /// First step, as a fraction of each coordinate's box width (0 < initial_step <= 1).
    pub initial_step: f64,
    /// Restart once the step falls below this fraction (0 < min_step < initial_step).
    pub min_step: f64,
    /// Iteration limit of the least-squares descent that polishes each local optimum before a
    /// restart; 0 turns the polish off.
    pub polish_iterations: usize,
}

impl Default for CoordinateSearch {
    fn default() -> Self {
        Self {
            initial_step: 0.25,
            min_step: 1e-3,
            polish_iterations: 0,
        }
    }
}

impl Algorithm for CoordinateSearch {
    const KIND: &'static str = "coordinate-search";

    fn validate(&self) -> Result<(), ConfigError> {
        let step_ok = self.initial_step > 0.0 && self.initial_step <= 1.0;
        if !step_ok {
            let found = format!("must be in (0, 1], found {}", self.initial_step);
            return Err(ConfigError::new(Self::KIND, "initial_step", found));
        }
        if !(self.min_step > 0.0 && self.min_step < self.initial_step) {
            let found = format!(
                "must be in (0, initial_step = {}), found {}",
                self.initial_step, self.min_step
            );
            return Err(ConfigError::new(Self::KIND, "min_step", found));
        }
        Ok(())
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        let mut x = vec![0.0; search.dim()];
        loop {
            search.random_pick(&mut x);
            let rmse = search.evaluate(&x)?;
            self.compass(search, &mut x, rmse)?;
            if self.polish_iterations > 0 {
                let limits = DescentLimits {
                    iterations: self.polish_iterations,
                    ..DescentLimits::default()
                };
                search.descend(&mut x, Rows::Full, limits)?;
                search.evaluate_below(&x, f64::NEG_INFINITY)?;
            }
            search.count("restart");
        }
    }
}

impl CoordinateSearch {
    /// Moves `x` (whose RMSE is `rmse`) coordinate by coordinate until the step is below
    /// `min_step`.
    fn compass(&self, search: &mut dyn Search, x: &mut [f64], mut rmse: f64) -> Result<(), Stop> {
        let widths: Vec<f64> = (search.lower().iter().zip(search.upper()))
            .map(|(lo, hi)| hi - lo)
            .collect();
        let mut step = self.initial_step;
        while step >= self.min_step {
            let mut improved = false;
            for (i, width) in widths.iter().enumerate() {
                if let Some(better) = try_coordinate(search, x, i, step * width, rmse)? {
                    rmse = better;
                    improved = true;
                }
            }
            if !improved {
                step /= 2.0;
                search.count("step_halved");
            }
        }
        Ok(())
    }
}

/// Tries `x[i] + delta`, then `x[i] - delta` (clamped to the box); keeps the first that lowers
/// the RMSE below `rmse` and returns its RMSE, else restores `x[i]` and returns `None`.
fn try_coordinate(
    search: &mut dyn Search,
    x: &mut [f64],
    i: usize,
    delta: f64,
    rmse: f64,
) -> Result<Option<f64>, Stop> {
    let old = x[i];
    let (lo, hi) = (search.lower()[i], search.upper()[i]);
    for moved in [old + delta, old - delta] {
        x[i] = moved.clamp(lo, hi);
        // Only an RMSE below the current one matters: the context may stop summing early.
        if let Some(new) = search.evaluate_below(x, rmse)?
            && new < rmse
        {
            return Ok(Some(new));
        }
    }
    x[i] = old;
    Ok(None)
}

/// Registers [`CoordinateSearch`] under `coordinate-search`; call it once, before reading an
/// experiment that uses the kind.
pub fn register() -> Result<(), RegistryError> {
    registry::register::<CoordinateSearch>()
}
