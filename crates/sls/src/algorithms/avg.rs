//! AVG, averaging simulated annealing and local search (section 2.4, Figure 7).
//!
//! ```text
//! loop                                          (until target or budget)
//!   s := RandomPick
//!   repeat
//!     s'  := SA(s)                              (from s)
//!     s'' := N2FB(s); if f(s) < f(s'') then s'' := s     (independently, from the same s)
//!     s   := (s' + s'') / 2
//!   until |f(s_k) - f(s_{k-2})| <= restart_tolerance * f(s_{k-2})   (no change over two rounds)
//! ```
//!
//! Choices where the paper is ambiguous:
//! - Section 3.1.5: "both search routines were run until both found a local minimum"; SA runs
//!   its whole schedule (defaults: Table 4's highest values, as the paper used) and the
//!   descent runs to the solver's own convergence (PORT limits).
//! - The stagnation test ("the value of the objective function does not change by a reasonable
//!   amount after two iterations") compares the averaged candidate's full-data RMSE with the
//!   one two rounds earlier, relatively (`restart_tolerance`).
//! - The average is taken in the optimiser's coordinates (the exponent as `ln(1 + n)` with
//!   brdf-model's default layout, i.e. a geometric-like mean of `1 + n`); it stays in the box
//!   because the box is convex.
//! - Every candidate (SA's steps, the descent's result, the average) is evaluated on the full
//!   data set, so the trial's best and its target test see all of them.

use crate::algorithms::sa::{Annealer, SaConfig};
use crate::algorithms::sals::descent_rows;
use crate::registry::Algorithm;
use crate::search::{DescentLimits, Search, Stop};
use crate::validate::{ConfigError, check_at_least, check_count};
use serde::{Deserialize, Serialize};

/// AVG's parameters.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct AvgConfig {
    /// The SA schedule (default: Table 4's highest values, which section 3.1.5 used).
    pub sa: SaConfig,
    /// Descent sample size: 0 (the default) for the full data set, else a fresh subsample.
    pub descent_sample_size: usize,
    /// Per-call iteration limit of the descent (PORT's default 150).
    pub descent_iterations: usize,
    /// Per-call residual-evaluation limit of the descent (PORT's default 200).
    pub descent_evaluations: usize,
    /// Restart when the averaged candidate's RMSE changed by at most this fraction over two
    /// rounds (default 1e-3).
    pub restart_tolerance: f64,
}

impl Default for AvgConfig {
    fn default() -> Self {
        Self {
            sa: SaConfig::default(),
            descent_sample_size: 0,
            descent_iterations: 150,
            descent_evaluations: 200,
            restart_tolerance: 1e-3,
        }
    }
}

impl AvgConfig {
    /// Checks the parameters; the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.sa.validate_as("avg.sa")?;
        check_count("avg", "descent_iterations", self.descent_iterations, 1)?;
        check_count("avg", "descent_evaluations", self.descent_evaluations, 1)?;
        check_at_least("avg", "restart_tolerance", self.restart_tolerance, 0.0)
    }
}

/// Whether the RMSE `now` changed by at most `tolerance` (relative) from `before`; an
/// unevaluable candidate (`+inf`) counts as stagnant only if both are.
pub(crate) fn stagnant(before: f64, now: f64, tolerance: f64) -> bool {
    if before.is_finite() && now.is_finite() {
        (now - before).abs() <= tolerance * before.abs()
    } else {
        before == now
    }
}

impl Algorithm for AvgConfig {
    const KIND: &'static str = "avg";

    fn validate(&self) -> Result<(), ConfigError> {
        AvgConfig::validate(self)
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        run(self, search)
    }
}

