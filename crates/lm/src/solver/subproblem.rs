//! The trust-region subproblem: minimise a free-set model subject to `||z|| <= radius` by the
//! More-Sorensen/Hebden iteration on the Levenberg-Marquardt parameter `lambda`.

use crate::linalg::norm;

/// Accepted relative error of the constrained step length (NL2SOL's EPSLON).
pub(super) const RADIUS_SLACK: f64 = 0.1;

/// Result of the scaled trust-region subproblem.
#[derive(Clone, Copy, Debug)]
pub(super) struct TrResult {
    pub(super) lambda: f64,
    /// Predicted reduction of the Newton step, negative when the model is singular or indefinite.
    pub(super) newton_reduction: f64,
    /// Scaled length of the Newton step (NL2SOL's DST0), negative when it does not exist.
    pub(super) newton_norm: f64,
    pub(super) is_newton: bool,
}

/// A free-set trust-region subproblem in the scaled variables `z = D_F s_F`: what the
/// More-Sorensen/Hebden iteration ([`trust_region`]) needs from a model.
pub(super) trait Subproblem {
    /// Number of free variables.
    fn n(&self) -> usize;
    /// Newton step into `z` and its predicted reduction, or `None` when the model is singular
    /// (or indefinite).
    fn newton(&mut self, z: &mut [f64]) -> Option<f64>;
    /// Step at `lam > 0` into `z`; false when the shifted system is not positive definite.
    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool;
    /// `||L^-1 z||` where `L L^T = H + lam I` is the last shifted system and `z` its step;
    /// `q` is scratch of length n.
    fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64;
    /// Gradient norm, a bound on `||H||`, and the smallest diagonal entry of `H`.
    fn bracket_data(&self) -> (f64, f64, f64);
    /// The steepest-descent direction `-gradient` into `z`.
    fn steepest_descent(&self, z: &mut [f64]);
}

/// Relative growth of the step's norm below which [`reached_minimum_norm_step`] calls the
/// steps converged.
pub(super) const MIN_NORM_STEP_TOL: f64 = 1e-10;

/// Whether the trust-region iteration has converged to the minimum-norm Gauss-Newton step
/// inside the region, where the boundary is out of reach ([`Safeguards::stop_at_minimum_norm_step`](crate::Safeguards::stop_at_minimum_norm_step));
/// `inside_norm` is the norm of the previous step inside, negative before the first.
///
/// Without a Gauss-Newton step (`newton_norm < 0`: the model is singular) and without a
/// positive lower bound on lambda, the steps `z(lambda)` grow as lambda falls towards the
/// minimum-norm minimiser of the model. When that lies inside the region, no lambda puts the
/// step on the boundary, and the iteration divides lambda by 1000 until its 60-step limit
/// (down to lambda ~ 1e-180). MINPACK's `lmpar` stops in this case once the step stops
/// growing (`parl = 0` and `fp <= temp < 0`, Moré 1978); so does this, once the step grew by
/// less than [`MIN_NORM_STEP_TOL`] relative to the step before.
pub(super) fn reached_minimum_norm_step(
    lo: f64,
    newton_norm: f64,
    nz: f64,
    inside_norm: f64,
) -> bool {
    lo == 0.0 && newton_norm < 0.0 && nz <= inside_norm * (1.0 + MIN_NORM_STEP_TOL)
}

/// Flops of step computation between two questions to the caller whether to stop.
///
/// One solver iteration on a large model can hold dozens of trust-region solves (up to 60
/// shifted factorizations each, times the active-set passes) between two evaluations, the only
/// other places the caller is asked: at 251 free variables that is about half a second, twelve
/// times a 0.05 s CPU cutoff. Asking costs a clock read (tens of nanoseconds), which is nothing
/// next to a million flops, while the paper's 5-parameter models (about 40 flops per shifted
/// solve) never reach it, so their steps do not ask at all.
const POLL_WORK: f64 = 1e6;

/// Asks the caller ([`crate::Problem::should_stop`]) whether to stop during a step's
/// computation, once per [`POLL_WORK`] flops charged; once it said yes, the step is abandoned.
pub(super) struct StopPoll<'a> {
    ask: &'a mut dyn FnMut() -> bool,
    work: f64,
    stopped: bool,
}

