//! The Gauss-Newton model in its spectral form, for long searches of the Levenberg parameter.
//!
//! With `T = U diag(sigma) V^T` (a singular value decomposition) the shifted system
//! `(T^T T + lambda I) z = -T^T u` has the solution `z = -V w`, `w_i = gamma_i / (s_i +
//! lambda)`, where `s_i = sigma_i^2` and `gamma = diag(sigma) U^T u`. Once the decomposition is
//! made (`O(n^3)`, a few sweeps of one-sided Jacobi), every further `lambda` costs `O(n^2)`
//! and needs no square root or division chain, where a Givens factorization costs `O(n^3)`.
//!
//! That matters for singular models (a dead lobe, or fewer rows than parameters): their
//! minimum-norm step often lies inside the trust region, no `lambda` puts the step on the
//! boundary, and the iteration divides `lambda` by about 1000 until its 60-step limit. In the
//! searches those solves took most of the factorizations (docs/performance.md). The trust-region
//! iteration ([`super::subproblem::trust_region`]) therefore switches to this form after
//! [`super::subproblem::SPECTRAL_AFTER`] factorizations: the ordinary solves, which end within
//! a few, keep their Givens steps.

use super::model::LeastSquaresModel;
use super::subproblem::Subproblem;
use crate::linalg::{dot, norm};

/// Most sweeps of the one-sided Jacobi iteration; a 5 x 5 triangle converges in about six.
const MAX_SWEEPS: usize = 40;

/// `0.5 ||u + T z||^2` as its spectrum: `z(lambda) = -V w(lambda)`, `w_i = gamma_i / (s_i +
/// lambda)`. The slices are scratch of the model it was made from.
pub(super) struct SpectralModel<'a> {
    pub(super) n: usize,
    /// `V`, `n x n`, column-major: column `i` is the right singular vector of `s_i`.
    pub(super) v: &'a [f64],
    /// The squared singular values `s_i = sigma_i^2` (the eigenvalues of `T^T T`).
    pub(super) s: &'a [f64],
    /// `gamma = diag(sigma) U^T u = V^T (T^T u)`: the gradient in the basis `V`.
    pub(super) gamma: &'a [f64],
    /// `w(lambda)` of the last shifted solve.
    pub(super) w: &'a mut [f64],
    /// The `lambda` of the last shifted solve.
    pub(super) lam: f64,
}

/// Decomposes upper-triangular (or any square) `t` (`n x n`, column-major) by one-sided Jacobi:
/// `a` receives `T V = U diag(sigma)` (its columns are `sigma_i u_i`) and `v` receives `V`.
/// Column pairs are rotated until each is orthogonal to working precision (Hestenes 1958;
/// Demmel and Veselic 1992 for its accuracy). A column that is exactly zero stays zero.
/// `poll` is asked per sweep (`2 n^3` flops each); returns false when it says stop.
pub(super) fn one_sided_jacobi(
    t: &[f64],
    n: usize,
    a: &mut [f64],
    v: &mut [f64],
    poll: &mut dyn FnMut(f64) -> bool,
) -> bool {
    a[..n * n].copy_from_slice(&t[..n * n]);
    v[..n * n].fill(0.0);
    for i in 0..n {
        v[i * n + i] = 1.0;
    }
    let flops = 2.0 * (n * n * n) as f64;
    for _ in 0..MAX_SWEEPS {
        if poll(flops) {
            return false;
        }
        let mut rotated = false;
        for i in 0..n {
            for j in i + 1..n {
                rotated |= rotate_pair(a, v, n, i, j);
            }
        }
        if !rotated {
            break;
        }
    }
    true
}

/// One Jacobi rotation making columns `i` and `j` of `a` orthogonal (the same rotation of
/// `v`'s columns); false when they already are, to working precision.
fn rotate_pair(a: &mut [f64], v: &mut [f64], n: usize, i: usize, j: usize) -> bool {
    let (ai, aj) = (&a[i * n..(i + 1) * n], &a[j * n..(j + 1) * n]);
    let (alpha, beta, gamma) = (dot(ai, ai), dot(aj, aj), dot(ai, aj));
    // Norms taken apart so that tiny columns (a dead lobe's) do not underflow the product.
    if gamma == 0.0 || gamma.abs() <= f64::EPSILON * alpha.sqrt() * beta.sqrt() {
        return false;
    }
    // The rotation angle's tangent, the smaller root (Rutishauser's formulas).
    let zeta = (beta - alpha) / (2.0 * gamma);
    let t = if zeta.abs() > 1e150 {
        0.5 / zeta
    } else {
        zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt())
    };
    let c = 1.0 / (1.0 + t * t).sqrt();
    let s = c * t;
    for m in [&mut *a, &mut *v] {
        for k in 0..n {
            let (x, y) = (m[i * n + k], m[j * n + k]);
            m[i * n + k] = c * x - s * y;
            m[j * n + k] = s * x + c * y;
        }
    }
    true
}

