//! One-sided Jacobi SVD (Hestenes) of a small-column matrix: accurate singular values even
//! for an ill-conditioned Jacobian because `J^T J` is never formed (its condition would be
//! squared). `p <= 20` columns and `m` up to 10^5 rows cost milliseconds, so faer or nalgebra
//! (minutes of build time on 2 cores) are not worth it here.

/// Singular values (descending) and right singular vectors.
pub(crate) struct Svd {
    /// Singular values, largest first.
    pub s: Vec<f64>,
    /// Right singular vectors, column-major `p x p`: `v[k * p + j]` is entry `j` of vector `k`.
    pub v: Vec<f64>,
}

/// SVD of the column-major `m x p` matrix `a` (`a[j * m + i]`).
pub(crate) fn svd(a: &[f64], m: usize, p: usize) -> Svd {
    let mut u = a.to_vec();
    let mut v = vec![0.0; p * p];
    for j in 0..p {
        v[j * p + j] = 1.0;
    }
    for _sweep in 0..80 {
        let mut rotated = false;
        for j in 0..p {
            for k in j + 1..p {
                let (cj, ck) = (&u[j * m..(j + 1) * m], &u[k * m..(k + 1) * m]);
                let alpha: f64 = cj.iter().map(|x| x * x).sum();
                let beta: f64 = ck.iter().map(|x| x * x).sum();
                let gamma: f64 = cj.iter().zip(ck).map(|(x, y)| x * y).sum();
                // Converged pair: the columns are orthogonal to working precision.
                if gamma == 0.0 || gamma.abs() <= 1e-15 * (alpha * beta).sqrt() {
                    continue;
                }
                rotated = true;
                let zeta = (beta - alpha) / (2.0 * gamma);
                let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = c * t;
                rotate(&mut u, m, j, k, c, s);
                rotate(&mut v, p, j, k, c, s);
            }
        }
        if !rotated {
            break;
        }
    }
    let norms: Vec<f64> = (0..p)
        .map(|j| {
            u[j * m..(j + 1) * m]
                .iter()
                .map(|x| x * x)
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let mut order: Vec<usize> = (0..p).collect();
    order.sort_by(|&a, &b| norms[b].total_cmp(&norms[a]));
    let s = order.iter().map(|&k| norms[k]).collect();
    let mut vs = vec![0.0; p * p];
    for (dst, &src) in order.iter().enumerate() {
        vs[dst * p..(dst + 1) * p].copy_from_slice(&v[src * p..(src + 1) * p]);
    }
    Svd { s, v: vs }
}

fn rotate(a: &mut [f64], m: usize, j: usize, k: usize, c: f64, s: f64) {
    let (left, right) = a.split_at_mut(k * m);
    let cj = &mut left[j * m..(j + 1) * m];
    let ck = &mut right[..m];
    for (x, y) in cj.iter_mut().zip(ck.iter_mut()) {
        let (a, b) = (*x, *y);
        *x = c * a - s * b;
        *y = s * a + c * b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_singular_values_and_rank_deficiency() {
        // Columns (1,1,0), (1,-1,0), (2,0,0): the third is the sum of the first two.
        let a = [1.0, 1.0, 0.0, 1.0, -1.0, 0.0, 2.0, 0.0, 0.0];
        let r = svd(&a, 3, 3);
        // A A^T = diag(6, 2, 0) in this basis: singular values sqrt(6), sqrt(2), 0.
        assert!((r.s[0] - 6f64.sqrt()).abs() < 1e-14, "{:?}", r.s);
        assert!((r.s[1] - 2f64.sqrt()).abs() < 1e-14, "{:?}", r.s);
        assert!(r.s[2] < 1e-15, "{:?}", r.s);
        // The null vector is proportional to (1, 1, -1).
        let nv = &r.v[6..9];
        assert!((nv[0] - nv[1]).abs() < 1e-14 && (nv[0] + nv[2]).abs() < 1e-14);
        // A graded matrix keeps its tiny singular value (J^T J would lose it).
        let g = [1.0, 0.0, 0.0, 1e-10];
        let r = svd(&g, 2, 2);
        assert!((r.s[1] - 1e-10).abs() < 1e-24);
    }
}
