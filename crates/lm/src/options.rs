//! Options, outcomes, reports and errors.

/// Which quadratic model the step is computed from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepModel {
    /// Gauss-Newton model `J^T J` only (a Levenberg-Marquardt trust-region method).
    GaussNewton,
    /// NL2SOL's adaptive choice between the Gauss-Newton model and the augmented model
    /// `J^T J + S`, where `S` is a secant approximation of the second-order term
    /// `sum_i r_i H_i`; the solver switches when the other model predicted the actual reduction
    /// better.
    Adaptive,
}

/// How the trust radius changes after a trial step (see the crate docs for the measurements).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusUpdate {
    /// N2FB's rule (NL2SOL's DA7SST and PORT's DG7ITB), the default: RADFAC is Fletcher's
    /// factor 0.1..0.5 after a rejected step or a reduction below 0.1 of the predicted one;
    /// 2..4 when the reduction is at least 0.75 of the linear prediction `-g^T s` and the radius
    /// was not decreased earlier in the iteration; otherwise 1, or 2 when DG7ITB's gradient
    /// tests at the new point pass. The radius becomes `t = RADFAC * ||D_new s||` (the scaled
    /// length of the step with the updated scaling) when RADFAC < 1 or `t` exceeds it. When the
    /// radius grows after a step that was not the Newton step, the longer step is tried at once
    /// from the same point (NL2SOL's IRC = 5) and the better one kept; unlike NL2SOL at most
    /// once per iteration. Measured on NIST (default budgets, Gauss-Newton model): one longer
    /// step 52/54; two 50/54; three 51/54 and no limit 50/54, both with a success code on a
    /// wrong answer (MGH17 start 1: repeated fourfold increases carry the iterate onto the
    /// plateau where an exponential term has died out, a spurious stationary point).
    /// Also unlike NL2SOL, no longer step is tried once the adaptive model choice may switch
    /// models ([`Options::adaptive_delay`]): with the retries there, MGH's unbounded cases
    /// (`examples/mgh_table.rs`) scored 68/78 with the defaults against 70/78 without, and
    /// 69/78 with [`Options::n2fb`] as without but with one success code on a wrong answer
    /// (Trigonometric, n = 10, from 10 x0: code 4 at f = 2.11e-5, not a listed minimum);
    /// NIST was unchanged (2026-12-02).
    Nl2sol,
    /// The ratio rule of the first version (More's): after a rejected step the radius shrinks
    /// to 0.1..0.5 of the step length (quadratic interpolation); after an accepted step with
    /// actual/predicted reduction below 0.25 it is halved, above 0.75 doubled (at most x4),
    /// otherwise kept.
    Classic,
}

