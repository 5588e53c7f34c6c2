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
//!   coded as +inf; [`mann_whitney`]) and two-sample Kolmogorov-Smirnov ([`kolmogorov_smirnov`];
//!   both as scipy computes them, with tails that keep tiny p-values) with Holm's correction
//!   over all pairs of the (instance, target, measure) family, and probabilistic domination
//!   (one RTD at or above the other everywhere and strictly above somewhere). The log-rank
//!   test (censored runs at their own censoring times) with its hazard ratio estimate is
//!   Holm-corrected over the same family.

use serde::{Deserialize, Serialize};
use statrs::statistics::{Data, Distribution, Max, Min, OrderStatistics};

mod bootstrap;
mod cell;
mod hypothesis;
mod infinite;
mod ks;
mod logrank;
mod mann_whitney;
pub mod pairwise;
mod rtd;
mod tables;

pub use bootstrap::{bootstrap_ert, simulated_restarts};
pub use cell::{Cell, CellKind};
pub use hypothesis::holm;
pub use ks::{KS_EXACT_MAX_N, kolmogorov_sf, kolmogorov_smirnov, ks_statistic};
pub use logrank::{LogRank, log_rank};
pub use mann_whitney::{MW_EXACT_MAX_N, mann_whitney};
pub use pairwise::{Direction, TESTS, Test, TestResult};
pub use rtd::{
    Measure, Outcome, cdf_at, censoring_heterogeneous, domination, ert, kaplan_meier,
    kaplan_meier_band, outcome, quantile,
};
pub use tables::{
    configs_csv, csv_field, direction_text, fmt_num, fmt_target, pad_right, significant, table,
    target_digits, target_text, tests_csv,
};

use brdf_experiment::seed::StableHasher;
use brdf_experiment::store::TrialRecord;

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

impl MeasureSummary {
    /// The summary's columns in `stats.csv` (and the Python package's records), in order.
    pub fn cells(&self) -> Vec<(&'static str, Cell)> {
        let q = self.quantiles;
        let r = self.restarts.map_or([None; 3], |r| r.map(Some));
        vec![
            ("trials", Cell::Count(self.trials)),
            ("successes", Cell::Count(self.successes)),
            ("success_rate", Cell::Number(Some(self.success_rate))),
            ("q10", Cell::Time(q[0])),
            ("q25", Cell::Time(q[1])),
            ("q50", Cell::Time(q[2])),
            ("q75", Cell::Time(q[3])),
            ("q90", Cell::Time(q[4])),
            ("ert", Cell::Time(self.ert)),
            ("ert_sd", Cell::Time(self.ert_sd)),
            ("ert_p10", Cell::Time(self.ert_p10)),
            ("ert_p50", Cell::Time(self.ert_p50)),
            ("ert_p90", Cell::Time(self.ert_p90)),
            ("restart_p10", Cell::Time(r[0])),
            ("restart_p50", Cell::Time(r[1])),
            ("restart_p90", Cell::Time(r[2])),
            ("km_censoring", Cell::Flag(self.km_censoring)),
        ]
    }
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

/// A pairwise comparison of two configurations' RTDs: every test of [`TESTS`] on the pair.
///
/// In `stats.json` (and for Python) a pair is one flat object: `instance`, `target`, `measure`,
/// `a`, `b`, then each test's columns ([`TestResult::cells`]) in [`TESTS`] order, the same
/// columns as `tests.csv`.
#[derive(Clone, Debug, PartialEq)]
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
    /// One result per test of [`TESTS`], in that order.
    pub results: Vec<TestResult>,
}

impl PairTest {
    /// The result of `test` on this pair.
    pub fn result(&self, test: &Test) -> Option<&TestResult> {
        self.results.iter().find(|r| r.test == test)
    }

    /// The configuration that `test` finds reaching the target sooner, if any.
    pub fn sooner(&self, test: &Test) -> Option<&str> {
        match self.result(test)?.direction {
            Direction::A => Some(&self.a),
            Direction::B => Some(&self.b),
            Direction::Neither => None,
        }
    }
}

impl Serialize for PairTest {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(None)?;
        map.serialize_entry("instance", &self.instance)?;
        map.serialize_entry("target", &self.target)?;
        map.serialize_entry("measure", &self.measure)?;
        map.serialize_entry("a", &self.a)?;
        map.serialize_entry("b", &self.b)?;
        pairwise::serialize_cells(&self.results, &mut map)?;
        map.end()
    }
}

impl<'de> Deserialize<'de> for PairTest {
    /// Reads what [`Serialize`] writes; a test's missing column reads as no value (files
    /// written before the log-rank test have none of its columns).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let mut m = serde_json::Map::deserialize(d)?;
        let mut take = |k: &str| m.remove(k).unwrap_or(serde_json::Value::Null);
        fn field<T: serde::de::DeserializeOwned, E: Error>(
            k: &str,
            v: serde_json::Value,
        ) -> Result<T, E> {
            serde_json::from_value(v).map_err(|e| E::custom(format!("{k}: {e}")))
        }
        let instance = field("instance", take("instance"))?;
        let target = field("target", take("target"))?;
        let measure = field("measure", take("measure"))?;
        let a = field("a", take("a"))?;
        let b = field("b", take("b"))?;
        let mut results = Vec::new();
        for test in TESTS {
            let r = TestResult::from_cells(test, |column, kind| {
                let v = take(column);
                let read = match kind {
                    CellKind::Number => serde_json::from_value(v).map(Cell::Number),
                    CellKind::Effect => infinite::deserialize(v).map(Cell::Effect),
                    CellKind::Flag => serde_json::from_value::<Option<bool>>(v)
                        .map(|f| Cell::Flag(f == Some(true))),
                };
                read.map_err(|e| format!("{column}: {e}"))
            })
            .map_err(D::Error::custom)?;
            results.push(r);
        }
        Ok(PairTest {
            instance,
            target,
            measure,
            a,
            b,
            results,
        })
    }
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

impl StatsReport {
    /// The per-configuration statistics as flat records (the Python package's `stats`): per
    /// instance, configuration, target and measure (`cpu` or `evaluations`, the names of the
    /// summaries in `stats.json`), the columns of `stats.csv` ([`MeasureSummary::cells`]).
    pub fn config_records(&self) -> Vec<serde_json::Map<String, serde_json::Value>> {
        let mut out = Vec::new();
        for c in &self.configs {
            for (measure, m) in [("cpu", &c.cpu), ("evaluations", &c.evaluations)] {
                let mut row = serde_json::Map::new();
                row.insert("instance".into(), c.instance.clone().into());
                row.insert("config".into(), c.config.clone().into());
                row.insert("target".into(), c.target.into());
                row.insert("measure".into(), measure.into());
                for (name, cell) in m.cells() {
                    let v = serde_json::to_value(cell).unwrap_or(serde_json::Value::Null);
                    row.insert(name.into(), v);
                }
                out.push(row);
            }
        }
        out
    }
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
                        tests.push(PairTest {
                            instance: inst.clone(),
                            target: t,
                            measure: m,
                            a: gs[i].config.clone(),
                            b: gs[j].config.clone(),
                            results: pairwise::run_all(&oa, &ob),
                        });
                    }
                }
                pairwise::adjust(tests[start..].iter_mut().map(|t| &mut t.results));
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
