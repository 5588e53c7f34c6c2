//! The two-sided Mann-Whitney U test, computed as scipy's `mannwhitneyu(method="auto")` does.
//!
//! - **Exact** when there are no ties and one sample has at most [`MW_EXACT_MAX_N`] values
//!   (and the counts fit in memory and in `u128`, true up to about 100,000 values):
//!   the number of interleavings with each U is a coefficient of the Gaussian binomial
//!   `[m + n choose k]_q`, counted in exact integers; the p-value is `2 P(U >= max(U_a, U_b))`.
//! - **Asymptotic** otherwise: the normal approximation with the tie correction and the
//!   continuity correction, `p = 2 sf(z)`, `z = (max(U_a, U_b) - mn/2 - 1/2) / s`,
//!   `s^2 = mn/12 ((N + 1) - sum(t^3 - t) / (N (N - 1)))` over groups of `t` tied values.
//!   The tail is `erfc(z / sqrt 2) / 2`, never `1 - cdf`, so it keeps its relative accuracy
//!   down to about 1e-300 instead of becoming 0 below 1e-16.
//!
//! Both p-values are clamped to [0, 1].

/// With no ties and a sample of at most this many values the p-value is exact (scipy's rule).
pub const MW_EXACT_MAX_N: usize = 8;

/// The exact distribution holds `k n + 1` counts; above this many the normal approximation is
/// used instead (scipy has no such bound; it only matters past a million values).
const MW_EXACT_MAX_COUNTS: usize = 10_000_000;

/// Two-sided Mann-Whitney U (statistic of `a`, p-value in [0, 1]); `None` for an empty
/// sample or a NaN value. See the module documentation for the p-value.
pub fn mann_whitney(a: &[f64], b: &[f64]) -> Option<(f64, f64)> {
    if a.is_empty() || b.is_empty() || a.iter().chain(b).any(|x| x.is_nan()) {
        return None;
    }
    let (m, n) = (a.len(), b.len());
    let ranks = Ranks::of(a, b);
    let u_a = ranks.sum_a - (m * (m + 1)) as f64 / 2.0;
    let u_max = u_a.max((m * n) as f64 - u_a);
    let exact = m.min(n) <= MW_EXACT_MAX_N && !ranks.has_ties();
    let p = match exact.then(|| exact_sf(u_max, m, n)).flatten() {
        Some(sf) => 2.0 * sf,
        None => 2.0 * normal_sf(u_max, m, n, ranks.tie_term),
    };
    Some((u_a, p.clamp(0.0, 1.0)))
}

/// Mid-ranks of the pooled samples: the rank sum of `a` and the tie term `sum(t^3 - t)`.
struct Ranks {
    sum_a: f64,
    tie_term: f64,
}

impl Ranks {
    fn of(a: &[f64], b: &[f64]) -> Ranks {
        let mut pooled: Vec<(f64, bool)> = a
            .iter()
            .map(|&x| (x, true))
            .chain(b.iter().map(|&x| (x, false)))
            .collect();
        pooled.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (mut sum_a, mut tie_term, mut start) = (0.0, 0.0, 0);
        while start < pooled.len() {
            let end = start
                + pooled[start..]
                    .iter()
                    .take_while(|v| v.0 == pooled[start].0)
                    .count();
            let t = (end - start) as f64;
            // Ranks start + 1 ..= end share their mean.
            let mid_rank = (start + 1 + end) as f64 / 2.0;
            let in_a = pooled[start..end].iter().filter(|v| v.1).count() as f64;
            sum_a += in_a * mid_rank;
            tie_term += t * t * t - t;
            start = end;
        }
        Ranks { sum_a, tie_term }
    }

    fn has_ties(&self) -> bool {
        self.tie_term > 0.0
    }
}