/// Solver options. [`Options::default`] gives PORT's double-precision defaults (see the crate
/// docs for the meaning of each test).
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Iteration limit (PORT MXITER, default 150). An iteration is one Jacobian evaluation and
    /// the step trials from that point.
    pub max_iterations: usize,
    /// Residual-evaluation limit (PORT MXFCAL, default 200); the starting evaluation counts.
    pub max_evaluations: usize,
    /// Relative function convergence tolerance (RFCTOL, default 1e-10).
    pub rel_function_tol: f64,
    /// X-convergence tolerance (XCTOL, default sqrt(eps) = 1.49e-8).
    pub x_tol: f64,
    /// False-convergence tolerance (XFTOL, default 100 eps = 2.2e-14).
    pub false_conv_tol: f64,
    /// Absolute function convergence tolerance (AFCTOL, default 1e-20) on `f = 0.5 sum r^2`.
    pub abs_function_tol: f64,
    /// Singular convergence tolerance (SCTOL, default 1e-10).
    pub singular_tol: f64,
    /// Initial trust radius in the scaled norm `||D s||` (LMAX0, default 1).
    pub initial_radius: f64,
    /// Radius of the singular-convergence test step (LMAXS, default 1).
    pub singular_radius: f64,
    /// Make the singular-convergence test step at least as long as x itself,
    /// `max(singular_radius, ||D x||)` (default true, also in [`Options::n2fb`]; ours: N2FB
    /// tests at LMAXS alone). Where huge Jacobian columns make a step of scaled length LMAXS a
    /// round-off change of x, N2FB's test finds no predicted reduction and returns singular
    /// convergence (code 7) while the projected gradient is still large (MGH's
    /// Jennrich-Sampson from 10 x0 after 2 evaluations, `tests/robustness.rs`). Inside the
    /// searches a code 7 only shrinks the subsample or ends a hopeless descent early, and the
    /// longer test step keeps poor descents running: the searches turn it off
    /// (`sls::DescentModel::options`; measurements in the crate docs, "Robustness").
    pub singular_radius_at_least_x: bool,
    /// Raise a first trust radius that is a round-off change of x (`LMAX0 < 16 eps ||D x||`,
    /// from starts with huge Jacobian columns) to `sqrt(eps) ||D x||` (default false, as N2FB).
    /// On: MGH's Jennrich-Sampson from 10 x0 runs instead of ending in false convergence at the
    /// start, but ends with singular convergence at another stationary point (f = 129.79, not a
    /// listed minimum; `mgh_table -- OUT default lift`, 2026-12-02), and the default's 70/78
    /// unbounded is unchanged (boxed 75/78 KKT instead of 74/78). Off by default because inside
    /// the searches such descents are hopeless starts that should end at once: with it on, AED
    /// needed 8% and RPLS 41% more sample-evaluations to target on the paper's tuning instance
    /// (crate docs).
    pub lift_round_off_radius: bool,
    /// Include the secant approximation `S` of the second-order term in the scaling, as NL2SOL
    /// and N2FB do (default true, after [`Options::secant_scaling_delay`]):
    /// `D_i = max(0.6 D_i, sqrt(||J_i||^2 + S_ii))` when `S_ii > 0` (NL2SOL's DUPDAT; PORT's
    /// DD7UPD takes `max(max_k |J_ki|, sqrt(S_ii))`), so `D` follows the diagonal of
    /// `J^T J + S` rather than of `J^T J`. `S` is kept by the secant update whatever the model.
    /// On large-residual problems the Gauss-Newton diagonal underestimates the curvature and the
    /// round trust region in `D`-scaled coordinates lets the step zigzag in the variables whose
    /// second-order term it misses (Brown and Dennis: 150 iterations without it, 71 with the
    /// defaults, 21 with [`Options::n2fb`]). See the crate docs for the measurements.
    pub secant_scaling: bool,
    /// Secant updates per parameter before `S` enters the scaling (default 2: from iteration
    /// `2p + 1` on, `p` parameters, as each iteration after the first updates `S` once; 0 is
    /// N2FB's rule, from the second iteration).
    /// With no delay the searches' short descents (AED: 10 iterations on subsamples) measured
    /// 8% slower; with the delay they are unchanged and long solves still get the secant term
    /// (crate docs, "Robustness").
    pub secant_scaling_delay: usize,
    /// How fast the scaling `D` may fall (NL2SOL's and PORT's DFAC): each new Jacobian sets
    /// `D_i = max(scaling_decay D_i, t_i)`, `t_i` the column's norm (with the secant term, see
    /// [`Options::secant_scaling`]). Default [`Options::NL2SOL_SCALING_DECAY`] (0.6, N2FB's);
    /// 1 is MINPACK's rule (Moré 1978), under which `D` never falls. A slower fall helps
    /// curved valleys: with 1, Moré-Garbow-Hillstrom's Penalty II (n = 10) is solved from x0
    /// and 10 x0 and Osborne 1 from 10 x0, which creep to the iteration limit with 0.6. But
    /// `D` then cannot follow columns that shrink by orders of magnitude (an exponential
    /// started steep, `tests/robustness.rs`, ends with singular convergence far from the
    /// solution), NIST needs 9% more iterations for the same 52/54, and the searches slowed
    /// (AED 20% more sample-evaluations to target). Values 0.6 to 1 scored 69 to 71 of the 78
    /// unbounded MGH runs, not monotonically, so the default stays N2FB's (crate docs,
    /// "Robustness").
    pub scaling_decay: f64,
    /// Secant updates per parameter before the adaptive model choice ([`StepModel::Adaptive`])
    /// may switch to the augmented model (default 2: from iteration `2p + 1` on; 0 is N2FB's
    /// rule). Until then the solve is exactly a Gauss-Newton one (with its longer-step
    /// retries), so short descents (AED: 10 iterations on subsamples) are unchanged, while long
    /// solves of large-residual problems get the augmented model (Brown and Dennis: 71
    /// iterations with the Gauss-Newton model, 23 with this default; crate docs, "Robustness").
    pub adaptive_delay: usize,
    /// Trust-radius rule (default [`RadiusUpdate::Nl2sol`], N2FB's; see the crate docs).
    pub radius_update: RadiusUpdate,
    /// Hold the variables of numerically dead Jacobian columns (scaled column at most `eps`
    /// times the largest: a BRDF lobe with `d^n ~ 1e-150`) for the iteration, as if on a bound,
    /// and zero their columns (default true, also in [`Options::n2fb`]; ours, N2FB has no such
    /// rule). Left in, such columns make `R` so ill-conditioned that the step moves the dead
    /// variables by amounts set by rounding: on a 25-row problem with two dead exponential
    /// terms the solver then never fixed the live variable and could end with singular
    /// convergence (code 7) far from a stationary point; it never returned a success code
    /// (`tests/dead_columns.rs`). Inside the searches those moves seem to be what revives a
    /// dead lobe of a two-lobe fit, and a code 7 only means "shrink the subsample": with the
    /// hold, AED needed 3.6 times the sample-evaluations on the cross brushed metal instance
    /// (median 10.7e6 against 3.0e6, 100 seeds, target 0.02) and RPLS 1.19 times, so the
    /// searches' descents run with it off (`sls::DescentModel::options`).
    pub hold_dead_columns: bool,
    /// End the search for the Levenberg parameter once the steps inside the trust region have
    /// converged to the minimum-norm Gauss-Newton step (default true; MINPACK's `lmpar` rule,
    /// Moré 1978). Without it a singular model whose minimum-norm step lies inside the region
    /// keeps dividing lambda by 1000 to the 60-step limit (lambda ~ 1e-180). In the searches'
    /// descents (dead columns not held) a quarter of AED's searches for lambda in the raw
    /// exponent coordinate did that, 40% of its CPU time (perf); stopping early cut its median
    /// CPU to target on the tuning instance from 3.6 to 2.4 ms. But on the two-lobe cross
    /// instance AED then needed 1.8 times the sample-evaluations (the moves of a dead lobe's
    /// parameters that only a tiny lambda allows seem to be what revives it, as with
    /// [`Options::hold_dead_columns`]), so the searches keep it off
    /// (`sls::DescentModel::options`). The Moré-Garbow-Hillstrom and NIST tables are the same
    /// either way.
    pub stop_at_minimum_norm_step: bool,
    /// After a rejected trial step `v`, try once the corrected step `v + c` before shrinking the
    /// radius (default true; ours, not N2FB's, so [`Options::n2fb`] has it off, and so do the
    /// searches' descents, `sls::DescentModel::options`). The rejected evaluation already
    /// tells how far the residuals bent away from the linear model along `v`:
    /// `e = r(x + v) - r(x) - J v`, about `0.5 v^T H_i v` for each residual. `c` minimises
    /// `||J c + e||^2 + lambda ||D c||^2` with the step's Levenberg parameter, the
    /// second-order correction of constrained optimisation and, in effect, Transtrum and
    /// Sethna's geodesic acceleration (2012) with the trial point as its finite difference, so
    /// it costs one residual evaluation and no Jacobian. It is tried only with every variable
    /// free and `||D c|| <= 0.75 ||D v||` (GSL's `avmax`), and kept when it passes the usual
    /// acceptance test against `v`'s predicted reduction; else the step is rejected as before.
    /// On curved valleys, where the quadratic models see only the tangent and steps beyond the
    /// valley's curvature fail, the corrected step follows the valley and the radius can grow:
    /// Penalty II (n = 10) from x0 and Osborne 1 from 10 x0, which crept to the iteration
    /// limit, are solved (`tests/robustness.rs`). MGH unbounded 71/78 against 70/78 without
    /// it, NIST 52/54 either way in 964 instead of 1370 iterations; the crate docs
    /// ("Robustness") have the measurements, the sensitivity to the 0.75 and what it costs the
    /// searches, which keep it off.
    pub second_order_correction: bool,
    /// Quadratic model (default [`StepModel::Adaptive`] after [`Options::adaptive_delay`];
    /// [`StepModel::GaussNewton`] never uses the augmented model: see the crate docs).
    pub model: StepModel,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            max_iterations: 150,
            max_evaluations: 200,
            rel_function_tol: 1e-10,
            x_tol: f64::EPSILON.sqrt(),
            false_conv_tol: 100.0 * f64::EPSILON,
            abs_function_tol: 1e-20,
            singular_tol: 1e-10,
            initial_radius: 1.0,
            singular_radius: 1.0,
            singular_radius_at_least_x: true,
            lift_round_off_radius: false,
            secant_scaling: true,
            secant_scaling_delay: 2,
            scaling_decay: Self::NL2SOL_SCALING_DECAY,
            adaptive_delay: 2,
            radius_update: RadiusUpdate::Nl2sol,
            hold_dead_columns: true,
            stop_at_minimum_norm_step: true,
            second_order_correction: true,
            model: crate::DEFAULT_MODEL,
        }
    }
}

