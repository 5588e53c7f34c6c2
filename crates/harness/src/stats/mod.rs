//! Run-time distribution statistics: success rates, quantiles, ERT with bootstrap, pairwise tests.
//!
//! Conventions (see the project's harness notes):
//! - A run *succeeds* for target `q` when its anytime trace first reaches RMSE `<= q`; its
//!   run time is that stamp's CPU seconds (or sample-evaluations). A run that did not reach `q`
//!   is *censored* at the time it ended (normally the cutoff) and stays in every denominator.
//! - The RTD is the Kaplan-Meier estimate of the time-to-target distribution. With one shared
//!   cutoff (every censored run ended after the last success) it equals the plain empirical CDF
//!   over all runs; with different censoring times (a changed or evaluation-based cutoff, runs
//!   that stopped early) it stays unbiased. Quantiles are read from that curve (inverse CDF:
//!   the smallest time at which the curve reaches `p`; `None` = not reached, i.e. +inf).
//! - ERT (expected run time with restarts, COCO's aRT): the time all runs spent (successful runs
//!   up to success, censored runs up to where they stopped) divided by the number of successes;
//!   with a shared cutoff `c` this is `mean success time + (1-p)/p * c`.
//! - ERT uncertainty: the trials are resampled with replacement `bootstrap` times and ERT is
//!   recomputed; the standard deviation (the paper's "± sd") and the 10/50/90 percentiles are
//!   reported. COCO's simulated restarts (draw runs with replacement until a success, summing
//!   their times) give the 10/50/90 percentiles of the restarted run time itself.
//! - Pairwise comparisons per instance and target: Mann-Whitney U (two-sided, censored runs
//!   coded as +inf; statrs) and two-sample Kolmogorov-Smirnov (statrs) with Holm's correction
//!   over all pairs of the (instance, target, measure) family, and probabilistic domination
//!   (one RTD at or above the other everywhere and strictly above somewhere).

use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};
use statrs::statistics::{Data, Distribution, Max, Min, OrderStatistics};
use statrs::stats_tests::ks_test::{KSTwoSampleAlternativeMethod, ks_twosample};
use statrs::stats_tests::mannwhitneyu::{MannWhitneyUMethod, mannwhitneyu};
use statrs::stats_tests::{Alternative, NaNPolicy};

use crate::seed::StableHasher;
use crate::store::TrialRecord;

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
            curve.push((t, 1.0 - survival));
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
fn ks_statistic(a: &[f64], b: &[f64]) -> f64 {
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

/// Summary of one (instance, configuration, target) in one measure.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeasureSummary {
    /// Trials that reached the target.
    pub successes: usize,
    /// Trials in total.
    pub trials: usize,
    /// successes / trials.
    pub success_rate: f64,
    /// 10/25/50/75/90% quantiles of time-to-target from the RTD (`None` = not reached).
    pub quantiles: [Option<f64>; 5],
    /// Expected run time with restarts (`None` = no success).
    pub ert: Option<f64>,
    /// Bootstrap standard deviation of the ERT.
    pub ert_sd: Option<f64>,
    /// Bootstrap 10th percentile of the ERT.
    pub ert_p10: Option<f64>,
    /// Bootstrap median of the ERT.
    pub ert_p50: Option<f64>,
    /// Bootstrap 90th percentile of the ERT.
    pub ert_p90: Option<f64>,
    /// COCO simulated restarts: 10/50/90% of the restarted run time.
    pub restarts: Option<[f64; 3]>,
    /// Whether censoring times differ (Kaplan-Meier then differs from the plain ECDF).
    pub km_censoring: bool,
}

/// Quantile levels reported in [`MeasureSummary::quantiles`].
pub const QUANTILES: [f64; 5] = [0.10, 0.25, 0.50, 0.75, 0.90];

