//! How a solve ended: N2FB's return codes, the report and the errors that prevent a start.

use crate::InvalidOption;

/// How a solve ended, with N2FB's meanings and codes (IV(1)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// 3: the scaled relative change of x to a local optimum is very likely at most `tolerances.x`.
    XConvergence,
    /// 4: f is very likely within `tolerances.relative_function` (relative) of its local optimum.
    RelativeFunctionConvergence,
    /// 5: both 3 and 4.
    BothConvergence,
    /// 6: f < `tolerances.absolute_function`.
    AbsoluteFunctionConvergence,
    /// 7: the Hessian near x looks singular: a step of scaled length at most `radius.singular_test`
    /// is unlikely to reduce f by more than `tolerances.singular` relative.
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
    /// An option is out of range ([`crate::Options::validate`]).
    #[error("invalid options: {0}")]
    InvalidOptions(#[from] InvalidOption),
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