impl Options {
    /// NL2SOL's and PORT's DFAC, the factor by which the scaling may fall per iteration
    /// ([`Options::scaling_decay`]).
    pub const NL2SOL_SCALING_DECAY: f64 = 0.6;

    /// PORT's N2FB configuration: the defaults with NL2SOL's adaptive model choice
    /// ([`StepModel::Adaptive`]), the secant term in the scaling from the first secant
    /// update ([`Options::secant_scaling`] with no delay) and its scaling decay DFAC = 0.6
    /// ([`Options::NL2SOL_SCALING_DECAY`]), as N2FB always has them. It keeps our
    /// hold of numerically dead columns ([`Options::hold_dead_columns`]) and our longer
    /// singular-convergence test step ([`Options::singular_radius_at_least_x`]), which N2FB
    /// does not have, so that its codes stay honest; the searches turn both off. It has no
    /// second-order correction ([`Options::second_order_correction`]), which N2FB lacks.
    pub fn n2fb() -> Self {
        Self {
            model: StepModel::Adaptive,
            secant_scaling: true,
            secant_scaling_delay: 0,
            adaptive_delay: 0,
            scaling_decay: Self::NL2SOL_SCALING_DECAY,
            second_order_correction: false,
            ..Self::default()
        }
    }

    /// Checks every field; the error names the offending field.
    pub fn validate(&self) -> Result<(), SolveError> {
        let tol = |name: &str, v: f64, lo: f64| -> Result<(), SolveError> {
            if v.is_finite() && v >= lo && v < 1.0 {
                Ok(())
            } else {
                Err(SolveError::InvalidOptions(format!(
                    "{name} = {v} must be finite, >= {lo:e} and < 1"
                )))
            }
        };
        if self.max_iterations == 0 {
            return Err(SolveError::InvalidOptions(
                "max_iterations must be at least 1".into(),
            ));
        }
        if self.max_evaluations == 0 {
            return Err(SolveError::InvalidOptions(
                "max_evaluations must be at least 1".into(),
            ));
        }
        tol("rel_function_tol", self.rel_function_tol, 0.0)?;
        tol("x_tol", self.x_tol, 0.0)?;
        tol("false_conv_tol", self.false_conv_tol, 0.0)?;
        tol("singular_tol", self.singular_tol, 0.0)?;
        if !(self.abs_function_tol.is_finite() && self.abs_function_tol >= 0.0) {
            return Err(SolveError::InvalidOptions(format!(
                "abs_function_tol = {} must be finite and >= 0",
                self.abs_function_tol
            )));
        }
        if !(self.scaling_decay > 0.0 && self.scaling_decay <= 1.0) {
            return Err(SolveError::InvalidOptions(format!(
                "scaling_decay = {} must be > 0 and <= 1",
                self.scaling_decay
            )));
        }
        for (name, v) in [
            ("initial_radius", self.initial_radius),
            ("singular_radius", self.singular_radius),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(SolveError::InvalidOptions(format!(
                    "{name} = {v} must be finite and > 0"
                )));
            }
        }
        Ok(())
    }
}