/// Runs AVG.
pub fn run<S: Search + ?Sized>(config: &AvgConfig, search: &mut S) -> Result<(), Stop> {
    let n = search.dim();
    let mut annealer = Annealer::new(search);
    let mut s = vec![0.0; n];
    let mut s_sa = vec![0.0; n];
    let mut s_ls = vec![0.0; n];
    let rows = descent_rows(config.descent_sample_size, search.sample_count());
    let limits = DescentLimits {
        iterations: config.descent_iterations,
        evaluations: config.descent_evaluations,
    };
    loop {
        search.count("restarts");
        search.random_pick(&mut s);
        let mut f = search.evaluate(&s)?;
        // RMSEs of the averaged candidate one and two rounds ago.
        let mut history = [f64::NAN, f64::NAN];
        loop {
            s_sa.copy_from_slice(&s);
            annealer.anneal(&config.sa, search, &mut s_sa, f)?;
            s_ls.copy_from_slice(&s);
            search.descend(&mut s_ls, rows, limits)?;
            if search.evaluate(&s_ls)? > f {
                s_ls.copy_from_slice(&s);
            }
            for ((x, a), b) in s.iter_mut().zip(&s_sa).zip(&s_ls) {
                *x = 0.5 * (a + b);
            }
            f = search.evaluate(&s)?;
            search.count("avg_rounds");
            if !history[1].is_nan() && stagnant(history[1], f, config.restart_tolerance) {
                break;
            }
            history = [f, history[0]];
        }
        search.count("stagnation_restarts");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::sa::tests::Bowl;

    #[test]
    fn stagnation_test() {
        assert!(stagnant(1.0, 1.0005, 1e-3));
        assert!(!stagnant(1.0, 1.01, 1e-3));
        assert!(stagnant(f64::INFINITY, f64::INFINITY, 1e-3));
        assert!(!stagnant(f64::INFINITY, 1.0, 1e-3));
    }

    #[test]
    fn averages_sa_and_descent_from_the_same_start() {
        // Cold, tiny SA: its result stays near the start; the bowl's descent jumps to (0, 3).
        let config = AvgConfig {
            sa: SaConfig {
                t_start: 1e-6,
                t_stop: 1e-6,
                temperatures: 1,
                iterations: 2,
                ..SaConfig::default()
            },
            ..AvgConfig::default()
        };
        let mut b = Bowl::new(200);
        assert_eq!(run(&config, &mut b), Err(Stop::EvaluationBudget));
        // pick, 2 SA steps, descent result, average.
        assert_eq!(b.evaluated[0], vec![0.9, 1.0]);
        assert_eq!(b.evaluated[3], vec![0.0, 3.0]);
        let avg = &b.evaluated[4];
        assert!(
            (avg[0] - 0.45).abs() < 1e-2 && (avg[1] - 2.0).abs() < 1e-2,
            "{avg:?}"
        );
        // The averages halve the distance to the minimum each round, so the RMSE keeps
        // changing by a factor 4: no restart within the budget at the default tolerance.
        let picks = |b: &Bowl| {
            b.evaluated
                .iter()
                .filter(|x| x.as_slice() == [0.9, 1.0])
                .count()
        };
        assert_eq!(picks(&b), 1);
        // With a tolerance of 100% every third round is "stagnant": a restart after
        // 1 + 3 * (2 + 1 + 1) evaluations.
        let config = AvgConfig {
            restart_tolerance: 1.0,
            ..config
        };
        let mut b = Bowl::new(40);
        assert_eq!(run(&config, &mut b), Err(Stop::EvaluationBudget));
        assert_eq!(b.evaluated[13], vec![0.9, 1.0]);
        assert_eq!(b.evaluated[26], vec![0.9, 1.0]);
        assert_eq!(picks(&b), 4);
    }

    #[test]
    fn validation_names_the_field() {
        let c = AvgConfig {
            restart_tolerance: -1.0,
            ..AvgConfig::default()
        };
        assert_eq!(c.validate().unwrap_err().field, "restart_tolerance");
        let mut c = AvgConfig::default();
        c.sa.iterations = 0;
        let e = c.validate().unwrap_err();
        assert_eq!((e.algorithm, e.field), ("avg.sa", "iterations"));
    }
}
