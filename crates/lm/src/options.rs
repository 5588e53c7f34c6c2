//! Solver options in groups (limits, tolerances, step model, scaling, trust radius,
//! safeguards), the named presets, and their validation. Why each default departs from N2FB,
//! with the measurements, is in `docs/solver.md`.

/// Which quadratic model the step is computed from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepModel {
    /// Gauss-Newton model `J^T J` only (a Levenberg-Marquardt trust-region method).
    GaussNewton,
    /// NL2SOL's adaptive choice between the Gauss-Newton model and the augmented model
    /// `J^T J + S`, `S` a secant approximation of the second-order term `sum_i r_i H_i`: after
    /// a poor step the solver switches when the other model predicted the actual reduction
    /// better. The choice may switch only once `S` has had `delay` secant updates per
    /// parameter (from iteration `delay * p + 1` on); until then the solve is exactly a
    /// Gauss-Newton one. Default delay 2; 0 is N2FB's rule.
    Adaptive {
        /// Secant updates per parameter before the first switch.
        delay: usize,
    },
}

impl StepModel {
    /// The adaptive model choice with N2FB's rule: it may switch from the first update.
    pub const N2FB: StepModel = StepModel::Adaptive { delay: 0 };
}

/// Whether (and when) the secant term `S` enters the scaling `D`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SecantScaling {
    /// `D` follows the Jacobian's columns only.
    Off,
    /// NL2SOL's DUPDAT: `D_i = max(decay D_i, sqrt(||J_i||^2 + S_ii))` where `S_ii > 0`, once
    /// `S` has had `delay` secant updates per parameter (default 2; 0 is N2FB's rule, from the
    /// second iteration). `S` is kept by the secant update whatever the model.
    After {
        /// Secant updates per parameter before `S` enters the scaling.
        delay: usize,
    },
}

/// How the trust radius changes after a trial step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusUpdate {
    /// N2FB's rule (NL2SOL's DA7SST with PORT's DG7ITB), the default: RADFAC is Fletcher's
    /// factor 0.1..0.5 after a rejected or poor step, 2..4 after a step that achieved at least
    /// 0.75 of the linear prediction `-g^T s` with no decrease earlier in the iteration, else 1
    /// (2 when DG7ITB's gradient tests pass); the radius becomes `RADFAC ||D_new s||` when
    /// RADFAC < 1 or that is larger. When the radius grows after a step that was not the
    /// Newton step, the longer step is tried at once from the same point (IRC = 5), at most
    /// once per iteration and never once the adaptive model choice may switch.
    Nl2sol,
    /// Moré's ratio rule: after a rejected step the radius shrinks to 0.1..0.5 of the step
    /// length (quadratic interpolation); after an accepted step with actual/predicted reduction
    /// below 0.25 it is halved, above 0.75 doubled (at most x4), otherwise kept.
    Classic,
}

/// Budgets of one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Iteration limit (PORT MXITER, at least 1, default 150). An iteration is one Jacobian
    /// evaluation and the step trials from that point.
    pub iterations: usize,
    /// Residual-evaluation limit (PORT MXFCAL, at least 1, default 200); the starting
    /// evaluation counts.
    pub evaluations: usize,
}

/// Convergence tolerances (PORT's names; see [`crate::Outcome`] for the tests).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative function convergence (RFCTOL, in `[0, 1)`, default 1e-10).
    pub relative_function: f64,
    /// X-convergence (XCTOL, in `[0, 1)`, default `sqrt(eps)` = 1.49e-8).
    pub x: f64,
    /// False convergence (XFTOL, in `[0, 1)`, default `100 eps` = 2.2e-14).
    pub false_convergence: f64,
    /// Absolute function convergence on `f = 0.5 sum r^2` (AFCTOL, finite and >= 0, default
    /// 1e-20).
    pub absolute_function: f64,
    /// Singular convergence (SCTOL, in `[0, 1)`, default 1e-10).
    pub singular: f64,
}

/// How the scaling `D` follows the Jacobian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scaling {
    /// How fast `D` may fall (NL2SOL's DFAC, in `(0, 1]`): each new Jacobian sets
    /// `D_i = max(decay D_i, t_i)`, `t_i` the column's 2-norm. Default
    /// [`Scaling::NL2SOL_DECAY`]; 1 is MINPACK's rule, under which `D` never falls.
    pub decay: f64,
    /// Whether the secant term enters `D` (default [`SecantScaling::After`] 2 updates per
    /// parameter).
    pub secant: SecantScaling,
}

impl Scaling {
    /// NL2SOL's and PORT's DFAC, the factor by which the scaling may fall per iteration.
    pub const NL2SOL_DECAY: f64 = 0.6;
}

/// The trust radius: its start, its update rule and the singular-convergence test step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radius {
    /// Initial radius in the scaled norm `||D s||` (LMAX0, finite and > 0, default 1).
    pub initial: f64,
    /// Scaled length of the singular-convergence test step (LMAXS, finite and > 0,
    /// default 1).
    pub singular_test: f64,
    /// Update rule (default [`RadiusUpdate::Nl2sol`]).
    pub update: RadiusUpdate,
}

