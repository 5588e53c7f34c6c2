//! The per-instance tables of a report: success, median and ERT with bootstrap intervals;
//! pairwise tests with Holm's correction; final quality; the best fit's parameters.

use super::{escape, table};
use crate::stats::{MeasureSummary, StatsReport, TESTS, Test, direction_text, fmt_num, pairwise};
use brdf_experiment::spec::InstanceSpec;
use brdf_experiment::store::TrialRecord;

/// A number in a right-aligned cell.
fn num(v: Option<f64>) -> String {
    fmt_num(v)
}

/// ERT with its bootstrap 10-90% interval, e.g. `1.23 [0.98, 1.61]`.
pub fn ert_text(m: &MeasureSummary) -> String {
    match m.ert {
        None => "- (no success)".into(),
        Some(e) => format!("{} [{}, {}]", num(Some(e)), num(m.ert_p10), num(m.ert_p90)),
    }
}

/// Success, median and ERT (with bootstrap 10-90% intervals) per target and configuration,
/// in CPU seconds and sample-evaluations.
pub fn success_table(report: &StatsReport, instance: &str) -> String {
    let rows: Vec<Vec<String>> = report
        .configs
        .iter()
        .filter(|c| c.instance == instance)
        .map(|c| {
            vec![
                c.target.to_string(),
                escape(&c.config),
                format!("{}/{}", c.cpu.successes, c.cpu.trials),
                num(c.cpu.quantiles[2]),
                ert_text(&c.cpu),
                num(c.evaluations.quantiles[2]),
                ert_text(&c.evaluations),
            ]
        })
        .collect();
    table(
        "success",
        &[
            "target RMSE",
            "configuration",
            "success",
            "median CPU s",
            "ERT CPU s [10%, 90%]",
            "median sample-evaluations",
            "ERT sample-evaluations [10%, 90%]",
        ],
        &rows,
    )
}

fn p_holm(p: Option<f64>, holm: Option<f64>) -> String {
    match (p, holm) {
        (Some(p), Some(h)) => format!("{} ({})", pf(p), pf(h)),
        _ => "-".into(),
    }
}

fn pf(p: f64) -> String {
    if p < 1e-4 {
        format!("{p:.1e}")
    } else {
        format!("{p:.4}")
    }
}

/// The tests in the order the page shows them: the primary test first, then the other
/// p-value tests, then the direction-only ones.
fn page_order() -> Vec<&'static Test> {
    let primary = pairwise::primary();
    let mut tests = vec![primary];
    tests.extend(TESTS.iter().filter(|t| t.p.is_some() && **t != primary));
    tests.extend(TESTS.iter().filter(|t| t.p.is_none()));
    tests
}

/// The pairwise tests of one instance: each test's p-value with its Holm-adjusted value (over
/// the pairs of each target and measure) and effect, and the direction-only tests' outcomes.
pub fn tests_table(report: &StatsReport, instance: &str) -> String {
    let order = page_order();
    let rows: Vec<Vec<String>> = report
        .tests
        .iter()
        .filter(|t| t.instance == instance)
        .map(|t| {
            let mut row = vec![
                t.target.to_string(),
                t.measure.label().to_string(),
                escape(&t.a),
                escape(&t.b),
            ];
            for test in &order {
                let Some(r) = t.result(test) else {
                    row.push("-".into());
                    continue;
                };
                if test.p.is_some() {
                    row.push(p_holm(r.p, r.p_holm));
                    if test.effect.is_some() {
                        row.push(num(r.effect));
                    }
                } else {
                    row.push(escape(&direction_text(r, &t.a, &t.b)));
                }
            }
            row
        })
        .collect();
    if rows.is_empty() {
        return "<p class=\"note\">One configuration only: no pairwise tests.</p>\n".into();
    }
    let mut head: Vec<String> = ["target RMSE", "measure", "A", "B"]
        .map(String::from)
        .to_vec();
    for test in &order {
        if test.p.is_some() {
            head.push(format!("{} p (Holm)", test.name));
            if let Some(e) = &test.effect {
                head.push(e.name.to_string());
            }
        } else {
            head.push(test.name.to_string());
        }
    }
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    table("tests", &head, &rows)
}

/// Final RMSE per trial and when trials ended (the paper's Table 5).
pub fn finals_table(report: &StatsReport, instance: &str) -> String {
    let rows: Vec<Vec<String>> = report
        .finals
        .iter()
        .filter(|q| q.instance == instance)
        .map(|q| {
            vec![
                escape(&q.config),
                q.trials.to_string(),
                q.finished.to_string(),
                num(q.rmse_median),
                format!("{} - {}", num(q.rmse_min), num(q.rmse_max)),
                num(q.end_cpu_median),
            ]
        })
        .collect();
    table(
        "finals",
        &[
            "configuration",
            "trials",
            "ended by themselves",
            "median final RMSE",
            "final RMSE range",
            "median end CPU s",
        ],
        &rows,
    )
}

/// The parameters of the lowest-RMSE trial of an instance (ties: the first in file order).
pub fn best_fit(inst: &InstanceSpec, records: &[TrialRecord]) -> String {
    let best = records
        .iter()
        .filter(|r| r.instance == inst.name && r.result.best_rmse.is_finite())
        .filter(|r| !r.result.best_x.is_empty())
        .min_by(|a, b| a.result.best_rmse.total_cmp(&b.result.best_rmse));
    let Some(r) = best else {
        return "<p class=\"note\">No trial recorded a finite RMSE.</p>\n".into();
    };
    let intro = format!(
        "<p>Lowest final RMSE {:.6} by {} (trial {}, seed {}).</p>\n",
        r.result.best_rmse,
        escape(&r.config),
        r.trial,
        r.seed
    );
    let layout = match inst.model.layout() {
        Ok(l) if l.dim() == r.result.best_x.len() => l,
        _ => {
            return format!(
                "{intro}<p class=\"note\">The stored parameters do not fit the spec's model.</p>\n"
            );
        }
    };
    let params = layout.decode(&r.result.best_x);
    let rows: Vec<Vec<String>> = layout
        .all_names()
        .into_iter()
        .map(|name| {
            let fixed = if layout.fixed_value(name).is_some() {
                "fixed"
            } else {
                "fitted"
            };
            let v = params
                .get(name)
                .map_or_else(|| "-".into(), |v| format!("{v:.9}"));
            vec![escape(name), v, fixed.into()]
        })
        .collect();
    intro + &table("params", &["parameter", "value", ""], &rows)
}
