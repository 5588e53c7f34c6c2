//! The three forms of the free-set quadratic model that the trust-region iteration solves:
//! the Gauss-Newton model by Givens rotations, the same in its dual form when it has fewer rows
//! than variables, and the augmented model by Cholesky factorizations.

use super::factorisation::triangular_full_rank;
use super::subproblem::Subproblem;
use crate::linalg::{
    backward_solve, cholesky_shifted, dot, forward_solve, norm, shifted_triangular, upper_solve,
    upper_transpose_solve,
};

/// Relative pivot threshold at which the augmented model `D^-1 (J^T J + S) D^-1` counts as
/// singular or indefinite (no Newton step).
pub(super) const RANK_TOL: f64 = 1e-14;

/// Relative pivot threshold for shifted (lambda > 0) factorizations.
pub(super) const SHIFTED_TOL: f64 = 1e-15;

/// The Gauss-Newton model in least-squares form `0.5 ||u + T z||^2`, `T` upper triangular;
/// shifted systems are factored by Givens rotations of `[T; sqrt(lambda) I]` (MINPACK's
/// qrsolv), so `J^T J` is never formed.
pub(super) struct LeastSquaresModel<'a> {
    pub(super) n: usize,
    pub(super) t: &'a [f64],
    pub(super) u: &'a [f64],
    /// `T_lambda` with `T_lambda^T T_lambda = T^T T + lambda I`.
    pub(super) t_lambda: &'a mut [f64],
    /// The rotated right-hand side.
    pub(super) u_lambda: &'a mut [f64],
    /// Givens scratch rows ([`shifted_scratch_len`]).
    pub(super) row: &'a mut [f64],
    /// [`Safeguards::scale_tiny_rotations`](crate::Safeguards::scale_tiny_rotations).
    pub(super) scale_tiny: bool,
}

impl Subproblem for LeastSquaresModel<'_> {
    fn n(&self) -> usize {
        self.n
    }

    fn newton(&mut self, z: &mut [f64]) -> Option<f64> {
        let n = self.n;
        if !triangular_full_rank(self.t, n) {
            return None;
        }
        for i in 0..n {
            z[i] = -self.u[i];
        }
        upper_solve(self.t, n, z);
        Some(0.5 * dot(self.u, self.u))
    }

    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        let n = self.n;
        shifted_triangular(
            self.t,
            self.u,
            n,
            lam,
            self.t_lambda,
            self.u_lambda,
            self.row,
            self.scale_tiny,
        );
        if (0..n).any(|i| self.t_lambda[i * n + i] == 0.0) {
            return false;
        }
        for i in 0..n {
            z[i] = -self.u_lambda[i];
        }
        upper_solve(self.t_lambda, n, z);
        true
    }

    fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64 {
        let n = self.n;
        q[..n].copy_from_slice(&z[..n]);
        upper_transpose_solve(self.t_lambda, n, q);
        norm(&q[..n])
    }

    fn bracket_data(&self) -> (f64, f64, f64) {
        least_squares_bracket_data(self.t, self.u, self.n)
    }

    fn steepest_descent(&self, z: &mut [f64]) {
        least_squares_steepest_descent(self.t, self.u, self.n, z);
    }
}

/// Gradient norm `||T^T u||`, the bound `||T^T T|| <= ||T||_F^2` and 0, the smallest possible
/// diagonal entry of the positive semidefinite `T^T T`.
pub(super) fn least_squares_bracket_data(t: &[f64], u: &[f64], n: usize) -> (f64, f64, f64) {
    let mut g2 = 0.0;
    for j in 0..n {
        let v = dot(&t[j * n..j * n + j + 1], &u[..j + 1]);
        g2 += v * v;
    }
    let f2 = dot(&t[..n * n], &t[..n * n]);
    (g2.sqrt(), f2, 0.0)
}

/// `z = -T^T u`, the negative gradient of `0.5 ||u + T z||^2` at 0.
pub(super) fn least_squares_steepest_descent(t: &[f64], u: &[f64], n: usize, z: &mut [f64]) {
    for j in 0..n {
        z[j] = -dot(&t[j * n..j * n + j + 1], &u[..j + 1]);
    }
}

