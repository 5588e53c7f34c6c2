//! Uncertainty of ERT: bootstrap over trials and COCO's simulated restarts, both seeded.

use rand::{RngExt, SeedableRng};

use super::rtd::Outcome;

/// ERT bootstrap by resampling trials: (standard deviation, p10, p50, p90). Resamples without
/// success are skipped; all `None` when fewer than 2 resamples had one.
pub fn bootstrap_ert(
    outcomes: &[Outcome],
    resamples: usize,
    seed: u64,
) -> (Option<f64>, Option<f64>, Option<f64>, Option<f64>) {
    let n = outcomes.len();
    if n == 0 || outcomes.iter().all(|o| o.success.is_none()) {
        return (None, None, None, None);
    }
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    let mut erts = Vec::with_capacity(resamples);
    for _ in 0..resamples {
        let (mut spent, mut succ) = (0.0, 0usize);
        for _ in 0..n {
            let o = &outcomes[rng.random_range(0..n)];
            spent += o.spent;
            succ += usize::from(o.success.is_some());
        }
        if succ > 0 {
            erts.push(spent / succ as f64);
        }
    }
    if erts.len() < 2 {
        return (None, None, None, None);
    }
    erts.sort_by(f64::total_cmp);
    let mean = erts.iter().sum::<f64>() / erts.len() as f64;
    let var = erts.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (erts.len() - 1) as f64;
    (
        Some(var.sqrt()),
        Some(sorted_percentile(&erts, 0.10)),
        Some(sorted_percentile(&erts, 0.50)),
        Some(sorted_percentile(&erts, 0.90)),
    )
}

/// COCO's simulated restarts: percentiles (10, 50, 90) of the run time of "restart until a
/// success" built by drawing runs with replacement.
pub fn simulated_restarts(outcomes: &[Outcome], resamples: usize, seed: u64) -> Option<[f64; 3]> {
    let n = outcomes.len();
    if n == 0 || outcomes.iter().all(|o| o.success.is_none()) || resamples == 0 {
        return None;
    }
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    let mut totals = Vec::with_capacity(resamples);
    for _ in 0..resamples {
        let mut total = 0.0;
        loop {
            let o = &outcomes[rng.random_range(0..n)];
            total += o.spent;
            if o.success.is_some() {
                break;
            }
        }
        totals.push(total);
    }
    totals.sort_by(f64::total_cmp);
    Some([
        sorted_percentile(&totals, 0.10),
        sorted_percentile(&totals, 0.50),
        sorted_percentile(&totals, 0.90),
    ])
}

/// Inverse-ECDF percentile of sorted finite values (Hyndman-Fan type 1).
fn sorted_percentile(sorted: &[f64], p: f64) -> f64 {
    let k = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}