/// Summarises outcomes; `seed` drives the bootstrap.
pub fn summarise(outcomes: &[Outcome], resamples: usize, seed: u64) -> MeasureSummary {
    let successes = outcomes.iter().filter(|o| o.success.is_some()).count();
    let curve = kaplan_meier(outcomes);
    let e = ert(outcomes);
    let (sd, p10, p50, p90) = bootstrap_ert(outcomes, resamples, seed);
    MeasureSummary {
        successes,
        trials: outcomes.len(),
        success_rate: if outcomes.is_empty() {
            0.0
        } else {
            successes as f64 / outcomes.len() as f64
        },
        quantiles: QUANTILES.map(|p| quantile(&curve, p)),
        ert: e.is_finite().then_some(e),
        ert_sd: sd,
        ert_p10: p10,
        ert_p50: p50,
        ert_p90: p90,
        restarts: simulated_restarts(outcomes, resamples, seed ^ 0x5eed),
        km_censoring: censoring_heterogeneous(outcomes),
    }
}

/// Statistics of one (instance, configuration, target).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConfigStats {
    /// Instance name.
    pub instance: String,
    /// Configuration label.
    pub config: String,
    /// Target RMSE.
    pub target: f64,
    /// In CPU seconds.
    pub cpu: MeasureSummary,
    /// In sample-evaluations.
    pub evaluations: MeasureSummary,
}

/// A pairwise comparison of two configurations' RTDs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairTest {
    /// Instance name.
    pub instance: String,
    /// Target RMSE.
    pub target: f64,
    /// Measure compared.
    pub measure: Measure,
    /// First configuration.
    pub a: String,
    /// Second configuration.
    pub b: String,
    /// Mann-Whitney U of `a` (censored = +inf).
    pub mw_u: Option<f64>,
    /// Two-sided Mann-Whitney p-value.
    pub mw_p: Option<f64>,
    /// Holm-adjusted Mann-Whitney p-value.
    pub mw_p_holm: Option<f64>,
    /// Kolmogorov-Smirnov D.
    pub ks_d: Option<f64>,
    /// Two-sided KS p-value.
    pub ks_p: Option<f64>,
    /// Holm-adjusted KS p-value.
    pub ks_p_holm: Option<f64>,
    /// `a`'s RTD is at or above `b`'s everywhere and above somewhere.
    pub a_dominates: bool,
    /// `b`'s RTD is at or above `a`'s everywhere and above somewhere.
    pub b_dominates: bool,
}

/// All statistics of an experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StatsReport {
    /// Bootstrap resamples used.
    pub bootstrap: usize,
    /// Per instance, configuration and target.
    pub configs: Vec<ConfigStats>,
    /// Pairwise tests.
    pub tests: Vec<PairTest>,
    /// Final solution quality per instance and configuration (the paper's Table 5).
    #[serde(default)]
    pub finals: Vec<FinalQuality>,
}

/// The distribution of the best full-data RMSE at the end of each trial, and of the CPU time
/// at which trials ended, for one (instance, configuration). This is what the paper's Table 5
/// reports for DS, whose trials end by themselves (RTOL) rather than on the target.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FinalQuality {
    /// Instance name.
    pub instance: String,
    /// Configuration label.
    pub config: String,
    /// Trials.
    pub trials: usize,
    /// Mean, median, minimum and maximum final RMSE (None without finite values).
    pub rmse_mean: Option<f64>,
    /// Median final RMSE.
    pub rmse_median: Option<f64>,
    /// Minimum final RMSE.
    pub rmse_min: Option<f64>,
    /// Maximum final RMSE.
    pub rmse_max: Option<f64>,
    /// Median CPU seconds at which trials ended (target, budget or the algorithm's own stop).
    pub end_cpu_median: Option<f64>,
    /// Maximum CPU seconds at which a trial ended.
    pub end_cpu_max: Option<f64>,
    /// Trials that ended by themselves (`StopReason::Finished`).
    pub finished: usize,
}

/// Final-quality statistics of one group.
pub fn final_quality(g: &Group<'_>) -> FinalQuality {
    let rmse: Vec<f64> = g
        .records
        .iter()
        .map(|r| r.result.best_rmse)
        .filter(|x| x.is_finite())
        .collect();
    let ends: Vec<f64> = g
        .records
        .iter()
        .map(|r| r.result.ended_at.cpu_seconds)
        .collect();
    // statrs answers NaN for an empty sample; the report says None.
    let some = |x: f64| (!x.is_nan()).then_some(x);
    let (mut rmse, mut ends) = (Data::new(rmse), Data::new(ends));
    FinalQuality {
        instance: g.instance.clone(),
        config: g.config.clone(),
        trials: g.records.len(),
        rmse_mean: rmse.mean().and_then(some),
        rmse_median: some(rmse.median()),
        rmse_min: some(rmse.min()),
        rmse_max: some(rmse.max()),
        end_cpu_median: some(ends.median()),
        end_cpu_max: some(ends.max()),
        finished: g
            .records
            .iter()
            .filter(|r| r.result.stop == sls::StopReason::Finished)
            .count(),
    }
}