impl SpectralModel<'_> {
    /// `w(lambda)` into `self.w`.
    fn solve_w(&mut self, lam: f64) {
        self.lam = lam;
        for i in 0..self.n {
            self.w[i] = self.gamma[i] / (self.s[i] + lam);
        }
    }
}

/// `z = -V w` for `V` (`n x n`, column-major).
fn minus_v_times(v: &[f64], n: usize, w: &[f64], z: &mut [f64]) {
    z[..n].fill(0.0);
    for (i, &wi) in w[..n].iter().enumerate() {
        for (zk, &vk) in z[..n].iter_mut().zip(&v[i * n..(i + 1) * n]) {
            *zk -= vk * wi;
        }
    }
}

impl Subproblem for SpectralModel<'_> {
    fn n(&self) -> usize {
        self.n
    }

    /// Not asked: the iteration switches to this form after its Newton step was tried.
    fn newton(&mut self, _z: &mut [f64]) -> Option<f64> {
        None
    }

    fn shifted(&mut self, lam: f64, z: &mut [f64]) -> bool {
        if !(lam > 0.0) {
            return false;
        }
        self.solve_w(lam);
        minus_v_times(self.v, self.n, self.w, z);
        true
    }

    /// `z^T (T^T T + lambda I)^-1 z = sum_i w_i^2 / (s_i + lambda)` for the last step.
    fn inverse_norm(&mut self, _z: &[f64], q: &mut [f64]) -> f64 {
        for i in 0..self.n {
            q[i] = self.w[i] / (self.s[i] + self.lam).sqrt();
        }
        norm(&q[..self.n])
    }

    fn bracket_data(&self) -> (f64, f64, f64) {
        let g2: f64 = dot(&self.gamma[..self.n], &self.gamma[..self.n]);
        let hnorm: f64 = self.s[..self.n].iter().sum();
        (g2.sqrt(), hnorm, 0.0)
    }

    fn steepest_descent(&self, z: &mut [f64]) {
        // -g = -V gamma.
        minus_v_times(self.v, self.n, self.gamma, z);
    }
}