/// How a solve ended, with N2FB's meanings and codes (IV(1)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// 3: the scaled relative change of x to a local optimum is very likely at most `x_tol`.
    XConvergence,
    /// 4: f is very likely within `rel_function_tol` (relative) of its local optimum.
    RelativeFunctionConvergence,
    /// 5: both 3 and 4.
    BothConvergence,
    /// 6: f < `abs_function_tol`.
    AbsoluteFunctionConvergence,
    /// 7: the Hessian near x looks singular: a step of scaled length at most `singular_radius`
    /// is unlikely to reduce f by more than `singular_tol` relative.
    SingularConvergence,
    /// 8: the iterates seem to converge to a non-critical point (the trust radius shrank to
    /// round-off without progress: tolerances too tight for f's accuracy, a wrong Jacobian, or a
    /// discontinuous f).
    FalseConvergence,
    /// 9: the residual-evaluation limit was reached.
    EvaluationLimit,
    /// 10: the iteration limit was reached.
    IterationLimit,
    /// 11: the caller asked to stop ([`crate::Problem::should_stop`] returned true); NL2SOL's
    /// code for its STOPX interrupt. `x` is the last accepted point.
    Interrupted,
}

impl Outcome {
    /// N2FB's return code (3..=11).
    pub fn code(self) -> u8 {
        match self {
            Outcome::XConvergence => 3,
            Outcome::RelativeFunctionConvergence => 4,
            Outcome::BothConvergence => 5,
            Outcome::AbsoluteFunctionConvergence => 6,
            Outcome::SingularConvergence => 7,
            Outcome::FalseConvergence => 8,
            Outcome::EvaluationLimit => 9,
            Outcome::IterationLimit => 10,
            Outcome::Interrupted => 11,
        }
    }

