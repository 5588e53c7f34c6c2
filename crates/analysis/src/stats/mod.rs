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
mod hypothesis;
mod infinite;
mod ks;
mod logrank;
mod mann_whitney;
mod rtd;
mod tables;

pub use bootstrap::{bootstrap_ert, simulated_restarts};
pub use hypothesis::holm;
pub use ks::{KS_EXACT_MAX_N, kolmogorov_sf, kolmogorov_smirnov, ks_statistic};
pub use logrank::{LogRank, log_rank};
pub use mann_whitney::{MW_EXACT_MAX_N, mann_whitney};
pub use rtd::{
    Measure, Outcome, cdf_at, censoring_heterogeneous, domination, ert, kaplan_meier, outcome,
    quantile,
};
pub use tables::{configs_csv, csv_field, fmt_num, fmt_target, table, tests_csv};

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
    /// Log-rank chi-square (censored runs at their own censoring times; [`log_rank`]).
    #[serde(default)]
    pub lr_chi2: Option<f64>,
    /// Log-rank p-value (chi-square, 1 degree of freedom).
    #[serde(default)]
    pub lr_p: Option<f64>,
    /// Holm-adjusted log-rank p-value.
    #[serde(default)]
    pub lr_p_holm: Option<f64>,
    /// Hazard ratio estimate `(O_a/E_a)/(O_b/E_b)`: above 1, `a` reaches the target sooner.
    /// Infinite when only `a` ever reached the target (0 when only `b` did); `None` when there
    /// is no log-rank test. The infinity is written as the string `"inf"` in `stats.json`
    /// (JSON has no infinity; `null` means no test) and as `inf` in `tests.csv` (where no test
    /// is an empty field).
    #[serde(default, with = "infinite")]
    pub lr_hazard_ratio: Option<f64>,
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
                        let lr = log_rank(&oa, &ob);
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
                            lr_chi2: lr.map(|x| x.chi2),
                            lr_p: lr.map(|x| x.p),
                            lr_p_holm: None,
                            lr_hazard_ratio: lr.map(|x| x.hazard_ratio),
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
    let lr = apply(|t| t.lr_p, family);
    for (i, t) in family.iter_mut().enumerate() {
        t.mw_p_holm = mw[i];
        t.ks_p_holm = ks[i];
        t.lr_p_holm = lr[i];
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
                failure: None,
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
    fn holm_hand_computed() {
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

    fn pair_test(hazard_ratio: Option<f64>) -> PairTest {
        PairTest {
            instance: "i".into(),
            target: 0.1,
            measure: Measure::CpuSeconds,
            a: "A".into(),
            b: "B".into(),
            mw_u: Some(1.0),
            mw_p: Some(0.5),
            mw_p_holm: Some(0.5),
            ks_d: Some(0.25),
            ks_p: Some(0.75),
            ks_p_holm: Some(0.75),
            a_dominates: true,
            b_dominates: false,
            lr_chi2: hazard_ratio.map(|_| 4.0),
            lr_p: hazard_ratio.map(|_| 0.05),
            lr_p_holm: hazard_ratio.map(|_| 0.05),
            lr_hazard_ratio: hazard_ratio,
        }
    }

    /// An infinite hazard ratio (only `a` reached the target) must not read like "no test":
    /// `"inf"` in stats.json and `inf` in tests.csv, where no test is `null` and empty.
    #[test]
    fn infinite_hazard_ratio_differs_from_no_test_in_json_and_csv() {
        let cases = [
            (Some(f64::INFINITY), serde_json::json!("inf"), "inf"),
            (Some(0.0), serde_json::json!(0.0), "0"),
            (Some(2.5), serde_json::json!(2.5), "2.5"),
            (None, serde_json::Value::Null, ""),
        ];
        for (hr, json, csv) in cases {
            let t = pair_test(hr);
            let value = serde_json::to_value(&t).unwrap();
            assert_eq!(value["lr_hazard_ratio"], json, "{hr:?}");
            let back: PairTest = serde_json::from_str(&serde_json::to_string(&t).unwrap()).unwrap();
            assert_eq!(back, t);
            let report = StatsReport {
                bootstrap: 0,
                configs: vec![],
                tests: vec![t],
                finals: vec![],
            };
            let row = tests_csv(&report);
            let last = row.lines().nth(1).unwrap().rsplit(',').next().unwrap();
            assert_eq!(last, csv, "{hr:?}");
        }
        // Files written before: `null` and a missing field both read as no ratio.
        let mut old = serde_json::to_value(pair_test(Some(1.0))).unwrap();
        old["lr_hazard_ratio"] = serde_json::Value::Null;
        let t: PairTest = serde_json::from_value(old.clone()).unwrap();
        assert_eq!(t.lr_hazard_ratio, None);
        old.as_object_mut().unwrap().remove("lr_hazard_ratio");
        let t: PairTest = serde_json::from_value(old.clone()).unwrap();
        assert_eq!(t.lr_hazard_ratio, None);
        old["lr_hazard_ratio"] = serde_json::json!("infinite");
        let e = serde_json::from_value::<PairTest>(old)
            .unwrap_err()
            .to_string();
        assert!(e.contains("\"inf\""), "{e}");
    }
}
