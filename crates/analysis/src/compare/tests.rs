use super::*;
use brdf_experiment::store::TrialRecord;

const TARGET: f64 = 0.1;
const CUTOFF: u64 = 1_000_000;

fn stamp(evals: u64) -> sls::Stamp {
    sls::Stamp {
        cpu_seconds: evals as f64 * 1e-6,
        wall_seconds: evals as f64 * 1e-6,
        evaluations: sls::EvalCounts {
            rmse_rows: evals,
            ..Default::default()
        },
    }
}

/// A trial that reaches the target after `evals` sample-evaluations, or (None) is censored at
/// the cutoff.
fn trial(i: u32, evals: Option<u64>) -> TrialRecord {
    let end = evals.unwrap_or(CUTOFF);
    let mut trace = vec![sls::TracePoint {
        at: stamp(1),
        rmse: 1.0,
    }];
    if let Some(e) = evals {
        trace.push(sls::TracePoint {
            at: stamp(e),
            rmse: TARGET,
        });
    }
    TrialRecord {
        key: TrialRecord::make_key("i", "AED", i),
        instance: "i".into(),
        config: "AED".into(),
        trial: i,
        seed: u64::from(i),
        target: TARGET,
        budget: sls::Budget {
            cpu_seconds: None,
            sample_evaluations: Some(CUTOFF),
        },
        result: sls::TrialResult {
            stop: sls::StopReason::CpuBudget,
            reached_at: evals.map(stamp),
            ended_at: stamp(end),
            best_rmse: if evals.is_some() { TARGET } else { 1.0 },
            best_x: vec![],
            trace,
            counters: vec![],
            failure: None,
        },
    }
}

fn conditions() -> Conditions {
    Conditions {
        data_hash: Some("d1".into()),
        source: serde_json::json!({"synthetic": "tuning"}),
        model: serde_json::json!({"exponent": "log", "starts": "uniform"}),
        run_target: TARGET,
        budget: sls::Budget {
            cpu_seconds: None,
            sample_evaluations: Some(CUTOFF),
        },
        algorithm: serde_json::json!({"algorithm": {"kind": "aed", "phi": 1.2}}),
        counting: 3,
    }
}

/// An entry whose 30 trials reach the target at `scale` times 1000, 2000, ... evaluations.
fn entry(scale: u64) -> Entry {
    Entry {
        instance: "i".into(),
        config: "AED".into(),
        targets: vec![TARGET],
        conditions: conditions(),
        records: (0..30)
            .map(|i| trial(i, Some(scale * 1000 * (u64::from(i) + 1))))
            .collect(),
    }
}

fn verdicts(c: &Comparison) -> Vec<Verdict> {
    c.rows.iter().map(|r| r.verdict.clone()).collect()
}

#[test]
fn a_clearly_slower_b_is_slower_and_the_reverse_faster() {
    let (fast, slow) = (entry(1), entry(4));
    let c = compare(
        std::slice::from_ref(&fast),
        std::slice::from_ref(&slow),
        Options::default(),
    );
    assert_eq!(verdicts(&c), vec![Verdict::Slower]);
    assert_eq!(c.slower(), 1);
    let m = &c.rows[0].measures[0];
    assert_eq!(m.measure, Measure::Evaluations);
    // Medians 15000 and 60000 evaluations (the 15th of 30 successes): B's is 4 times A's.
    assert_eq!(m.a.quantiles[2], Some(15000.0));
    assert_eq!(m.median_change, Some(3.0));
    assert!(m.p_holm.unwrap() < 1e-6, "{m:?}");
    assert!(m.hazard_ratio.unwrap() > 1.0);
    let c = compare(&[slow], &[fast], Options::default());
    assert_eq!(verdicts(&c), vec![Verdict::Faster]);
    assert_eq!(c.slower(), 0);
}

#[test]
fn identical_results_show_no_significant_difference() {
    let c = compare(&[entry(1)], &[entry(1)], Options::default());
    assert_eq!(verdicts(&c), vec![Verdict::NoDifference]);
    let m = &c.rows[0].measures[0];
    assert_eq!(m.median_change, Some(0.0));
    assert!(m.p.unwrap() > 0.99, "{m:?}");
}

#[test]
fn a_change_below_the_minimum_effect_is_no_difference() {
    let c = compare(
        &[entry(1)],
        &[entry(4)],
        Options {
            min_effect: 5.0,
            ..Options::default()
        },
    );
    assert_eq!(verdicts(&c), vec![Verdict::NoDifference]);
}