/// The final-quality statistics as CSV (one row per instance and configuration).
pub fn finals_csv(report: &StatsReport) -> String {
    let mut s = String::from(
        "instance,config,trials,finished,rmse_mean,rmse_median,rmse_min,rmse_max,end_cpu_median,end_cpu_max\n",
    );
    let f = |v: Option<f64>| v.map_or_else(String::new, |x| format!("{x}"));
    for q in &report.finals {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{}\n",
            csv_field(&q.instance),
            csv_field(&q.config),
            q.trials,
            q.finished,
            f(q.rmse_mean),
            f(q.rmse_median),
            f(q.rmse_min),
            f(q.rmse_max),
            f(q.end_cpu_median),
            f(q.end_cpu_max)
        ));
    }
    s
}

/// A group of trials of one (instance, configuration), sorted by trial index.
#[derive(Clone, Debug)]
pub struct Group<'a> {
    /// Instance name.
    pub instance: String,
    /// Configuration label.
    pub config: String,
    /// The trials.
    pub records: Vec<&'a TrialRecord>,
}

/// Groups records by (instance, configuration) in the given orders; trials sorted by index.
/// Records of instances or configurations not listed are left out.
pub fn group<'a>(
    records: &'a [TrialRecord],
    instances: &[String],
    configs: &[String],
) -> Vec<Group<'a>> {
    let mut groups = Vec::new();
    for inst in instances {
        for cfg in configs {
            let mut recs: Vec<&TrialRecord> = records
                .iter()
                .filter(|r| &r.instance == inst && &r.config == cfg)
                .collect();
            if recs.is_empty() {
                continue;
            }
            recs.sort_by_key(|r| r.trial);
            groups.push(Group {
                instance: inst.clone(),
                config: cfg.clone(),
                records: recs,
            });
        }
    }
    groups
}

/// Outcomes of a group for a target and measure.
pub fn group_outcomes(g: &Group<'_>, target: f64, measure: Measure) -> Vec<Outcome> {
    g.records
        .iter()
        .map(|r| outcome(r, target, measure))
        .collect()
}

/// Computes all statistics. `targets` gives each instance's targets; `seed` the bootstrap seed.
pub fn compute(
    groups: &[Group<'_>],
    targets: &[(String, Vec<f64>)],
    resamples: usize,
    seed: u64,
) -> StatsReport {
    let mut configs = Vec::new();
    let mut tests = Vec::new();
    for (inst, tlist) in targets {
        let gs: Vec<&Group> = groups.iter().filter(|g| &g.instance == inst).collect();
        for &t in tlist {
            for g in &gs {
                let s = |m: Measure| {
                    let bseed = StableHasher::new()
                        .u64(seed)
                        .str(inst)
                        .str(&g.config)
                        .u64(t.to_bits())
                        .str(m.short())
                        .finish();
                    summarise(&group_outcomes(g, t, m), resamples, bseed)
                };
                configs.push(ConfigStats {
                    instance: inst.clone(),
                    config: g.config.clone(),
                    target: t,
                    cpu: s(Measure::CpuSeconds),
                    evaluations: s(Measure::Evaluations),
                });
            }
            for m in Measure::ALL {
                let start = tests.len();
                for i in 0..gs.len() {
                    for j in i + 1..gs.len() {
                        let oa = group_outcomes(gs[i], t, m);
                        let ob = group_outcomes(gs[j], t, m);
                        let a: Vec<f64> = oa.iter().map(Outcome::time_or_inf).collect();
                        let b: Vec<f64> = ob.iter().map(Outcome::time_or_inf).collect();
                        let mw = mann_whitney(&a, &b);
                        let ks = kolmogorov_smirnov(&a, &b);
                        let (ad, bd) = domination(&kaplan_meier(&oa), &kaplan_meier(&ob));
                        tests.push(PairTest {
                            instance: inst.clone(),
                            target: t,
                            measure: m,
                            a: gs[i].config.clone(),
                            b: gs[j].config.clone(),
                            mw_u: mw.map(|x| x.0),
                            mw_p: mw.map(|x| x.1),
                            mw_p_holm: None,
                            ks_d: ks.map(|x| x.0),
                            ks_p: ks.map(|x| x.1),
                            ks_p_holm: None,
                            a_dominates: ad,
                            b_dominates: bd,
                        });
                    }
                }
                adjust_family(&mut tests[start..]);
            }
        }
    }
    StatsReport {
        bootstrap: resamples,
        configs,
        tests,
        finals: groups.iter().map(final_quality).collect(),
    }
}

fn adjust_family(family: &mut [PairTest]) {
    let apply = |get: fn(&PairTest) -> Option<f64>, fam: &[PairTest]| -> Vec<Option<f64>> {
        let idx: Vec<usize> = (0..fam.len()).filter(|&i| get(&fam[i]).is_some()).collect();
        let p: Vec<f64> = idx.iter().filter_map(|&i| get(&fam[i])).collect();
        let adj = holm(&p);
        let mut out = vec![None; fam.len()];
        for (k, &i) in idx.iter().enumerate() {
            out[i] = Some(adj[k]);
        }
        out
    };
    let mw = apply(|t| t.mw_p, family);
    let ks = apply(|t| t.ks_p, family);
    for (i, t) in family.iter_mut().enumerate() {
        t.mw_p_holm = mw[i];
        t.ks_p_holm = ks[i];
    }
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "inf".to_string(), |x| format!("{x}"))
}

