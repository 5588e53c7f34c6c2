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
        if !(lam > lo && lam < hi) {
            lam = if lo > 0.0 {
                (lo * hi).sqrt()
            } else {
                1e-3 * hi
            };
            lam = lam.max(lo + 1e-3 * (hi - lo));
        }
        if !sub.shifted(lam, z) {
            lo = lam;
            lam = 0.0;
            if hi - lo <= 1e-14 * hi {
                break;
            }
            continue;
        }
        let nz = norm(z);
        if !nz.is_finite() {
            lo = lam;
            lam = 0.0;
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
#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::shifted_scratch_len;
    use crate::solver::model::{LeastSquaresModel, WideLeastSquaresModel};

    /// A deterministic upper-triangular `n x n` matrix whose rows from `k` on are zero (what the
    /// QR of a `k`-row Jacobian gives), and a right-hand side zero from `k` on.
    pub(super) fn trapezoid(n: usize, k: usize) -> (Vec<f64>, Vec<f64>) {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut t = vec![0.0; n * n];
        for j in 0..n {
            for a in 0..=j.min(k - 1) {
                t[j * n + a] = next() + if a == j { 3.0 } else { 0.0 };
            }
        }
        let u = (0..n).map(|a| if a < k { next() } else { 0.0 }).collect();
        (t, u)
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn wide_model<'a>(
        n: usize,
        k: usize,
        t: &'a [f64],
        u: &'a [f64],
        gram: &'a mut [f64],
        chol: &'a mut [f64],
        w: &'a mut [f64],
        v: &'a mut [f64],
    ) -> WideLeastSquaresModel<'a> {
        WideLeastSquaresModel {
            n,
            k,
            t,
            u,
            gram,
            chol,
            w,
            v,
        }
        .with_gram()
    }

    /// Counts the shifted factorizations of the model it wraps.
    struct Counted<S> {
        sub: S,
        shifted: usize,
    }

    impl<S: Subproblem> Subproblem for Counted<S> {
        fn n(&self) -> usize {
            self.sub.n()
        }
        fn newton(&mut self, z: &mut [f64]) -> Option<f64> {
            self.sub.newton(z)
        }
        fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
            self.shifted += 1;
            self.sub.shifted(lam, z)
        }
        fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64 {
            self.sub.inverse_norm(z, q)
        }
        fn bracket_data(&self) -> (f64, f64, f64) {
            self.sub.bracket_data()
        }
        fn steepest_descent(&self, z: &mut [f64]) {
            self.sub.steepest_descent(z)
        }
    }

    /// A singular model whose minimum-norm step lies inside the region: with
    /// `stop_at_min_norm` the iteration returns that step after a few factorizations; without
    /// it, it runs to its 60-step limit.
    #[test]
    pub(super) fn singular_model_stops_at_its_minimum_norm_step() {
        // 0.5 ||u + T z||^2 with variable 1 dead: the minimum-norm minimiser solves
        // 2 z0 + z2 = -0.2, 3 z2 = 0.3, z1 = 0, so z = (-0.15, 0, 0.1), of norm 0.18.
        let n = 3;
        let t = [2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 3.0];
        let u = [0.2, 0.0, -0.3];
        let want = [-0.15, 0.0, 0.1];
        let mut counts = vec![];
        for stop in [true, false] {
            let (mut t_lambda, mut u_lambda) = (vec![0.0; n * n], vec![0.0; n]);
            let mut row = vec![0.0; shifted_scratch_len(n)];
            let mut sub = Counted {
                sub: LeastSquaresModel {
                    n,
                    t: &t,
                    u: &u,
                    t_lambda: &mut t_lambda,
                    u_lambda: &mut u_lambda,
                    row: &mut row,
                    scale_tiny: true,
                },
                shifted: 0,
            };
            let (mut z, mut best, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            let mut never = || false;
            let mut poll = StopPoll::new(&mut never);
            let scratch = (&mut best[..], &mut q[..]);
            let tr = trust_region(&mut sub, 1.0, 0.0, stop, &mut poll, &mut z, scratch);
            assert!(
                !tr.is_newton && tr.newton_norm < 0.0,
                "singular: no Newton step"
            );
            for (a, b) in z.iter().zip(&want) {
                assert!((a - b).abs() < 1e-9, "stop {stop}: {z:?}");
            }
            counts.push(sub.shifted);
        }
        assert!(
            counts[0] <= 10,
            "with the stop: {} factorizations",
            counts[0]
        );
        assert_eq!(counts[1], 60, "without it, the 60-step limit");
    }

    /// The dual (wide) model gives the primal Givens model's step and `||L^-1 z||`.
    #[test]
    pub(super) fn wide_model_matches_the_primal_model() {
        for (n, k) in [(8, 3), (20, 7), (40, 39)] {
            let (t, u) = trapezoid(n, k);
            let mut t_lambda = vec![0.0; n * n];
            let (mut u_lambda, mut row) = (vec![0.0; n], vec![0.0; shifted_scratch_len(n)]);
            let mut primal = LeastSquaresModel {
                n,
                t: &t,
                u: &u,
                t_lambda: &mut t_lambda,
                u_lambda: &mut u_lambda,
                row: &mut row,
                scale_tiny: true,
            };
            let (mut gram, mut chol) = (vec![0.0; k * k], vec![0.0; k * k]);
            let (mut w, mut v) = (vec![0.0; k], vec![0.0; k]);
            let mut wide = wide_model(n, k, &t, &u, &mut gram, &mut chol, &mut w, &mut v);
            assert_eq!(primal.bracket_data(), wide.bracket_data());
            assert!(wide.newton(&mut vec![0.0; n]).is_none());
            for lam in [1e-3, 0.1, 1.0, 30.0, 1e4] {
                let (mut zp, mut zw, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                assert!(primal.shifted(lam, &mut zp));
                assert!(wide.shifted(lam, &mut zw));
                let scale = norm(&zp);
                for (a, b) in zp.iter().zip(&zw) {
                    assert!(
                        (a - b).abs() <= 1e-11 * scale,
                        "n {n} k {k} lam {lam}: {a} {b}"
                    );
                }
                let np = primal.inverse_norm(&zp, &mut q);
                let nw = wide.inverse_norm(&zw, &mut q);
                assert!(
                    (np - nw).abs() <= 1e-9 * np,
                    "n {n} k {k} lam {lam}: {np} {nw}"
                );
            }
        }
    }

    /// The trust-region iteration ends at the same step with either model.
    #[test]
    pub(super) fn wide_trust_region_step_matches_the_primal_one() {
        let (n, k) = (30, 6);
        let (t, u) = trapezoid(n, k);
        let mut t_lambda = vec![0.0; n * n];
        let (mut u_lambda, mut row) = (vec![0.0; n], vec![0.0; shifted_scratch_len(n)]);
        let (mut gram, mut chol) = (vec![0.0; k * k], vec![0.0; k * k]);
        let (mut w, mut v) = (vec![0.0; k], vec![0.0; k]);
        let (mut best, mut q) = (vec![0.0; n], vec![0.0; n]);
        for radius in [1e-3, 0.05, 0.5] {
            let mut primal = LeastSquaresModel {
                n,
                t: &t,
                u: &u,
                t_lambda: &mut t_lambda,
                u_lambda: &mut u_lambda,
                row: &mut row,
                scale_tiny: true,
            };
            let mut zp = vec![0.0; n];
            let mut never = || false;
            let mut poll = StopPoll::new(&mut never);
            let scratch = (&mut best[..], &mut q[..]);
            let rp = trust_region(&mut primal, radius, 0.0, true, &mut poll, &mut zp, scratch);
            let mut wide = wide_model(n, k, &t, &u, &mut gram, &mut chol, &mut w, &mut v);
            let mut zw = vec![0.0; n];
            let scratch = (&mut best[..], &mut q[..]);
            let rw = trust_region(&mut wide, radius, 0.0, true, &mut poll, &mut zw, scratch);
            // Within the region; on its boundary unless the minimum-norm Gauss-Newton step (the
            // limit lambda -> 0 of the singular model) is shorter.
            assert!(
                norm(&zw) <= radius * (1.0 + RADIUS_SLACK),
                "radius {radius}"
            );
            assert!(
                (rp.lambda - rw.lambda).abs() <= 1e-8 * rp.lambda.max(1e-12),
                "radius {radius}: {} {}",
                rp.lambda,
                rw.lambda
            );
            for (a, b) in zp.iter().zip(&zw) {
                assert!((a - b).abs() <= 1e-8 * radius, "radius {radius}: {a} {b}");
            }
        }
    }
}
