//! Pairwise tests of RTDs: Mann-Whitney U and two-sample Kolmogorov-Smirnov (statrs), with
//! Holm's step-down correction over a family of comparisons.

use statrs::stats_tests::ks_test::{KSTwoSampleAlternativeMethod, ks_twosample};
use statrs::stats_tests::mannwhitneyu::{MannWhitneyUMethod, mannwhitneyu};
use statrs::stats_tests::{Alternative, NaNPolicy};

/// Holm's step-down adjustment of p-values (same order as the input).
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut adjusted = vec![0.0; m];
    let mut running: f64 = 0.0;
    for (rank, &i) in order.iter().enumerate() {
        let a = ((m - rank) as f64 * p[i]).min(1.0);
        running = running.max(a);
        adjusted[i] = running;
    }
    adjusted
}

/// Two-sided Mann-Whitney U (statistic of `a`, p-value); `None` for empty samples.
pub fn mann_whitney(a: &[f64], b: &[f64]) -> Option<(f64, f64)> {
    mannwhitneyu(a, b, MannWhitneyUMethod::Automatic, Alternative::TwoSided).ok()
}

/// Below this `D sqrt(mn / (m + n))` the asymptotic two-sided p-value is 1 to within 1e-8
/// (the Kolmogorov distribution's CDF at 0.2 is below 1e-20).
const KS_NEGLIGIBLE_X: f64 = 0.2;

/// The two-sample KS statistic `D = sup |F_a - F_b|` (`+inf` values included, as censored
/// runs are).
pub(super) fn ks_statistic(a: &[f64], b: &[f64]) -> f64 {
    let (mut a, mut b) = (a.to_vec(), b.to_vec());
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < a.len() && j < b.len() {
        let t = if a[i].total_cmp(&b[j]).is_le() {
            a[i]
        } else {
            b[j]
        };
        while i < a.len() && a[i].total_cmp(&t).is_le() {
            i += 1;
        }
        while j < b.len() && b[j].total_cmp(&t).is_le() {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// Two-sample Kolmogorov-Smirnov (statistic D, two-sided p-value); exact for small samples.
pub fn kolmogorov_smirnov(a: &[f64], b: &[f64]) -> Option<(f64, f64)> {
    if a.is_empty() || b.is_empty() {
        return None;
    }
    // statrs 0.19's asymptotic series never terminates at D = 0 (its first term stays 1), which
    // happens whenever two configurations have identical outcomes, e.g. all censored.
    let d = ks_statistic(a, b);
    let (m, n) = (a.len() as f64, b.len() as f64);
    if d * (m * n / (m + n)).sqrt() < KS_NEGLIGIBLE_X {
        return Some((d, 1.0));
    }
    let method = if a.len() <= 100 && b.len() <= 100 {
        KSTwoSampleAlternativeMethod::TwoSidedExact
    } else {
        KSTwoSampleAlternativeMethod::TwoSidedAsymptotic
    };
    ks_twosample(a.to_vec(), b.to_vec(), method, NaNPolicy::Error).ok()
}