/// The Gauss-Newton model `0.5 ||u + T z||^2` when `T` has only `k < n` nonzero rows (fewer
/// residuals than free variables, as in AED's 25-row descents of many-lobe models), solved in
/// its dual form: `(T^T T + lambda I) z = -T^T u` has the solution `z = -T_k^T w` with
/// `(T_k T_k^T + lambda I) w = u_k`, a `k x k` system. The primal Givens factorization costs
/// `O(n^3)` per lambda (0.2 s per step at 16 lobes, seconds at 50, all of it between two calls
/// of the problem, so no CPU cutoff could interrupt it); this costs `O(k^3 + k n)` after the
/// Gram matrix (`O(k^2 n)`, once per model). The model is singular, so there is no Newton step.
pub(super) struct WideLeastSquaresModel<'a> {
    pub(super) n: usize,
    pub(super) k: usize,
    pub(super) t: &'a [f64],
    pub(super) u: &'a [f64],
    /// `G = T_k T_k^T` (symmetric, `k x k`, column-major).
    pub(super) gram: &'a mut [f64],
    /// Lower Cholesky factor of `G + lambda I`.
    pub(super) chol: &'a mut [f64],
    /// `w = (G + lambda I)^-1 u_k` of the last shifted system.
    pub(super) w: &'a mut [f64],
    /// Scratch: `(G + lambda I)^-1 w`.
    pub(super) v: &'a mut [f64],
}

impl WideLeastSquaresModel<'_> {
    /// Forms the Gram matrix; `t` is `n x n` column-major with rows `>= k` zero.
    pub(super) fn with_gram(self) -> Self {
        let (n, k) = (self.n, self.k);
        debug_assert!(k < n);
        self.gram.fill(0.0);
        // T is upper triangular: T[a, j] = t[j n + a], nonzero only for a <= j and a < k.
        for j in 0..n {
            let col = &self.t[j * n..j * n + (j + 1).min(k)];
            for (b, &tb) in col.iter().enumerate() {
                for (a, &ta) in col[..=b].iter().enumerate() {
                    self.gram[b * k + a] += ta * tb;
                }
            }
        }
        for b in 0..k {
            for a in 0..b {
                self.gram[a * k + b] = self.gram[b * k + a];
            }
        }
        self
    }
}

impl Subproblem for WideLeastSquaresModel<'_> {
    fn n(&self) -> usize {
        self.n
    }

    fn newton(&mut self, _z: &mut [f64]) -> Option<f64> {
        None
    }

    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        let (n, k) = (self.n, self.k);
        if !cholesky_shifted(self.gram, lam, k, SHIFTED_TOL, self.chol) {
            return false;
        }
        self.w.copy_from_slice(&self.u[..k]);
        forward_solve(self.chol, k, self.w);
        backward_solve(self.chol, k, self.w);
        // z = -T_k^T w: z_j = -sum_{a <= min(j, k-1)} T[a, j] w_a.
        for j in 0..n {
            let rows = (j + 1).min(k);
            z[j] = -dot(&self.t[j * n..j * n + rows], &self.w[..rows]);
        }
        true
    }

    /// `z^T (T^T T + lambda I)^-1 z = w^T G (G + lambda I)^-1 w` for `z = -T^T w` (push-through
    /// identity): a sum of positive terms in G's eigenbasis, so no cancellation.
    fn inverse_norm(&mut self, _z: &[f64], _q: &mut [f64]) -> f64 {
        let k = self.k;
        self.v.copy_from_slice(self.w);
        forward_solve(self.chol, k, self.v);
        backward_solve(self.chol, k, self.v);
        let mut s = 0.0;
        for a in 0..k {
            s += self.w[a] * dot(&self.gram[a * k..(a + 1) * k], self.v);
        }
        s.max(0.0).sqrt()
    }

    fn bracket_data(&self) -> (f64, f64, f64) {
        least_squares_bracket_data(self.t, self.u, self.n)
    }

    fn steepest_descent(&self, z: &mut [f64]) {
        least_squares_steepest_descent(self.t, self.u, self.n, z);
    }
}

/// The augmented model in normal form `g^T z + 0.5 z^T H z` (possibly indefinite), factored by
/// Cholesky of `H + lambda I`.
pub(super) struct QuadraticModel<'a> {
    pub(super) n: usize,
    pub(super) h: &'a [f64],
    pub(super) g: &'a [f64],
    /// Lower Cholesky factor of the last shifted system.
    pub(super) chol: &'a mut [f64],
}