impl<'a> StopPoll<'a> {
    /// A poll that calls `ask`.
    pub(super) fn new(ask: &'a mut dyn FnMut() -> bool) -> Self {
        Self {
            ask,
            work: 0.0,
            stopped: false,
        }
    }

    /// Adds `flops` of work about to be done; asks the caller once enough has accrued. True
    /// when the caller wants to stop.
    pub(super) fn charge(&mut self, flops: f64) -> bool {
        if !self.stopped {
            self.work += flops;
            if self.work >= POLL_WORK {
                self.work = 0.0;
                self.stopped = (self.ask)();
            }
        }
        self.stopped
    }

    /// Whether the caller asked to stop.
    pub(super) fn stopped(&self) -> bool {
        self.stopped
    }
}

/// Flops of one shifted factorization of an `n`-variable model (a Cholesky or a triangular
/// re-factorization: about `n^3 / 3`), charged to a [`StopPoll`].
fn shifted_solve_flops(n: usize) -> f64 {
    let n = n as f64;
    n * n * n / 3.0
}

/// The `lambda` of the next trial: `lam` when it lies inside the bracket `(lo, hi)`, else the
/// geometric mean of the bracket (`hi / 1000` while there is no lower bound), kept a
/// thousandth of the bracket above `lo`.
fn trial_lambda(lam: f64, lo: f64, hi: f64) -> f64 {
    if lam > lo && lam < hi {
        return lam;
    }
    let lam = if lo > 0.0 {
        (lo * hi).sqrt()
    } else {
        1e-3 * hi
    };
    lam.max(lo + 1e-3 * (hi - lo))
}

/// Whether a trial that just failed at `lo` (its shifted system not positive definite, or its
/// step not finite; the bracket is now `(lo, hi)`) would be repeated by every trial left: the
/// next trial's `lambda` is `lo` itself, the iteration's state is what it was before the failed
/// trial, and a shifted solve is a function of the model and `lambda` alone. Ending the
/// iteration there gives, bit for bit, what running out its trials gives (in the searches a
/// dead lobe's model whose `lambda` had fallen to 0 or a subnormal otherwise spent up to 59 more
/// factorisations, all failing the same way). Only the [`StopPoll`] charges of those trials are
/// skipped, so a CPU cutoff is noticed at the caller's next question instead of during them.
fn failure_repeats(lo: f64, hi: f64) -> bool {
    trial_lambda(0.0, lo, hi).to_bits() == lo.to_bits()
}