/// Rules of ours that N2FB lacks (each on or off). The library's default turns on all but
/// [`Safeguards::lift_round_off_radius`]; the searches turn them all off
/// ([`Safeguards::SEARCH`]), because there a solve that ends early only moves the search on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Safeguards {
    /// Hold the variables of numerically dead Jacobian columns (scaled column at most `eps`
    /// times the largest) for the iteration, as if on a bound, and zero their columns
    /// (default on): left in, they make `R` so ill-conditioned that the step moves them by
    /// amounts set by rounding. A held variable on a bound still counts as free for the
    /// convergence verdict when its true gradient `J^T r` points into the box (the hold zeroes
    /// its `g`), so a dead lobe that could be revived ends with code 7, not 4.
    pub hold_dead_columns: bool,
    /// Make the singular-convergence test step at least as long as x,
    /// `max(singular_test, ||D x||)` (default on): where huge columns make a step of LMAXS a
    /// round-off change of x, N2FB's test claims singular convergence while the projected
    /// gradient is still large.
    pub singular_radius_at_least_x: bool,
    /// Raise a first radius that is a round-off change of x (`LMAX0 < 16 eps ||D x||`) to
    /// `sqrt(eps) ||D x||` (default off, as N2FB).
    pub lift_round_off_radius: bool,
    /// End the search for the Levenberg parameter once the steps inside the region have
    /// converged to a singular model's minimum-norm step (MINPACK's `lmpar` rule, default on);
    /// without it the search divides lambda by 1000 to its 60-step limit.
    pub stop_at_minimum_norm_step: bool,
    /// After a rejected step `v`, try once the corrected step `v + c`, `c` minimising
    /// `||J c + e||^2 + lambda ||D c||^2` with `e = r(x + v) - r(x) - J v` (default on): one
    /// residual evaluation, no Jacobian; tried only with every variable free and
    /// `||D c|| <= 0.75 ||D v||`, kept when it passes the usual test against `v`'s predicted
    /// reduction.
    pub second_order_correction: bool,
    /// Compute a Givens rotation of the shifted factorization by `hypot`, which scales its two
    /// entries, when their squares underflow (default on). Computed plainly, a dead lobe's
    /// entries (about 1e-175) give `r = 0` and a NaN factor, which the search for the
    /// Levenberg parameter reads as "not positive definite" until its trials run out; it then
    /// ends on a scaled gradient step. The searches keep the plain rotation: with the scaling,
    /// AED needed 4.5 times the median sample-evaluations on the noiseless two-lobe cross
    /// instance (150 trials, log-rank Holm p 0.0013; docs/performance.md).
    pub scale_tiny_rotations: bool,
}

impl Safeguards {
    /// The library's default: every safeguard but the lifted first radius.
    pub const DEFAULT: Safeguards = Safeguards {
        hold_dead_columns: true,
        singular_radius_at_least_x: true,
        lift_round_off_radius: false,
        stop_at_minimum_norm_step: true,
        second_order_correction: true,
        scale_tiny_rotations: true,
    };

    /// The searches' descents: none, as in N2FB.
    pub const SEARCH: Safeguards = Safeguards {
        hold_dead_columns: false,
        singular_radius_at_least_x: false,
        lift_round_off_radius: false,
        stop_at_minimum_norm_step: false,
        second_order_correction: false,
        scale_tiny_rotations: false,
    };
}

/// Solver options. Presets: [`Options::default`] (the reference), [`Options::n2fb`],
/// [`Options::gauss_newton`] and [`Options::search`]; [`Options::for_search`] turns any of
/// them into the searches' variant.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Budgets (default 150 iterations, 200 residual evaluations).
    pub limits: Limits,
    /// Convergence tolerances (PORT's double-precision defaults).
    pub tolerances: Tolerances,
    /// Quadratic model (default [`StepModel::Adaptive`] with delay 2).
    pub model: StepModel,
    /// Scaling `D` (default decay 0.6, secant term after 2 updates per parameter).
    pub scaling: Scaling,
    /// Trust radius (default LMAX0 = LMAXS = 1, N2FB's update rule).
    pub radius: Radius,
    /// Our rules beyond N2FB (default [`Safeguards::DEFAULT`]).
    pub safeguards: Safeguards,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            limits: Limits {
                iterations: 150,
                evaluations: 200,
            },
            tolerances: Tolerances {
                relative_function: 1e-10,
                x: f64::EPSILON.sqrt(),
                false_convergence: 100.0 * f64::EPSILON,
                absolute_function: 1e-20,
                singular: 1e-10,
            },
            model: StepModel::Adaptive { delay: 2 },
            scaling: Scaling {
                decay: Scaling::NL2SOL_DECAY,
                secant: SecantScaling::After { delay: 2 },
            },
            radius: Radius {
                initial: 1.0,
                singular_test: 1.0,
                update: RadiusUpdate::Nl2sol,
            },
            safeguards: Safeguards::DEFAULT,
        }
    }
}

/// An option outside its range: which one, its value and what was expected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("option `{field}` = {value}: expected {expected}")]
pub struct InvalidOption {
    /// The field's path in [`Options`], e.g. `tolerances.x`.
    pub field: &'static str,
    /// The value given.
    pub value: String,
    /// The rule it breaks.
    pub expected: &'static str,
}