    /// True for codes 3..=6 (what R's nlminb and nls(port) count as convergence).
    pub fn is_success(self) -> bool {
        self.code() <= 6
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            Outcome::XConvergence => "x-convergence",
            Outcome::RelativeFunctionConvergence => "relative function convergence",
            Outcome::BothConvergence => "x- and relative function convergence",
            Outcome::AbsoluteFunctionConvergence => "absolute function convergence",
            Outcome::SingularConvergence => "singular convergence",
            Outcome::FalseConvergence => "false convergence",
            Outcome::EvaluationLimit => "evaluation limit",
            Outcome::IterationLimit => "iteration limit",
            Outcome::Interrupted => "interrupted",
        };
        write!(f, "{s} ({})", self.code())
    }
}

/// Result of a solve; the solution itself is left in the `x` slice passed to
/// [`crate::Solver::solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report {
    /// Why the solve stopped.
    pub outcome: Outcome,
    /// `0.5 * sum r_i^2` at the returned x.
    pub f: f64,
    /// Iterations (Jacobian evaluations made by the iteration loop).
    pub iterations: usize,
    /// Calls to [`crate::Problem::residuals`] (each computes all m residuals).
    pub residual_evaluations: usize,
    /// Calls to [`crate::Problem::jacobian`].
    pub jacobian_evaluations: usize,
}

/// Errors that prevent a solve from starting (N2FB's input errors).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// `lower[index] > upper[index]`, or a bound is NaN (PORT code 82).
    #[error("inconsistent bounds for parameter {index}: lower {lower} > upper {upper} (or NaN)")]
    InconsistentBounds {
        /// Parameter index.
        index: usize,
        /// Its lower bound.
        lower: f64,
        /// Its upper bound.
        upper: f64,
    },
    /// The residuals (or the Jacobian) cannot be computed at the (projected) start (PORT 63/65).
    #[error("residuals or Jacobian cannot be evaluated at the starting point")]
    StartNotEvaluable,
    /// An option is out of range; the message names the field.
    #[error("invalid options: {0}")]
    InvalidOptions(String),
    /// A slice has the wrong length.
    #[error("dimension mismatch: {what} has length {found}, expected {expected}")]
    DimensionMismatch {
        /// Which argument.
        what: &'static str,
        /// Required length.
        expected: usize,
        /// Given length.
        found: usize,
    },
}