/// The per-configuration statistics as CSV (one row per instance, configuration, target, measure).
pub fn configs_csv(report: &StatsReport) -> String {
    let mut s = String::from(
        "instance,config,target,measure,trials,successes,success_rate,q10,q25,q50,q75,q90,ert,ert_sd,ert_p10,ert_p50,ert_p90,restart_p10,restart_p50,restart_p90,km_censoring\n",
    );
    for c in &report.configs {
        for (m, ms) in [
            (Measure::CpuSeconds, &c.cpu),
            (Measure::Evaluations, &c.evaluations),
        ] {
            let q: Vec<String> = ms.quantiles.iter().map(|v| opt(*v)).collect();
            let r = ms.restarts.map_or([None; 3], |r| r.map(Some));
            let fields = [
                csv_field(&c.instance),
                csv_field(&c.config),
                c.target.to_string(),
                m.short().to_string(),
                ms.trials.to_string(),
                ms.successes.to_string(),
                ms.success_rate.to_string(),
                q.join(","),
                opt(ms.ert),
                opt(ms.ert_sd),
                opt(ms.ert_p10),
                opt(ms.ert_p50),
                opt(ms.ert_p90),
                opt(r[0]),
                opt(r[1]),
                opt(r[2]),
                ms.km_censoring.to_string(),
            ];
            s.push_str(&fields.join(","));
            s.push('\n');
        }
    }
    s
}

/// The pairwise tests as CSV.
pub fn tests_csv(report: &StatsReport) -> String {
    let mut s = String::from(
        "instance,target,measure,a,b,mw_u,mw_p,mw_p_holm,ks_d,ks_p,ks_p_holm,a_dominates,b_dominates\n",
    );
    for t in &report.tests {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            csv_field(&t.instance),
            t.target,
            t.measure.short(),
            csv_field(&t.a),
            csv_field(&t.b),
            opt(t.mw_u),
            opt(t.mw_p),
            opt(t.mw_p_holm),
            opt(t.ks_d),
            opt(t.ks_p),
            opt(t.ks_p_holm),
            t.a_dominates,
            t.b_dominates
        ));
    }
    s
}

/// Quotes a CSV field when needed.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Formats a number compactly for tables (`-` for none).
pub fn fmt_num(v: Option<f64>) -> String {
    match v {
        None => "-".into(),
        Some(0.0) => "0".into(),
        Some(x) if x.abs() >= 1e5 => format!("{x:.3e}"),
        Some(x) if x.abs() >= 100.0 => format!("{x:.0}"),
        Some(x) if x.abs() >= 1.0 => format!("{x:.2}"),
        Some(x) if x.abs() < 1e-4 => format!("{x:.2e}"),
        // Three significant digits below 1 (run times of a few milliseconds are common).
        Some(x) => {
            let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
            format!("{x:.decimals$}")
        }
    }
}

