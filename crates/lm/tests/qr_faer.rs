//! Differential test of the hand-written QR factorisations (`householder_qr`, the in-place one
//! of small problems, and `tall_qr`, the blocked one of tall Jacobians) against faer's
//! `qr_in_place`: `R` up to row signs, least-squares solutions, and the singularity
//! test the solver applies to `R`'s diagonal, on random, ill-conditioned and rank-deficient
//! tall-thin matrices at the sizes the searches use.

mod faer_ref;

use bounded_lm::qr::{householder_qr, tall_qr, tall_qr_scratch_len};
use faer_ref::{FaerQr, Rng};

/// The solver's relative pivot threshold for a Gauss-Newton step (`QR_RANK_TOL` in solver.rs).
const QR_RANK_TOL: f64 = 1e-13;

/// `R` (`p x p`) and `c` from each implementation, for `A S` and `rhs`.
struct Factors {
    inplace: (Vec<f64>, Vec<f64>),
    tall: (Vec<f64>, Vec<f64>),
    faer: (Vec<f64>, Vec<f64>),
}

fn factor_all(a: &[f64], m: usize, p: usize, scale: &[f64], rhs: &[f64]) -> Factors {
    let mut qr: Vec<f64> = (0..m * p)
        .map(|k| {
            if scale[k / m] == 0.0 {
                0.0
            } else {
                a[k] * scale[k / m]
            }
        })
        .collect();
    let mut rq = rhs.to_vec();
    householder_qr(&mut qr, m, p, &mut rq);
    for j in 0..p {
        for i in j + 1..m {
            assert_eq!(qr[j * m + i], 0.0, "householder_qr leaves zeros below R");
        }
    }
    let r0: Vec<f64> = (0..p * p)
        .map(|k| {
            let (j, i) = (k / p, k % p);
            if i <= j && i < m { qr[j * m + i] } else { 0.0 }
        })
        .collect();
    let inplace = (r0, rq[..p].to_vec());
    let (mut r1, mut c1) = (vec![f64::NAN; p * p], vec![f64::NAN; p]);
    let mut scratch = vec![f64::NAN; tall_qr_scratch_len(p)];
    tall_qr(a, m, p, scale, rhs, &mut r1, &mut c1, &mut scratch);
    let (mut r2, mut c2) = (vec![0.0; p * p], vec![0.0; p]);
    FaerQr::new(m, p).factor(a, scale, rhs, &mut r2, &mut c2);
    Factors {
        inplace,
        tall: (r1, c1),
        faer: (r2, c2),
    }
}

/// Flips rows (and `c`) so that `R`'s diagonal is non-negative: `R` is unique up to row signs.
fn normalised((r, c): &(Vec<f64>, Vec<f64>), p: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut r, mut c) = (r.clone(), c.clone());
    for i in 0..p {
        if r[i * p + i] < 0.0 {
            for j in i..p {
                r[j * p + i] = -r[j * p + i];
            }
            c[i] = -c[i];
        }
    }
    (r, c)
}

fn max_abs_diff(x: &[f64], y: &[f64]) -> f64 {
    x.iter()
        .zip(y)
        .fold(0.0f64, |a, (u, v)| a.max((u - v).abs()))
}