#[test]
fn a_different_target_is_not_comparable_and_says_so() {
    let mut b = entry(1);
    b.targets = vec![0.2];
    b.conditions.run_target = 0.2;
    let c = compare(&[entry(1)], &[b], Options::default());
    let v = verdicts(&c);
    let [Verdict::NotComparable(why)] = v.as_slice() else {
        panic!("{c:?}");
    };
    assert!(why.contains("different target"), "{why}");
    assert!(why.contains("0.1 vs 0.2"), "{why}");
    assert_eq!(c.comparable(), 0);
}

/// A relative target re-computed after a change of round-off (the best-known RMSE moved in its
/// last bits) is the same target; one moved by more is not.
#[test]
fn a_target_moved_by_round_off_is_the_same_target() {
    let moved = |by: f64| {
        let mut b = entry(1);
        let t = b.targets[0] * (1.0 + by);
        b.targets = vec![t];
        b.conditions.run_target = t;
        b
    };
    let c = compare(
        &[entry(1)],
        &[moved(2.0 * f64::EPSILON)],
        Options::default(),
    );
    assert_eq!(verdicts(&c), vec![Verdict::NoDifference]);
    assert_eq!(c.comparable(), 1);
    let c = compare(&[entry(1)], &[moved(1e-9)], Options::default());
    let v = verdicts(&c);
    let [Verdict::NotComparable(why)] = v.as_slice() else {
        panic!("{c:?}");
    };
    assert!(why.contains("different target"), "{why}");
}

#[test]
fn each_difference_of_conditions_is_named() {
    let a = conditions();
    let mut b = conditions();
    b.data_hash = Some("d2".into());
    b.budget.sample_evaluations = Some(5);
    b.model["starts"] = "sobol".into();
    b.algorithm["algorithm"]["phi"] = 1.4.into();
    b.counting = 4;
    let d = differences(&a, &b).join("; ");
    for want in [
        "different instance data (hash d1 vs d2)",
        "different model (starts: \"uniform\" vs \"sobol\")",
        "different budget/cutoff (1000000 sample-evaluations vs 5 sample-evaluations)",
        "different algorithm settings (algorithm.phi: 1.2 vs 1.4)",
        "different counting rule (results format 3 vs 4)",
    ] {
        assert!(d.contains(want), "{want} not in {d}");
    }
    assert!(differences(&a, &conditions()).is_empty());
}

#[test]
fn unmatched_configurations_and_targets_are_listed_as_not_comparable() {
    let mut other = entry(1);
    other.config = "RPLS".into();
    let mut two = entry(1);
    two.targets = vec![TARGET, 0.3];
    let c = compare(&[two, other], &[entry(1)], Options::default());
    let got: Vec<(String, Option<f64>, String)> = c
        .rows
        .iter()
        .map(|r| (r.config.clone(), r.target, r.verdict.text()))
        .collect();
    assert_eq!(
        got,
        vec![
            (
                "AED".into(),
                Some(TARGET),
                "no significant difference".into()
            ),
            (
                "AED".into(),
                Some(0.3),
                "not comparable: target only in A".into()
            ),
            (
                "RPLS".into(),
                None,
                "not comparable: instance and configuration only in A".into()
            ),
        ]
    );
}

#[test]
fn holm_adjusts_over_the_pairs() {
    let mut a2 = entry(1);
    a2.config = "RPLS".into();
    let mut b2 = entry(4);
    b2.config = "RPLS".into();
    let c = compare(&[entry(1), a2], &[entry(4), b2], Options::default());
    let ps: Vec<(f64, f64)> = c
        .rows
        .iter()
        .map(|r| (r.measures[0].p.unwrap(), r.measures[0].p_holm.unwrap()))
        .collect();
    // Two equal p-values: Holm multiplies the smallest by 2 and keeps the order.
    assert_eq!(ps.len(), 2);
    for (p, h) in ps {
        assert!((h - (2.0 * p).min(1.0)).abs() < 1e-12, "{p} {h}");
    }
}

#[test]
fn relative_changes_treat_not_reached_as_infinite() {
    assert_eq!(relative_change(Some(2.0), Some(3.0)), Some(0.5));
    assert_eq!(relative_change(Some(2.0), None), Some(f64::INFINITY));
    assert_eq!(relative_change(None, Some(1.0)), Some(-1.0));
    assert_eq!(relative_change(None, None), None);
}

#[test]
fn the_table_has_a_line_per_pair_and_a_summary() {
    let c = compare(&[entry(1)], &[entry(4)], Options::default());
    let t = table(&c);
    let lines: Vec<&str> = t.lines().collect();
    assert_eq!(lines.len(), 3, "{t}");
    assert!(lines[0].starts_with("instance"), "{t}");
    assert!(
        lines[1].contains("slower") && lines[1].contains("+300.0%"),
        "{t}"
    );
    assert!(lines[2].contains("1 significantly slower"), "{t}");
}