/// Upper tail of the normal approximation (tie and continuity corrected) at `u`.
fn normal_sf(u: f64, m: usize, n: usize, tie_term: f64) -> f64 {
    let (mf, nf) = (m as f64, n as f64);
    let total = mf + nf;
    let sd = (mf * nf / 12.0 * ((total + 1.0) - tie_term / (total * (total - 1.0)))).sqrt();
    let z = (u - mf * nf / 2.0 - 0.5) / sd;
    // sd = 0 (every value tied) gives z = -inf and a p-value of 1, as scipy's.
    0.5 * libm::erfc(z / std::f64::consts::SQRT_2)
}

/// Exact `P(U >= u)` for samples of `m` and `n` distinct values; `None` when there would be
/// more than [`MW_EXACT_MAX_COUNTS`] counts or they overflow `u128`.
fn exact_sf(u: f64, m: usize, n: usize) -> Option<f64> {
    let (k, big) = (m.min(n), m.max(n));
    if k.saturating_mul(big) > MW_EXACT_MAX_COUNTS {
        return None;
    }
    let counts = u_counts(k, big)?;
    let total: u128 = counts.iter().try_fold(0u128, |s, &c| s.checked_add(c))?;
    let from = u.ceil().max(0.0) as usize;
    let tail: u128 = counts.iter().skip(from).sum();
    Some(tail as f64 / total as f64)
}