/// Minimises the free-set model subject to `||z|| <= radius` (More-Sorensen/Hebden iteration on
/// `lambda`); `z` receives the step; `best` (the best feasible step seen) and `q` are scratch.
/// `stop_at_min_norm` is [`Safeguards::stop_at_minimum_norm_step`](crate::Safeguards::stop_at_minimum_norm_step).
/// When `poll` says stop, the iteration ends at once with whatever step it has; the caller
/// must check [`StopPoll::stopped`] and discard it.
pub(super) fn trust_region(
    sub: &mut impl Subproblem,
    radius: f64,
    lambda_guess: f64,
    stop_at_min_norm: bool,
    poll: &mut StopPoll<'_>,
    z: &mut [f64],
    (best, q): (&mut [f64], &mut [f64]),
) -> TrResult {
    let n = sub.n();
    let (gnorm, hnorm, min_diag) = sub.bracket_data();
    if gnorm == 0.0 {
        z.fill(0.0);
        return TrResult {
            lambda: 0.0,
            newton_reduction: 0.0,
            newton_norm: 0.0,
            is_newton: true,
        };
    }
    if !gnorm.is_finite() || !hnorm.is_finite() {
        // A broken model (overflow in the factorization): no step, and no claim of
        // stationarity (a zero "Newton" step here would be reported as code 4).
        z.fill(0.0);
        return TrResult {
            lambda: lambda_guess,
            newton_reduction: -1.0,
            newton_norm: -1.0,
            is_newton: false,
        };
    }
    let mut newton_reduction = -1.0;
    let mut newton_norm = -1.0;
    if let Some(red) = sub.newton(z) {
        let nz = norm(z);
        if nz.is_finite() && red.is_finite() {
            newton_reduction = red;
            newton_norm = nz;
            if nz <= radius * (1.0 + RADIUS_SLACK) {
                return TrResult {
                    lambda: 0.0,
                    newton_reduction,
                    newton_norm,
                    is_newton: true,
                };
            }
        }
    }
    let mut lo = (-min_diag).max(gnorm / radius - hnorm).max(0.0);
    let mut hi = gnorm / radius + hnorm;
    let mut lam = lambda_guess;
    let mut have_best = false;
    let mut best_lambda = hi;
    // The norm of the last step found inside the region (see the minimum-norm test below);
    // -1 before the first, so that the test cannot pass on it.
    let mut inside_norm = -1.0;
    for _ in 0..60 {
        if poll.charge(shifted_solve_flops(n)) {
            break;
        }
        lam = trial_lambda(lam, lo, hi);
        if !sub.shifted(lam, z) {
            lo = lam;
            lam = 0.0;
            if hi - lo <= 1e-14 * hi || failure_repeats(lo, hi) {
                break;
            }
            continue;
        }
        let nz = norm(z);
        if !nz.is_finite() {
            lo = lam;
            lam = 0.0;
            if failure_repeats(lo, hi) {
                break;
            }
            continue;
        }
        if nz <= radius * (1.0 + RADIUS_SLACK) {
            best[..n].copy_from_slice(&z[..n]);
            best_lambda = lam;
            have_best = true;
        }
        if (nz - radius).abs() <= RADIUS_SLACK * radius {
            return TrResult {
                lambda: lam,
                newton_reduction,
                newton_norm,
                is_newton: false,
            };
        }
        if nz > radius {
            lo = lam;
        } else {
            hi = lam;
            if stop_at_min_norm && reached_minimum_norm_step(lo, newton_norm, nz, inside_norm) {
                break;
            }
            inside_norm = nz;
        }
        if hi - lo <= 1e-14 * hi {
            break;
        }
        // Newton step on 1/||z(lambda)|| - 1/radius (Hebden): needs ||L^-1 z||.
        let nq = sub.inverse_norm(z, q);
        lam += (nz / nq) * (nz / nq) * (nz - radius) / radius;
    }
    if have_best {
        z[..n].copy_from_slice(&best[..n]);
        TrResult {
            lambda: best_lambda,
            newton_reduction,
            newton_norm,
            is_newton: false,
        }
    } else {
        // No factorization succeeded inside the bracket: fall back to a scaled gradient step.
        sub.steepest_descent(z);
        let zn = norm(z);
        if zn > 0.0 {
            for v in z[..n].iter_mut() {
                *v *= radius / zn;
            }
        }
        TrResult {
            lambda: hi,
            newton_reduction,
            newton_norm,
            is_newton: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed trial repeats exactly when the bracket leaves the next trial at the failed
    /// `lambda`: at 0 under a subnormal upper end, or at a collapsed bracket; not while the
    /// bracket still has room.
    #[test]
    fn a_failure_repeats_only_when_the_next_trial_is_the_same_lambda() {
        assert!(failure_repeats(0.0, 3.5e-323));
        assert!(failure_repeats(1.1130856366200477, 1.113085636620048));
        assert!(!failure_repeats(0.0, 1.0));
        assert!(!failure_repeats(1e-3, 1.0));
        assert!(!failure_repeats(1e-300, 6.6e-180));
    }

    /// The next trial keeps a `lambda` inside the bracket and otherwise takes the geometric
    /// mean, or a thousandth of `hi` without a lower bound.
    #[test]
    fn trial_lambda_stays_in_the_bracket() {
        assert_eq!(trial_lambda(0.5, 0.1, 1.0), 0.5);
        assert_eq!(trial_lambda(0.0, 0.0, 2.0), 2e-3);
        assert_eq!(trial_lambda(3.0, 0.01, 1.0), 0.1);
    }
}