fn frobenius(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Least-squares solution `R^-1 c` (back substitution).
fn solve(r: &[f64], c: &[f64], p: usize) -> Vec<f64> {
    let mut x = c.to_vec();
    for j in (0..p).rev() {
        x[j] /= r[j * p + j];
        for i in 0..j {
            x[i] -= r[j * p + i] * x[j];
        }
    }
    x
}

/// The solver's singularity test: some `|R_ii|` at or below `QR_RANK_TOL` times the largest.
fn singular(r: &[f64], p: usize) -> bool {
    let dmax = (0..p).fold(0.0f64, |a, i| a.max(r[i * p + i].abs()));
    !(dmax > 0.0 && (0..p).all(|i| r[i * p + i].abs() > QR_RANK_TOL * dmax))
}

/// `R` of each hand-written QR equals faer's up to row signs, within `tol * ||A S||_F`.
fn assert_r_matches(f: &Factors, p: usize, norm_a: f64, tol: f64, what: &str) {
    let faer = normalised(&f.faer, p);
    for (name, mine) in [("householder_qr", &f.inplace), ("tall_qr", &f.tall)] {
        let mine = normalised(mine, p);
        let dr = max_abs_diff(&mine.0, &faer.0);
        let dc = max_abs_diff(&mine.1, &faer.1);
        assert!(
            dr <= tol * norm_a,
            "{what}: {name} R differs from faer's by {dr:e}"
        );
        assert!(
            dc <= tol * norm_a.max(1.0),
            "{what}: {name} Q^T r differs by {dc:e}"
        );
    }
}

/// `R^T R` and `R^T c` of each hand-written QR equal faer's within `1e-13 ||A S||_F^2` (and
/// `||A S||_F ||c||`).
fn assert_gram_matches(f: &Factors, p: usize, norm_a: f64, what: &str) {
    let gram = |(r, c): &(Vec<f64>, Vec<f64>)| {
        let mut g = vec![0.0; p * p + p];
        for i in 0..p {
            for j in 0..p {
                g[i * p + j] = (0..p).map(|k| r[i * p + k] * r[j * p + k]).sum();
            }
            g[p * p + i] = (0..p).map(|k| r[i * p + k] * c[k]).sum();
        }
        g
    };
    let reference = gram(&f.faer);
    let scale_c = frobenius(&f.faer.1).max(1.0);
    for (name, mine) in [("householder_qr", &f.inplace), ("tall_qr", &f.tall)] {
        let g = gram(mine);
        let dg = max_abs_diff(&g[..p * p], &reference[..p * p]);
        let dc = max_abs_diff(&g[p * p..], &reference[p * p..]);
        assert!(
            dg <= 1e-13 * norm_a * norm_a,
            "{what}: {name} R^T R differs by {dg:e}"
        );
        assert!(
            dc <= 1e-13 * norm_a * scale_c,
            "{what}: {name} R^T c differs by {dc:e}"
        );
    }
}

fn scaled_norm(a: &[f64], m: usize, scale: &[f64]) -> f64 {
    let v: Vec<f64> = a
        .iter()
        .enumerate()
        .map(|(k, x)| x * scale[k / m])
        .collect();
    frobenius(&v)
}

const SIZES: [(usize, usize); 10] = [
    (25, 3),
    (25, 7),
    (25, 13),
    (129, 7),
    (257, 30),
    (400, 7),
    (1000, 13),
    (2049, 16),
    (10_000, 7),
    (10_000, 13),
];

#[test]
fn random_matrices_match_faer() {
    let mut rng = Rng(7);
    for (m, p) in SIZES {
        let a = rng.fill(m * p);
        let x_true = rng.fill(p);
        // A consistent right-hand side plus a residual, so the solution is known.
        let rhs: Vec<f64> = (0..m)
            .map(|i| (0..p).map(|j| a[j * m + i] * x_true[j]).sum::<f64>() + 1e-3 * rng.next())
            .collect();
        let scale: Vec<f64> = (0..p).map(|j| 0.5 + j as f64).collect();
        let f = factor_all(&a, m, p, &scale, &rhs);
        let norm_a = scaled_norm(&a, m, &scale);
        assert_r_matches(&f, p, norm_a, 1e-13, &format!("random {m}x{p}"));
        let xf = solve(&normalised(&f.faer, p).0, &normalised(&f.faer, p).1, p);
        for (name, mine) in [("householder_qr", &f.inplace), ("tall_qr", &f.tall)] {
            let x = solve(&mine.0, &mine.1, p);
            let dx = max_abs_diff(&x, &xf) / frobenius(&xf);
            assert!(
                dx < 1e-12,
                "random {m}x{p}: {name} solution differs by {dx:e}"
            );
            assert!(
                !singular(&mine.0, p),
                "random {m}x{p}: {name} called singular"
            );
        }
        assert!(!singular(&f.faer.0, p));
    }
}

/// Columns `exp(-k_j t)` with rates close together: the Jacobian of a sum of exponentials, whose
/// condition number grows quickly with the number of columns.
fn exponential_columns(m: usize, p: usize) -> Vec<f64> {
    let mut a = vec![0.0; m * p];
    for j in 0..p {
        let k = 1.0 + 0.1 * j as f64;
        for i in 0..m {
            let t = 4.0 * i as f64 / m as f64;
            a[j * m + i] = (-k * t).exp();
        }
    }
    a
}

#[test]
fn ill_conditioned_matrices_match_faer() {
    for (m, p) in [(25, 7), (400, 7), (10_000, 7), (10_000, 9)] {
        let a = exponential_columns(m, p);
        let x_true: Vec<f64> = (0..p).map(|j| 1.0 + j as f64).collect();
        let rhs: Vec<f64> = (0..m)
            .map(|i| (0..p).map(|j| a[j * m + i] * x_true[j]).sum())
            .collect();
        let scale = vec![1.0; p];
        let f = factor_all(&a, m, p, &scale, &rhs);
        let norm_a = scaled_norm(&a, m, &scale);
        // R itself is backward stable whatever the conditioning.
        assert_r_matches(&f, p, norm_a, 1e-12, &format!("ill-conditioned {m}x{p}"));
        let rf = normalised(&f.faer, p).0;
        let dmax = (0..p).fold(0.0f64, |a, i| a.max(rf[i * p + i].abs()));
        let dmin = (0..p).fold(f64::INFINITY, |a, i| a.min(rf[i * p + i].abs()));
        let cond = dmax / dmin;
        eprintln!("ill-conditioned {m}x{p}: diagonal ratio {cond:.2e}");
        assert!(
            cond > 1e6,
            "ill-conditioned {m}x{p}: diagonal ratio only {cond:e}"
        );
        for (name, mine) in [
            ("householder_qr", &f.inplace),
            ("tall_qr", &f.tall),
            ("faer", &f.faer),
        ] {
            let x = solve(&mine.0, &mine.1, p);
            let dx = max_abs_diff(&x, &x_true) / frobenius(&x_true);
            // Forward error of a backward-stable solve: about cond * eps.
            assert!(
                dx < 1e3 * cond * f64::EPSILON,
                "ill-conditioned {m}x{p} (ratio {cond:.1e}): {name} solution error {dx:e}"
            );
        }
    }
}

#[test]
fn dead_and_dependent_columns_are_singular_for_all() {
    let mut rng = Rng(11);
    for (m, p) in [(25, 7), (400, 7), (10_000, 7), (10_000, 13)] {
        let mut a = rng.fill(m * p);
        // Column 2 is dead (the solver zeroes it: scale 0, whatever the Jacobian holds there).
        let mut scale = vec![1.0; p];
        scale[2] = 0.0;
        let rhs = rng.fill(m);
        let f = factor_all(&a, m, p, &scale, &rhs);
        for (name, mine) in [("householder_qr", &f.inplace), ("tall_qr", &f.tall)] {
            assert_eq!(
                mine.0[2 * p + 2],
                0.0,
                "{m}x{p}: {name} dead column's R_22 not 0"
            );
            assert!(
                singular(&mine.0, p),
                "{m}x{p}: {name} missed the dead column"
            );
        }
        assert!(
            singular(&f.faer.0, p),
            "{m}x{p}: faer missed the dead column"
        );
        // With a zero column R is not unique past it (the reflector there is arbitrary), but
        // R^T R = S A^T A S and R^T c = S A^T rhs are.
        assert_gram_matches(&f, p, scaled_norm(&a, m, &scale), &format!("dead {m}x{p}"));
        // Column 4 = column 1 plus a perturbation far below the rank tolerance.
        scale[2] = 1.0;
        for i in 0..m {
            a[4 * m + i] = a[m + i] * (1.0 + 1e-16 * rng.next());
        }
        let f = factor_all(&a, m, p, &scale, &rhs);
        for (name, mine) in [
            ("householder_qr", &f.inplace),
            ("tall_qr", &f.tall),
            ("faer", &f.faer),
        ] {
            assert!(
                singular(&mine.0, p),
                "{m}x{p}: {name} missed the dependent column"
            );
        }
        // The same column perturbed well above it is full rank for all three.
        for i in 0..m {
            a[4 * m + i] = a[m + i] + 1e-6 * rng.next();
        }
        let f = factor_all(&a, m, p, &scale, &rhs);
        for (name, mine) in [
            ("householder_qr", &f.inplace),
            ("tall_qr", &f.tall),
            ("faer", &f.faer),
        ] {
            assert!(
                !singular(&mine.0, p),
                "{m}x{p}: {name} called a full-rank R singular"
            );
        }
    }
}

#[test]
fn tiny_and_huge_columns_do_not_overflow() {
    // Squares of 1e-170 underflow and of 1e170 overflow: both QRs rescale such columns.
    let (m, p) = (1000, 4);
    let mut rng = Rng(3);
    let mut a = rng.fill(m * p);
    for v in &mut a[..m] {
        *v *= 1e-170;
    }
    for v in &mut a[2 * m..3 * m] {
        *v *= 1e170;
    }
    let rhs = rng.fill(m);
    let scale = vec![1.0; p];
    let f = factor_all(&a, m, p, &scale, &rhs);
    for (name, mine) in [("householder_qr", &f.inplace), ("tall_qr", &f.tall)] {
        assert!(
            mine.0.iter().chain(&mine.1).all(|v| v.is_finite()),
            "{name} not finite"
        );
        for j in 0..p {
            let norm = safe_norm(&a[j * m..(j + 1) * m]);
            let d = mine.0[j * p + j].abs();
            // |R_jj| <= ||a_j||, and |R_00| is the first column's norm.
            assert!(
                d <= norm * (1.0 + 1e-12) && d > 0.0,
                "{name}: |R_{j}{j}| = {d:e}, norm {norm:e}"
            );
        }
        let r00 = mine.0[0].abs();
        let n0 = safe_norm(&a[..m]);
        assert!(
            (r00 - n0).abs() <= 1e-12 * n0,
            "{name}: R_00 = {r00:e}, expected {n0:e}"
        );
    }
}

/// 2-norm without under- or overflow (scaled by the max-abs entry).
fn safe_norm(x: &[f64]) -> f64 {
    let amax = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    amax * frobenius(&x.iter().map(|v| v / amax).collect::<Vec<_>>())
}