/// A plain-text table of the statistics, one block per instance and target.
pub fn table(report: &StatsReport) -> String {
    let mut out = String::new();
    let mut last: Option<(&str, f64)> = None;
    let width = report
        .configs
        .iter()
        .map(|c| c.config.len())
        .max()
        .unwrap_or(6)
        .max(13);
    for c in &report.configs {
        if last != Some((c.instance.as_str(), c.target)) {
            out.push_str(&format!(
                "\n{} - target RMSE {}\n{:<width$}  {:>9}  {:>9} {:>9} {:>9}  {:>9} {:>21}  {:>10} {:>10}\n",
                c.instance,
                c.target,
                "configuration",
                "success",
                "q25 s",
                "median s",
                "q75 s",
                "ERT s",
                "ERT 10-90% s",
                "med evals",
                "ERT evals",
            ));
            last = Some((c.instance.as_str(), c.target));
        }
        let m = &c.cpu;
        let band = match (m.ert_p10, m.ert_p90) {
            (Some(a), Some(b)) => format!("[{}, {}]", fmt_num(Some(a)), fmt_num(Some(b))),
            _ => "-".into(),
        };
        out.push_str(&format!(
            "{:<width$}  {:>9}  {:>9} {:>9} {:>9}  {:>9} {:>21}  {:>10} {:>10}\n",
            c.config,
            format!("{}/{}", m.successes, m.trials),
            fmt_num(m.quantiles[1]),
            fmt_num(m.quantiles[2]),
            fmt_num(m.quantiles[3]),
            fmt_num(m.ert),
            band,
            fmt_num(c.evaluations.quantiles[2]),
            fmt_num(c.evaluations.ert),
        ));
    }
    out.push_str(&finals_table(report, width));
    let sig: Vec<&PairTest> = report
        .tests
        .iter()
        .filter(|t| t.measure == Measure::CpuSeconds)
        .collect();
    if sig.len() > 30 {
        out.push_str(&format!(
            "\n{} pairwise tests (Mann-Whitney, KS, Holm-adjusted): see tests.csv\n",
            sig.len()
        ));
    } else if !sig.is_empty() {
        out.push_str("\nPairwise (CPU time; Holm-adjusted p-values; censored runs = +inf)\n");
        for t in sig {
            let dom = if t.a_dominates {
                format!("{} dominates", t.a)
            } else if t.b_dominates {
                format!("{} dominates", t.b)
            } else {
                "curves cross".into()
            };
            out.push_str(&format!(
                "  {} q={}: {} vs {}: Mann-Whitney p={}, KS p={}, {}\n",
                t.instance,
                t.target,
                t.a,
                t.b,
                fmt_p(t.mw_p_holm),
                fmt_p(t.ks_p_holm),
                dom
            ));
        }
    }
    out
}

fn finals_table(report: &StatsReport, width: usize) -> String {
    let mut out = String::new();
    let mut last: Option<&str> = None;
    for q in &report.finals {
        if last != Some(q.instance.as_str()) {
            out.push_str(&format!(
                "\n{} - final RMSE per trial\n{:<width$}  {:>7}  {:>9} {:>9} {:>9} {:>9}  {:>11} {:>9}\n",
                q.instance, "configuration", "trials", "mean", "median", "min", "max", "median end s", "finished"
            ));
            last = Some(q.instance.as_str());
        }
        let r = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |x| format!("{x:.6}"));
        out.push_str(&format!(
            "{:<width$}  {:>7}  {:>9} {:>9} {:>9} {:>9}  {:>11} {:>9}\n",
            q.config,
            q.trials,
            r(q.rmse_mean),
            r(q.rmse_median),
            r(q.rmse_min),
            r(q.rmse_max),
            fmt_num(q.end_cpu_median),
            q.finished
        ));
    }
    out
}

