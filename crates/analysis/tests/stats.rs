//! Run-time statistics by hand: ERT, Kaplan-Meier, Holm, domination, final quality, and the
//! pairwise tests' columns in stats.json and tests.csv.

use brdf_analysis::stats::*;
use brdf_experiment::store::TrialRecord;

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
    let with = |test: &'static Test, statistic, p, effect, direction| TestResult {
        test,
        statistic,
        p,
        p_holm: p,
        effect,
        direction,
    };
    PairTest {
        instance: "i".into(),
        target: 0.1,
        measure: Measure::CpuSeconds,
        a: "A".into(),
        b: "B".into(),
        results: vec![
            with(
                &pairwise::MANN_WHITNEY,
                Some(1.0),
                Some(0.5),
                None,
                Direction::A,
            ),
            with(
                &pairwise::KOLMOGOROV_SMIRNOV,
                Some(0.25),
                Some(0.75),
                None,
                Direction::Neither,
            ),
            with(&pairwise::DOMINATION, None, None, None, Direction::A),
            with(
                &pairwise::LOG_RANK,
                hazard_ratio.map(|_| 4.0),
                hazard_ratio.map(|_| 0.05),
                hazard_ratio,
                hazard_ratio.map_or(Direction::Neither, |h| {
                    if h > 1.0 {
                        Direction::A
                    } else if h < 1.0 {
                        Direction::B
                    } else {
                        Direction::Neither
                    }
                }),
            ),
        ],
    }
}

/// A pair in stats.json holds exactly the columns of its row in tests.csv: both render the
/// one list of tests.
#[test]
fn a_pair_has_the_same_columns_in_json_and_csv() {
    let t = pair_test(Some(2.0));
    let report = StatsReport {
        bootstrap: 0,
        configs: vec![],
        tests: vec![t.clone()],
        finals: vec![],
    };
    let csv = tests_csv(&report);
    let mut header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let value = serde_json::to_value(&t).unwrap();
    let mut keys: Vec<&str> = value
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    header.sort_unstable();
    keys.sort_unstable();
    assert_eq!(header, keys);
    let cells: usize = TESTS
        .iter()
        .map(|t| TestResult::empty(t).cells().len())
        .sum();
    assert_eq!(header.len(), 5 + cells);
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
        let mut back: PairTest = serde_json::from_str(&serde_json::to_string(&t).unwrap()).unwrap();
        // Mann-Whitney's direction needs the sample sizes, which no column holds.
        back.results[0].direction = Direction::A;
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
    assert_eq!(t.result(&pairwise::LOG_RANK).unwrap().effect, None);
    old.as_object_mut().unwrap().remove("lr_hazard_ratio");
    let t: PairTest = serde_json::from_value(old.clone()).unwrap();
    assert_eq!(t.result(&pairwise::LOG_RANK).unwrap().effect, None);
    old["lr_hazard_ratio"] = serde_json::json!("infinite");
    let e = serde_json::from_value::<PairTest>(old)
        .unwrap_err()
        .to_string();
    assert!(e.contains("\"inf\""), "{e}");
}

/// With one shared cutoff Greenwood's band is the binomial interval's normal approximation:
/// 4 of 10 solved, F = 0.4 +- 1.96 sqrt(0.4 * 0.6 / 10); clamped to [0, 1].
#[test]
fn kaplan_meier_band_hand_computed() {
    let mut o: Vec<Outcome> = (1..=4).map(|i| succ(f64::from(i))).collect();
    o.extend((0..6).map(|_| cens(10.0)));
    let band = kaplan_meier_band(&o);
    let (t, f, lo, hi) = band[3];
    let half = 1.96 * (0.4f64 * 0.6 / 10.0).sqrt();
    assert_eq!(t, 4.0);
    assert!((f - 0.4).abs() < 1e-12);
    assert!((lo - (0.4 - half)).abs() < 1e-12 && (hi - (0.4 + half)).abs() < 1e-12);
    let (_, f, lo, _) = band[0];
    assert!((f - 0.1).abs() < 1e-12 && lo == 0.0, "{lo}");
    // All solved: the last step is certain.
    let all: Vec<Outcome> = (1..=3).map(|i| succ(f64::from(i))).collect();
    assert_eq!(kaplan_meier_band(&all)[2], (3.0, 1.0, 1.0, 1.0));
}