/// The number of interleavings of `k` and `n` distinct values with each U = 0 ..= kn: the
/// coefficients of the Gaussian binomial `prod_{i=1..k} (1 - q^(n+i)) / (1 - q^i)`, built one
/// factor at a time (each partial product is again a polynomial with integer coefficients).
fn u_counts(k: usize, n: usize) -> Option<Vec<u128>> {
    let mut poly: Vec<i128> = vec![1];
    for i in 1..=k {
        let degree = i * n;
        let mut next = vec![0i128; degree + 1];
        for (d, &c) in poly.iter().enumerate() {
            next[d] = next[d].checked_add(c)?;
            if let Some(slot) = next.get_mut(d + n + i) {
                *slot = slot.checked_sub(c)?;
            }
        }
        // Dividing by (1 - q^i): c[d] += c[d - i], exact because the quotient is a polynomial.
        for d in i..=degree {
            next[d] = next[d].checked_add(next[d - i])?;
        }
        poly = next;
    }
    poly.into_iter().map(|c| u128::try_from(c).ok()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_close(got: f64, want: f64, rel: f64, what: &str) {
        assert!(
            (got - want).abs() <= rel * want.abs(),
            "{what}: got {got:e}, want {want:e}"
        );
    }

    /// `a` = 0, 0, 1, 1, ..., n-1, n-1 (every value twice); `b` the same shifted by `s`, its
    /// last `c` values censored at `+inf`.
    fn tied(n: usize, s: f64, c: usize) -> (Vec<f64>, Vec<f64>) {
        let a = (0..2 * n).map(|i| (i / 2) as f64).collect();
        let b = (0..2 * n - c)
            .map(|i| (i / 2) as f64 + s)
            .chain(std::iter::repeat_n(f64::INFINITY, c))
            .collect();
        (a, b)
    }

    /// References from scipy 1.17.1: `scipy.stats.mannwhitneyu(a, b, method="auto")` (the
    /// normal approximation with tie and continuity corrections: the samples have ties).
    #[test]
    fn normal_approximation_agrees_with_scipy_down_to_tiny_p_values() {
        let cases = [
            (30, 3.0, 0, 1458.0, 0.07292981072341169),
            (60, 40.0, 10, 800.0, 1.167487222031033e-32),
            (150, 120.0, 50, 1800.0, 4.320695624745271e-92),
            (300, 250.0, 100, 5000.0, 5.728493148655283e-187),
            (400, 400.0, 200, 0.0, 2.7460820400976397e-263),
        ];
        for (n, s, c, u_want, p_want) in cases {
            let (a, b) = tied(n, s, c);
            let (u, p) = mann_whitney(&a, &b).unwrap();
            let what = format!("n={n} s={s} c={c}");
            assert_eq!(u, u_want, "{what}");
            assert_close(p, p_want, 1e-12, &what);
        }
    }

    /// References from scipy 1.17.1: `scipy.stats.mannwhitneyu(a, b, method="auto")` with
    /// `a = 0..m`, `b = 0..n` minus `shift` (no ties, one sample of at most 8: exact).
    #[test]
    fn exact_distribution_agrees_with_scipy() {
        let cases = [
            (5, 9, 0.5, 15.0, 0.36363636363636365),
            (8, 40, 20.5, 196.0, 0.33269512307219773),
            (3, 200, 150.5, 456.0, 0.12975895045573965),
            (8, 700, 600.5, 4836.0, 0.00011481940180083975),
        ];
        for (m, n, shift, u_want, p_want) in cases {
            let a: Vec<f64> = (0..m).map(f64::from).collect();
            let b: Vec<f64> = (0..n).map(|j| f64::from(j) - shift).collect();
            let (u, p) = mann_whitney(&a, &b).unwrap();
            let what = format!("m={m} n={n}");
            assert_eq!(u, u_want, "{what}");
            assert_close(p, p_want, 1e-12, &what);
        }
        // SciPy's documented example (Conover): U = 17, exact two-sided p = 1/9.
        let male = [19.0, 22.0, 16.0, 29.0, 24.0];
        let female = [20.0, 11.0, 17.0, 12.0];
        let (u, p) = mann_whitney(&male, &female).unwrap();
        assert_eq!(u, 17.0);
        assert_close(p, 1.0 / 9.0, 1e-14, "Conover");
    }

    /// `1 - Phi(z)` was exactly 0 for z > 8.3; the tail stays positive and falls as the
    /// samples separate, within [0, 1].
    #[test]
    fn p_values_stay_positive_in_unit_interval_and_fall_with_separation() {
        let mut last = 1.0;
        for shift in 0..=120 {
            let (a, b) = tied(100, f64::from(shift), 20);
            let (_, p) = mann_whitney(&a, &b).unwrap();
            assert!(p > 0.0 && p <= 1.0, "shift {shift}: p = {p:e}");
            assert!(p <= last, "shift {shift}: {last:e} -> {p:e}");
            last = p;
        }
        assert!(last < 1e-60, "{last:e}");
    }

    /// Counts that would overflow `u128` (8 values against 300,000: C(300008, 8) > 2^128)
    /// fall back to the normal approximation instead of failing.
    #[test]
    fn exact_counts_that_overflow_fall_back_to_the_normal_tail() {
        assert!(exact_sf(1.0, 8, 300_000).is_none());
        let a: Vec<f64> = (0..8).map(|i| f64::from(i) * 1000.0 + 0.5).collect();
        let b: Vec<f64> = (0..300_000).map(f64::from).collect();
        let (_, p) = mann_whitney(&a, &b).unwrap();
        // U of a: sum over i of the 1000 i + 1 values of b below a_i.
        let u_a: f64 = 28_008.0;
        let u_max = (8.0 * 300_000.0 - u_a).max(u_a);
        assert_eq!(p, 2.0 * normal_sf(u_max, 8, 300_000, 0.0));
    }

    #[test]
    fn degenerate_samples() {
        assert_eq!(mann_whitney(&[], &[1.0]), None);
        assert_eq!(mann_whitney(&[f64::NAN], &[1.0]), None);
        // Every value tied (all censored): no evidence, p = 1.
        let inf = [f64::INFINITY; 30];
        assert_eq!(mann_whitney(&inf, &inf), Some((450.0, 1.0)));
        // Censored runs as +inf: all of b is slower.
        let (u, _) = mann_whitney(&[1.0, 2.0, 3.0], &[4.0, f64::INFINITY, f64::INFINITY]).unwrap();
        assert_eq!(u, 0.0);
    }
}
