//! Run-time distributions: outcomes of trials for a target, the Kaplan-Meier RTD, its
//! quantiles, ERT and probabilistic domination (conventions in the [`super`] docs).

use serde::{Deserialize, Serialize};

use brdf_experiment::store::TrialRecord;

/// How run time is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// CPU seconds of the worker thread.
    CpuSeconds,
    /// Sample-evaluations (residual + Jacobian + RMSE rows).
    Evaluations,
}

impl Measure {
    /// Both measures, CPU first.
    pub const ALL: [Measure; 2] = [Measure::CpuSeconds, Measure::Evaluations];

    /// Reads this measure from a stamp.
    pub fn of(self, stamp: &sls::Stamp) -> f64 {
        match self {
            Measure::CpuSeconds => stamp.cpu_seconds,
            Measure::Evaluations => stamp.evaluations.total() as f64,
        }
    }

    /// Axis label.
    pub fn label(self) -> &'static str {
        match self {
            Measure::CpuSeconds => "CPU seconds",
            Measure::Evaluations => "sample-evaluations",
        }
    }

    /// Short name for file names and CSV.
    pub fn short(self) -> &'static str {
        match self {
            Measure::CpuSeconds => "cpu",
            Measure::Evaluations => "evals",
        }
    }
}

/// One run seen for one target and measure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Run time to target, if reached.
    pub success: Option<f64>,
    /// Time the run spent in total (success time, or where it was censored).
    pub spent: f64,
}

impl Outcome {
    /// Run time with censored runs coded as +inf (for rank tests).
    pub fn time_or_inf(&self) -> f64 {
        self.success.unwrap_or(f64::INFINITY)
    }
}

/// The outcome of one stored trial for `target` in `measure`.
pub fn outcome(record: &TrialRecord, target: f64, measure: Measure) -> Outcome {
    let r = &record.result;
    let hit = r.first_reaching(target).or_else(|| {
        // The trace should always hold the reaching point; fall back to reached_at for the
        // run's own target so a trial without trace still counts.
        r.reached_at.filter(|_| target >= record.target)
    });
    match hit {
        Some(s) => {
            let t = measure.of(&s);
            Outcome {
                success: Some(t),
                spent: t,
            }
        }
        None => Outcome {
            success: None,
            spent: measure.of(&r.ended_at),
        },
    }
}

/// Expected run time with restarts: total time spent / successes (+inf without successes).
pub fn ert(outcomes: &[Outcome]) -> f64 {
    let successes = outcomes.iter().filter(|o| o.success.is_some()).count();
    if successes == 0 {
        return f64::INFINITY;
    }
    outcomes.iter().map(|o| o.spent).sum::<f64>() / successes as f64
}

/// Kaplan-Meier estimate of the CDF of time-to-target: `(time, F(time))` after each distinct
/// success time, in increasing time. Censored runs leave the risk set at their censoring time
/// (a run censored at exactly a success time counts as still at risk then).
pub fn kaplan_meier(outcomes: &[Outcome]) -> Vec<(f64, f64)> {
    kaplan_meier_band(outcomes)
        .into_iter()
        .map(|(t, f, _, _)| (t, f))
        .collect()
}

/// [`kaplan_meier`] with a pointwise 95% confidence band: `(time, F, lo, hi)`, Greenwood's
/// variance `S^2 sum d_j / (n_j (n_j - d_j))` of the survival `S = 1 - F`, as `F +- 1.96 sd`
/// clamped to [0, 1] (the binomial interval's normal approximation when all runs share one
/// cutoff).
pub fn kaplan_meier_band(outcomes: &[Outcome]) -> Vec<(f64, f64, f64, f64)> {
    let mut events: Vec<(f64, bool)> = outcomes
        .iter()
        .map(|o| match o.success {
            Some(t) => (t, true),
            None => (o.spent, false),
        })
        .collect();
    // Successes before censorings at equal times (standard KM convention).
    events.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
    let mut at_risk = events.len() as f64;
    let mut survival = 1.0;
    let mut greenwood = 0.0;
    let mut curve = Vec::new();
    let mut i = 0;
    while i < events.len() {
        let t = events[i].0;
        let mut deaths = 0.0;
        let mut censored = 0.0;
        while i < events.len() && events[i].0 == t {
            if events[i].1 {
                deaths += 1.0;
            } else {
                censored += 1.0;
            }
            i += 1;
        }
        if deaths > 0.0 {
            survival *= 1.0 - deaths / at_risk;
            if at_risk > deaths {
                greenwood += deaths / (at_risk * (at_risk - deaths));
            }
            let half = 1.96 * survival * greenwood.sqrt();
            let f = 1.0 - survival;
            curve.push((t, f, (f - half).max(0.0), (f + half).min(1.0)));
        }
        at_risk -= deaths + censored;
    }
    curve
}

/// Value of a step CDF (from [`kaplan_meier`]) at `t`.
pub fn cdf_at(curve: &[(f64, f64)], t: f64) -> f64 {
    curve
        .iter()
        .take_while(|(x, _)| *x <= t)
        .last()
        .map_or(0.0, |p| p.1)
}

/// Smallest time at which the step CDF reaches `p` (`None` if it never does).
pub fn quantile(curve: &[(f64, f64)], p: f64) -> Option<f64> {
    // A small tolerance so that e.g. 5 of 10 runs count as reaching p = 0.5 despite rounding.
    curve.iter().find(|(_, f)| *f >= p - 1e-12).map(|c| c.0)
}

/// Whether censoring times differ in a way that makes KM differ from the plain ECDF.
pub fn censoring_heterogeneous(outcomes: &[Outcome]) -> bool {
    let last_success = outcomes
        .iter()
        .filter_map(|o| o.success)
        .fold(f64::NEG_INFINITY, f64::max);
    outcomes
        .iter()
        .any(|o| o.success.is_none() && o.spent < last_success)
}

/// `Some((a_dominates_b, b_dominates_a))`: probabilistic domination of step CDFs.
pub fn domination(a: &[(f64, f64)], b: &[(f64, f64)]) -> (bool, bool) {
    let mut times: Vec<f64> = a.iter().chain(b).map(|p| p.0).collect();
    times.sort_by(f64::total_cmp);
    let (mut a_ge, mut b_ge, mut a_gt, mut b_gt) = (true, true, false, false);
    for t in times {
        let (fa, fb) = (cdf_at(a, t), cdf_at(b, t));
        if fa < fb - 1e-12 {
            a_ge = false;
            b_gt = true;
        }
        if fb < fa - 1e-12 {
            b_ge = false;
            a_gt = true;
        }
    }
    (a_ge && a_gt, b_ge && b_gt)
}