impl Options {
    /// PORT's N2FB configuration: the adaptive model and the secant term in the scaling from
    /// the first update, DFAC 0.6 and no second-order correction (which N2FB lacks). It keeps
    /// our dead-column hold and longer singular test step so that its codes stay honest
    /// ([`Options::for_search`] drops them).
    pub fn n2fb() -> Self {
        let mut options = Self {
            model: StepModel::N2FB,
            scaling: Scaling {
                decay: Scaling::NL2SOL_DECAY,
                secant: SecantScaling::After { delay: 0 },
            },
            ..Self::default()
        };
        options.safeguards.second_order_correction = false;
        options
    }

    /// The default with the Gauss-Newton model only.
    pub fn gauss_newton() -> Self {
        Self {
            model: StepModel::GaussNewton,
            ..Self::default()
        }
    }

    /// The searches' descents: the default with [`Safeguards::SEARCH`].
    pub fn search() -> Self {
        Self::default().for_search()
    }

    /// This configuration with the searches' safeguards ([`Safeguards::SEARCH`]).
    pub fn for_search(self) -> Self {
        Self {
            safeguards: Safeguards::SEARCH,
            ..self
        }
    }

    /// The same options with other budgets.
    pub fn with_limits(self, iterations: usize, evaluations: usize) -> Self {
        Self {
            limits: Limits {
                iterations,
                evaluations,
            },
            ..self
        }
    }

    /// Checks every field; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), InvalidOption> {
        self.validate_limits()?;
        self.validate_tolerances()?;
        check(
            "scaling.decay",
            self.scaling.decay,
            self.scaling.decay > 0.0 && self.scaling.decay <= 1.0,
            "> 0 and <= 1",
        )?;
        for (field, v) in [
            ("radius.initial", self.radius.initial),
            ("radius.singular_test", self.radius.singular_test),
        ] {
            check(field, v, v.is_finite() && v > 0.0, "finite and > 0")?;
        }
        Ok(())
    }

    fn validate_limits(&self) -> Result<(), InvalidOption> {
        for (field, v) in [
            ("limits.iterations", self.limits.iterations),
            ("limits.evaluations", self.limits.evaluations),
        ] {
            check(field, v, v >= 1, "at least 1")?;
        }
        Ok(())
    }

    fn validate_tolerances(&self) -> Result<(), InvalidOption> {
        let t = &self.tolerances;
        for (field, v) in [
            ("tolerances.relative_function", t.relative_function),
            ("tolerances.x", t.x),
            ("tolerances.false_convergence", t.false_convergence),
            ("tolerances.singular", t.singular),
        ] {
            check(
                field,
                v,
                v.is_finite() && (0.0..1.0).contains(&v),
                "in [0, 1)",
            )?;
        }
        let a = t.absolute_function;
        check(
            "tolerances.absolute_function",
            a,
            a.is_finite() && a >= 0.0,
            "finite and >= 0",
        )
    }
}

fn check(
    field: &'static str,
    value: impl std::fmt::Display,
    ok: bool,
    expected: &'static str,
) -> Result<(), InvalidOption> {
    if ok {
        Ok(())
    } else {
        Err(InvalidOption {
            field,
            value: value.to_string(),
            expected,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_validate_and_differ_where_documented() {
        for o in [
            Options::default(),
            Options::n2fb(),
            Options::gauss_newton(),
            Options::search(),
        ] {
            assert_eq!(o.validate(), Ok(()));
        }
        assert_eq!(Options::search().safeguards, Safeguards::SEARCH);
        assert_eq!(Options::search().model, Options::default().model);
        let n2fb = Options::n2fb().for_search();
        assert_eq!(n2fb.model, StepModel::Adaptive { delay: 0 });
        assert_eq!(n2fb.scaling.secant, SecantScaling::After { delay: 0 });
        assert!(!Options::n2fb().safeguards.second_order_correction);
        assert!(Options::n2fb().safeguards.hold_dead_columns);
    }

    #[test]
    fn validate_names_the_field_and_the_rule() {
        let mut o = Options::default();
        o.tolerances.x = 1.0;
        let e = o.validate().unwrap_err();
        assert_eq!((e.field, e.expected), ("tolerances.x", "in [0, 1)"));
        assert_eq!(
            e.to_string(),
            "option `tolerances.x` = 1: expected in [0, 1)"
        );
        let o = Options::default().with_limits(0, 10);
        assert_eq!(o.validate().unwrap_err().field, "limits.iterations");
        let mut o = Options::default();
        o.scaling.decay = f64::NAN;
        assert_eq!(o.validate().unwrap_err().field, "scaling.decay");
        let mut o = Options::default();
        o.radius.singular_test = 0.0;
        assert_eq!(o.validate().unwrap_err().field, "radius.singular_test");
        let mut o = Options::default();
        o.tolerances.absolute_function = -1.0;
        assert_eq!(
            o.validate().unwrap_err().field,
            "tolerances.absolute_function"
        );
    }
}