impl Subproblem for QuadraticModel<'_> {
    fn n(&self) -> usize {
        self.n
    }

    fn newton(&mut self, z: &mut [f64]) -> Option<f64> {
        let n = self.n;
        if !cholesky_shifted(self.h, 0.0, n, RANK_TOL, self.chol) {
            return None;
        }
        for i in 0..n {
            z[i] = -self.g[i];
        }
        forward_solve(self.chol, n, z);
        backward_solve(self.chol, n, z);
        Some(-0.5 * dot(self.g, z))
    }

    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        let n = self.n;
        if !cholesky_shifted(self.h, lam, n, SHIFTED_TOL, self.chol) {
            return false;
        }
        for i in 0..n {
            z[i] = -self.g[i];
        }
        forward_solve(self.chol, n, z);
        backward_solve(self.chol, n, z);
        true
    }

    fn inverse_norm(&mut self, z: &[f64], q: &mut [f64]) -> f64 {
        let n = self.n;
        q[..n].copy_from_slice(&z[..n]);
        forward_solve(self.chol, n, q);
        norm(&q[..n])
    }

    fn bracket_data(&self) -> (f64, f64, f64) {
        let n = self.n;
        let mut hnorm = 0.0f64;
        let mut min_diag = f64::INFINITY;
        for j in 0..n {
            let col: f64 = self.h[j * n..(j + 1) * n].iter().map(|v| v.abs()).sum();
            hnorm = hnorm.max(col);
            min_diag = min_diag.min(self.h[j * n + j]);
        }
        (norm(self.g), hnorm, min_diag)
    }

    fn steepest_descent(&self, z: &mut [f64]) {
        for (zi, gi) in z.iter_mut().zip(self.g) {
            *zi = -gi;
        }
    }
}

#[cfg(test)]
#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::shifted_scratch_len;
    use crate::solver::subproblem::{RADIUS_SLACK, StopPoll, trust_region};

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

    /// Solves the singular model `0.5 ||u + T z||^2` with variable 1 dead, whose minimum-norm
    /// minimiser (solving 2 z0 + z2 = -0.2, 3 z2 = 0.3, z1 = 0) is `(-0.15, 0, 0.1)`, of norm
    /// 0.18, inside the unit region. Returns the step and the shifted factorizations it took.
    fn solve_singular_model(stop_at_min_norm: bool, lambda_guess: f64) -> (Vec<f64>, usize) {
        let n = 3;
        let t = [2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 3.0];
        let u = [0.2, 0.0, -0.3];
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
        let tr = trust_region(
            &mut sub,
            1.0,
            lambda_guess,
            stop_at_min_norm,
            &mut poll,
            &mut z,
            scratch,
        );
        assert!(
            !tr.is_newton && tr.newton_norm < 0.0,
            "singular: no Newton step"
        );
        (z, sub.shifted)
    }

    const MIN_NORM_STEP: [f64; 3] = [-0.15, 0.0, 0.1];

    /// A singular model whose minimum-norm step lies inside the region: with
    /// `stop_at_min_norm` the iteration returns that step after a few factorizations; without
    /// it, it runs to its 60-step limit.
    #[test]
    pub(super) fn singular_model_stops_at_its_minimum_norm_step() {
        let mut counts = vec![];
        for stop in [true, false] {
            let (z, shifted) = solve_singular_model(stop, 0.0);
            for (a, b) in z.iter().zip(&MIN_NORM_STEP) {
                assert!((a - b).abs() < 1e-9, "stop {stop}: {z:?}");
            }
            counts.push(shifted);
        }
        assert!(
            counts[0] <= 10,
            "with the stop: {} factorizations",
            counts[0]
        );
        assert_eq!(counts[1], 60, "without it, the 60-step limit");
    }

    /// Started from a subnormal `lambda` (as a search's solve after a long run of tiny ones),
    /// the next trial's `lambda` rounds to 0, whose singular system fails, and so would every
    /// trial after it: the iteration ends there with its last step inside the region instead
    /// of factorizing the same failing system to its limit.
    #[test]
    pub(super) fn a_failure_every_later_trial_would_repeat_ends_the_iteration() {
        let (z, shifted) = solve_singular_model(false, 1e-320);
        // lambda 1e-320 and 1e-323 succeed, 1e-3 * 1e-323 rounds to 0 and fails; without
        // the ending, 57 more trials would fail at 0.
        assert_eq!(shifted, 3, "two successes, one failure at lambda 0");
        for (a, b) in z.iter().zip(&MIN_NORM_STEP) {
            assert!((a - b).abs() < 1e-9, "{z:?}");
        }
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