fn fmt_p(p: Option<f64>) -> String {
    match p {
        None => "-".into(),
        // statrs computes the asymptotic Mann-Whitney p as 1 - Phi(z), which is exactly 0 once
        // z > ~8.3: all that is known then is p < ~1e-15.
        Some(0.0) => "<1e-15".into(),
        Some(p) if p < 1e-4 => format!("{p:.1e}"),
        Some(p) => format!("{p:.4}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn succ(t: f64) -> Outcome {
        Outcome {
            success: Some(t),
            spent: t,
        }
    }
    fn cens(t: f64) -> Outcome {
        Outcome {
            success: None,
            spent: t,
        }
    }

    fn ended(i: u32, best: f64, cpu: f64, stop: sls::StopReason) -> TrialRecord {
        let at = sls::Stamp {
            cpu_seconds: cpu,
            wall_seconds: cpu,
            evaluations: sls::EvalCounts::default(),
        };
        TrialRecord {
            key: TrialRecord::make_key("i", "DS", i),
            instance: "i".into(),
            config: "DS".into(),
            trial: i,
            seed: u64::from(i),
            target: 0.1,
            budget: sls::Budget {
                cpu_seconds: Some(10.0),
                sample_evaluations: None,
            },
            result: sls::TrialResult {
                stop,
                reached_at: None,
                ended_at: at,
                best_rmse: best,
                best_x: vec![],
                trace: vec![],
                counters: vec![],
            },
        }
    }

    #[test]
    fn final_quality_hand_computed() {
        use sls::StopReason::{CpuBudget, Finished};
        let recs = [
            ended(0, 0.75, 1.0, Finished),
            ended(1, 0.25, 4.0, Finished),
            ended(2, f64::INFINITY, 10.0, CpuBudget),
            ended(3, 0.5, 2.0, Finished),
        ];
        let g = Group {
            instance: "i".into(),
            config: "DS".into(),
            records: recs.iter().collect(),
        };
        let q = final_quality(&g);
        // The trial without a finite RMSE counts as a trial but not in the RMSE statistics.
        assert_eq!((q.trials, q.finished), (4, 3));
        assert_eq!(q.rmse_mean, Some(0.5));
        assert_eq!(q.rmse_median, Some(0.5));
        assert_eq!((q.rmse_min, q.rmse_max), (Some(0.25), Some(0.75)));
        assert_eq!(q.end_cpu_median, Some(3.0));
        assert_eq!(q.end_cpu_max, Some(10.0));
        let empty = final_quality(&Group {
            instance: "i".into(),
            config: "DS".into(),
            records: vec![&recs[2]],
        });
        assert_eq!((empty.rmse_mean, empty.rmse_median), (None, None));
        assert_eq!((empty.rmse_min, empty.rmse_max), (None, None));
        assert_eq!(empty.end_cpu_median, Some(10.0));
        let report = StatsReport {
            bootstrap: 0,
            configs: vec![],
            tests: vec![],
            finals: vec![q],
        };
        let csv = finals_csv(&report);
        assert_eq!(csv.lines().nth(1), Some("i,DS,4,3,0.5,0.5,0.25,0.75,3,10"));
        assert!(table(&report).contains("final RMSE per trial"));
    }

    #[test]
    fn ks_identical_samples_terminate_with_p_one() {
        // All censored on both sides (the DS-without-restart case): D = 0.
        let inf = vec![f64::INFINITY; 200];
        assert_eq!(kolmogorov_smirnov(&inf, &inf), Some((0.0, 1.0)));
        let a: Vec<f64> = (0..150).map(f64::from).collect();
        assert_eq!(kolmogorov_smirnov(&a, &a), Some((0.0, 1.0)));
        assert_eq!(kolmogorov_smirnov(&a, &[]), None);
        // Disjoint samples: D = 1 and a tiny p-value.
        let b: Vec<f64> = (0..150).map(|x| f64::from(x) + 1000.0).collect();
        let (d, p) = kolmogorov_smirnov(&a, &b).unwrap();
        assert!((d - 1.0).abs() < 1e-9, "{d}");
        assert!(p < 1e-10, "{p}");
        assert_eq!(ks_statistic(&[1.0, 2.0], &[2.0, 3.0]), 0.5);
    }

    #[test]
    fn ert_hand_computed() {
        // 3 successes at 1, 2, 3 s; 2 runs censored at the 10 s cutoff:
        // ERT = (1 + 2 + 3 + 2 * 10) / 3 = 26/3 = mean 2 + (2/5)/(3/5) * 10.
        let o = [succ(1.0), cens(10.0), succ(2.0), cens(10.0), succ(3.0)];
        assert!((ert(&o) - 26.0 / 3.0).abs() < 1e-12);
        assert!(ert(&[cens(1.0)]).is_infinite());
        let s = summarise(&o, 200, 1);
        assert_eq!(s.successes, 3);
        assert!((s.success_rate - 0.6).abs() < 1e-12);
        // Shared cutoff: the RTD is the ECDF over all 5 runs: 0.2, 0.4, 0.6 at 1, 2, 3.
        assert_eq!(s.quantiles, [Some(1.0), Some(2.0), Some(3.0), None, None]);
        assert!(!s.km_censoring);
        let (lo, hi) = (s.ert_p10.unwrap(), s.ert_p90.unwrap());
        assert!(lo <= 26.0 / 3.0 && 26.0 / 3.0 <= hi, "{lo} {hi}");
        let r = s.restarts.unwrap();
        assert!(r[0] >= 1.0 && r[0] <= r[1] && r[1] <= r[2]);
        // Seeded: the same seed gives the same bootstrap.
        assert_eq!(s, summarise(&o, 200, 1));
    }

    #[test]
    fn kaplan_meier_hand_computed() {
        // Success 1, censored 2, success 3, success 4: S = 3/4, then 3/4 * 1/2 = 3/8, then 0.
        let o = [succ(1.0), cens(2.0), succ(3.0), succ(4.0)];
        let km = kaplan_meier(&o);
        assert_eq!(km.len(), 3);
        assert!((km[0].1 - 0.25).abs() < 1e-12);
        assert!((km[1].1 - 0.625).abs() < 1e-12);
        assert!((km[2].1 - 1.0).abs() < 1e-12);
        assert!(censoring_heterogeneous(&o));
        assert_eq!(quantile(&km, 0.5), Some(3.0));
        assert_eq!(cdf_at(&km, 3.5), 0.625);
        assert_eq!(cdf_at(&km, 0.5), 0.0);
    }

    #[test]
    fn mann_whitney_textbook() {
        // SciPy's documented example (Conover): U = 17, exact two-sided p = 1/9.
        let male = [19.0, 22.0, 16.0, 29.0, 24.0];
        let female = [20.0, 11.0, 17.0, 12.0];
        let (u, p) = mann_whitney(&male, &female).unwrap();
        assert_eq!(u, 17.0);
        assert!((p - 0.1111111111).abs() < 1e-6, "{p}");
        // Censored runs as +inf: all of b is slower.
        let a = [1.0, 2.0, 3.0];
        let b = [4.0, f64::INFINITY, f64::INFINITY];
        let (u, _) = mann_whitney(&a, &b).unwrap();
        assert_eq!(u, 0.0);
    }

    #[test]
    fn ks_and_holm() {
        let a = [1.0, 2.0, 3.0, 4.0];
        let b = [5.0, 6.0, 7.0, 8.0];
        let (d, p) = kolmogorov_smirnov(&a, &b).unwrap();
        assert_eq!(d, 1.0);
        // Exact: only 2 of C(8,4) = 70 orderings give D = 1.
        assert!((p - 2.0 / 70.0).abs() < 1e-9, "{p}");
        let adj = holm(&[0.01, 0.04, 0.03]);
        let want = [0.03, 0.06, 0.06];
        for (x, y) in adj.iter().zip(want) {
            assert!((x - y).abs() < 1e-12, "{adj:?}");
        }
    }

    #[test]
    fn domination_detects_order() {
        let fast = kaplan_meier(&[succ(1.0), succ(2.0)]);
        let slow = kaplan_meier(&[succ(3.0), cens(5.0)]);
        assert_eq!(domination(&fast, &slow), (true, false));
        assert_eq!(domination(&slow, &fast), (false, true));
        let x = kaplan_meier(&[succ(1.0), succ(10.0)]);
        let y = kaplan_meier(&[succ(2.0), succ(3.0)]);
        assert_eq!(domination(&x, &y), (false, false));
    }
}
