//! The summary that answers first: the best per instance and target, ratios, marks, ranks.

use brdf_analysis::analysis::summary::*;
use brdf_analysis::stats::Outcome;
use brdf_analysis::stats::{ConfigStats, Direction, Measure, StatsReport, pairwise};
use brdf_analysis::stats::{PairTest, TestResult, summarise as summarise_outcomes};

fn stats_of(ert: [Option<f64>; 3]) -> StatsReport {
    let mut configs = Vec::new();
    for (c, e) in ["A", "B", "C"].iter().zip(ert) {
        let mut s = summarise_outcomes(
            &[Outcome {
                success: Some(1.0),
                spent: 1.0,
            }],
            0,
            0,
        );
        s.ert = e;
        configs.push(ConfigStats {
            instance: "i".into(),
            config: c.to_string(),
            target: 0.1,
            cpu: s.clone(),
            evaluations: s,
        });
    }
    // B against A: the log-rank test finds A sooner, significantly.
    let mut lr = TestResult::empty(pairwise::primary());
    lr.p = Some(0.001);
    lr.p_holm = Some(0.003);
    lr.effect = Some(3.0);
    lr.direction = Direction::A;
    let tests = vec![PairTest {
        instance: "i".into(),
        target: 0.1,
        measure: Measure::Evaluations,
        a: "A".into(),
        b: "B".into(),
        results: vec![lr],
    }];
    StatsReport {
        bootstrap: 0,
        configs,
        tests,
        finals: vec![],
    }
}

#[test]
fn the_best_ratios_marks_and_ranks() {
    let stats = stats_of([Some(10.0), Some(40.0), None]);
    let labels = ["A".to_string(), "B".into(), "C".into()];
    let s = summarise(&stats, &["i".into()], &labels, Measure::Evaluations);
    let r = &s.rows[0];
    assert_eq!(r.best, Some(0));
    let b = r.cells[1].as_ref().unwrap();
    assert_eq!(b.ratio, Some(4.0));
    assert!(b.significant);
    assert!(!r.cells[0].as_ref().unwrap().significant);
    assert_eq!(r.cells[2].as_ref().unwrap().ratio, None);
    assert_eq!(s.matrix[0][1], 1);
    assert_eq!(s.matrix[1][0], 0);
    assert_eq!(s.compared[0][1], 1);
    assert_eq!(s.ranking(), vec![0, 1, 2]);
    assert_eq!(s.aggregates[0].best, 1);
    assert_eq!(s.aggregates[1].geo_mean_ratio, Some(4.0));
    assert_eq!(s.aggregates[2].solved, 0);
    assert_eq!((s.aggregates[0].wins, s.aggregates[1].losses), (1, 1));
    // In CPU seconds there is no test: no mark.
    let s = summarise(&stats, &["i".into()], &labels, Measure::CpuSeconds);
    assert!(!s.rows[0].cells[1].as_ref().unwrap().significant);
}
