//! The polish: full-data descents with bounded-lm's robust preset from a point until the solver
//! says it is at rest. `brdf-fit` ends every fit with it and the best-known RMSE polishes its
//! best candidate with it.
//!
//! The searches' descents use the searches' solver settings (`Options::search()`: N2FB's short
//! singular-convergence test step, dead columns left free, plain Givens rotations), chosen
//! because they measured faster *inside a search*, where a descent that ends early only moves
//! the search on. As a polish they stop too soon: on noisy cross data (two lobes, sigma 0.1, one
//! lobe dead) such a descent ended after one iteration with singular convergence at RMSE
//! 0.1173881, while bounded-lm's `Options::default()` went on to 0.1173341 (the value
//! `fit --diagnose`'s refit reports). So the polish uses the library's robust preset, and it
//! stops only where the solver says the point is stationary: a success code (3 to 6), or
//! singular or false convergence (7, 8) in a descent that gained nothing (the solver can move
//! the point no further: a dead lobe, parameters the data do not determine). Iteration and
//! evaluation limits (9, 10) and descents that still gain go on, up to [`MAX_DESCENTS`].

use bounded_lm::{Outcome, Safeguards};
use sls::{DescentEnd, DescentLimits, Rows, Search, TrialContext};

/// Most full-data descents of one polish (the first included).
pub const MAX_DESCENTS: usize = 20;

/// A descent lowering the RMSE by more than this (relative) counts as a gain.
pub const GAIN: f64 = 1e-12;

/// Sets `cx`'s descents to bounded-lm's robust preset, `Options::default()`: the searches'
/// default model and scaling with every safeguard of [`Safeguards::DEFAULT`].
pub fn use_robust_solver<O: sls::Objective>(cx: &mut TrialContext<'_, O>) {
    let s = Safeguards::DEFAULT;
    // `DescentModel::Default` is `Options::search()`, the default with the searches' safeguards.
    cx.set_descent_model(sls::DescentModel::Default);
    cx.set_hold_dead_columns(s.hold_dead_columns);
    cx.set_singular_radius_at_least_x(s.singular_radius_at_least_x);
    cx.set_stop_at_minimum_norm_step(s.stop_at_minimum_norm_step);
    cx.set_scale_tiny_rotations(s.scale_tiny_rotations);
    cx.set_second_order_correction(s.second_order_correction);
}

/// Where a polish ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rest {
    /// The lowest full-data RMSE reached (never above the start's, when given).
    pub rmse: f64,
    /// Full-data descents made.
    pub descents: usize,
    /// How the last descent ended (`None`: no descent ran, the context had stopped).
    pub end: Option<DescentEnd>,
    /// Whether the solver said the point is at rest (see the module docs); false when the
    /// polish ended on [`MAX_DESCENTS`] or was stopped.
    pub at_rest: bool,
}

impl Rest {
    /// The last descent's end in words: `relative function convergence (4)`.
    pub fn end_text(&self) -> String {
        match self.end {
            Some(DescentEnd::Solver(o)) => o.to_string(),
            Some(DescentEnd::StartNotEvaluable) => "start not evaluable".into(),
            None => "no descent".into(),
        }
    }
}

/// Descends from `x` (whose full-data RMSE is `start`, or `f64::INFINITY` when unknown) with the
/// context's solver until the solver says the point is at rest (module docs). Callers set the
/// robust preset first ([`use_robust_solver`]).
pub fn to_rest<O: sls::Objective>(cx: &mut TrialContext<'_, O>, x: &mut [f64], start: f64) -> Rest {
    let mut rest = Rest {
        rmse: start,
        descents: 0,
        end: None,
        at_rest: false,
    };
    for _ in 0..MAX_DESCENTS {
        // Stops only when the caller's context does (an interrupt); no target, no clock.
        let Ok(d) = cx.descend(x, Rows::Full, DescentLimits::default()) else {
            break;
        };
        rest.descents += 1;
        rest.end = Some(d.end);
        let rmse = cx.evaluate(x).unwrap_or(f64::INFINITY);
        // NaN (both infinite) counts as no gain.
        let gained = rest.rmse - rmse > GAIN * rmse;
        rest.rmse = rest.rmse.min(rmse);
        let stationary = match d.end {
            DescentEnd::Solver(o) if o.is_success() => true,
            DescentEnd::Solver(Outcome::SingularConvergence | Outcome::FalseConvergence) => !gained,
            // A start that cannot be evaluated cannot be descended from.
            DescentEnd::StartNotEvaluable => {
                break;
            }
            DescentEnd::Solver(_) => false,
        };
        if stationary {
            rest.at_rest = true;
            break;
        }
    }
    rest
}