impl LeastSquaresModel<'_> {
    /// This model's spectral form, built in its own scratch (the Givens factors are not needed
    /// any more): `V` and `gamma` in `row`, the squared singular values in `u_lambda`, `w` in
    /// `t_lambda`. `None` when `poll` said stop during the decomposition.
    pub(super) fn spectral_form(
        &mut self,
        poll: &mut dyn FnMut(f64) -> bool,
    ) -> Option<SpectralModel<'_>> {
        let n = self.n;
        let (v, rest) = self.row.split_at_mut(n * n);
        let a = &mut *self.t_lambda;
        if !one_sided_jacobi(self.t, n, a, v, poll) {
            return None;
        }
        let (gamma, s) = (&mut rest[..n], &mut *self.u_lambda);
        for i in 0..n {
            let col = &a[i * n..(i + 1) * n];
            s[i] = dot(col, col);
            gamma[i] = dot(col, &self.u[..n]);
        }
        Some(SpectralModel {
            n,
            v,
            s,
            gamma,
            w: &mut a[..n],
            lam: 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::shifted_scratch_len;

    /// A deterministic upper-triangular `n x n` matrix; the columns in `dead` are zero, and
    /// `tiny` scales the last column by 1e-150 (a dead lobe that is not exactly zero).
    fn triangle(n: usize, dead: &[usize], tiny: bool, seed: u64) -> (Vec<f64>, Vec<f64>) {
        let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut t = vec![0.0; n * n];
        for j in 0..n {
            for a in 0..=j {
                t[j * n + a] = next() + if a == j { 2.0 } else { 0.0 };
            }
            if dead.contains(&j) {
                t[j * n..(j + 1) * n].fill(0.0);
            }
            if tiny && j == n - 1 {
                t[j * n..(j + 1) * n].iter_mut().for_each(|v| *v *= 1e-150);
            }
        }
        let u = (0..n).map(|_| next()).collect();
        (t, u)
    }

    fn givens(n: usize, t: &[f64], u: &[f64], lam: f64) -> (Vec<f64>, f64) {
        let (mut tl, mut ul) = (vec![0.0; n * n], vec![0.0; n]);
        let mut row = vec![0.0; shifted_scratch_len(n)];
        let mut model = LeastSquaresModel {
            n,
            t,
            u,
            t_lambda: &mut tl,
            u_lambda: &mut ul,
            row: &mut row,
        };
        let mut z = vec![0.0; n];
        assert!(model.shifted(lam, &mut z));
        let nq = model.inverse_norm(&z.clone(), &mut vec![0.0; n]);
        (z, nq)
    }

    /// `T V` has orthogonal columns, `V` is orthogonal, and `(T V) V^T` is `T` again.
    #[test]
    fn one_sided_jacobi_decomposes_the_triangle() {
        for (n, dead) in [(5, vec![]), (7, vec![2]), (13, vec![0, 6]), (1, vec![])] {
            let (t, _) = triangle(n, &dead, false, n as u64);
            let (mut a, mut v) = (vec![0.0; n * n], vec![0.0; n * n]);
            assert!(one_sided_jacobi(&t, n, &mut a, &mut v, &mut |_| false));
            let col = |m: &[f64], i: usize| m[i * n..(i + 1) * n].to_vec();
            for i in 0..n {
                for j in 0..n {
                    let vv = dot(&col(&v, i), &col(&v, j));
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((vv - want).abs() < 1e-14, "V^T V [{i},{j}] = {vv}");
                    if i != j {
                        let aa = dot(&col(&a, i), &col(&a, j));
                        assert!(aa.abs() < 1e-13, "columns {i} and {j} of T V: {aa}");
                    }
                }
            }
            for j in 0..n {
                for k in 0..n {
                    // (A V^T)[k, j] = sum_i A[k, i] V[j, i].
                    let back: f64 = (0..n).map(|i| a[i * n + k] * v[i * n + j]).sum();
                    assert!((back - t[j * n + k]).abs() < 1e-13, "T[{k},{j}]");
                }
            }
        }
    }

    /// The spectral form's steps, `||L^-1 z||` and steepest-descent direction are the Givens
    /// model's, for full-rank, exactly singular and nearly dead triangles.
    #[test]
    fn spectral_steps_match_the_givens_steps() {
        for (n, dead, tiny) in [
            (5, vec![], false),
            (5, vec![1], false),
            (6, vec![], true),
            (9, vec![0, 4], true),
        ] {
            let (t, u) = triangle(n, &dead, tiny, 7 + n as u64);
            let (mut tl, mut ul) = (vec![0.0; n * n], vec![0.0; n]);
            let mut row = vec![0.0; shifted_scratch_len(n)];
            let mut model = LeastSquaresModel {
                n,
                t: &t,
                u: &u,
                t_lambda: &mut tl,
                u_lambda: &mut ul,
                row: &mut row,
            };
            let mut sd_givens = vec![0.0; n];
            model.steepest_descent(&mut sd_givens);
            let mut spectral = model.spectral_form(&mut |_| false).expect("not stopped");
            let mut sd = vec![0.0; n];
            spectral.steepest_descent(&mut sd);
            for (a, b) in sd.iter().zip(&sd_givens) {
                assert!(
                    (a - b).abs() <= 1e-13 * norm(&sd_givens),
                    "steepest descent"
                );
            }
            for lam in [1e-12, 1e-4, 0.3, 10.0, 1e5] {
                let (zg, nqg) = givens(n, &t, &u, lam);
                let mut z = vec![0.0; n];
                assert!(spectral.shifted(lam, &mut z));
                let nq = spectral.inverse_norm(&z.clone(), &mut vec![0.0; n]);
                let scale = norm(&zg);
                for (a, b) in z.iter().zip(&zg) {
                    assert!(
                        (a - b).abs() <= 1e-9 * scale,
                        "n {n} lam {lam}: {z:?} {zg:?}"
                    );
                }
                assert!(
                    (nq - nqg).abs() <= 1e-8 * nqg,
                    "n {n} lam {lam}: {nq} {nqg}"
                );
            }
            assert!(
                !spectral.shifted(0.0, &mut vec![0.0; n]),
                "lambda must be positive"
            );
        }
    }

    /// The decomposition asks the poll once per sweep and gives up when it says stop.
    #[test]
    fn the_decomposition_stops_when_asked() {
        let n = 6;
        let (t, _) = triangle(n, &[], false, 3);
        let (mut a, mut v) = (vec![0.0; n * n], vec![0.0; n * n]);
        let mut asked = 0;
        assert!(!one_sided_jacobi(&t, n, &mut a, &mut v, &mut |flops| {
            asked += 1;
            assert_eq!(flops, 2.0 * 216.0);
            asked == 2
        }));
        assert_eq!(asked, 2);
    }
}
