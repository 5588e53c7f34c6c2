//! The per-instance tables of a report: success, median and ERT with bootstrap intervals;
//! pairwise tests with Holm's correction; final quality; the best fit's parameters. Each with
//! a caption; numbers right-aligned with at most a few significant digits.

use super::format::{num, p_value, significant};
use super::summary::Targets;
use super::{data_table, escape};
use crate::stats::{MeasureSummary, StatsReport, TESTS, Test, direction_text, pairwise};
use brdf_experiment::spec::InstanceSpec;
use brdf_experiment::store::TrialRecord;

/// ERT with its bootstrap 10-90% interval under it, e.g. `1.23` / `[0.98, 1.61]`.
pub fn ert_text(m: &MeasureSummary) -> String {
    match m.ert {
        None => "&ndash; (no success)".into(),
        Some(e) => format!(
            "{}<br><span class=\"iv\">[{}, {}]</span>",
            num(Some(e)),
            num(m.ert_p10),
            num(m.ert_p90)
        ),
    }
}

/// Success, median and ERT (with bootstrap 10-90% intervals) per target and configuration,
/// in CPU seconds and sample-evaluations.
pub fn success_table(report: &StatsReport, instance: &str, targets: &Targets) -> String {
    let mut last = None;
    let rows: Vec<Vec<String>> = report
        .configs
        .iter()
        .filter(|c| c.instance == instance)
        .map(|c| {
            // The target once per group of its configurations.
            let first = last != Some(c.target);
            last = Some(c.target);
            vec![
                if first {
                    targets.text(instance, c.target)
                } else {
                    String::new()
                },
                escape(&c.config),
                format!("{}/{}", c.cpu.successes, c.cpu.trials),
                num(c.cpu.quantiles[2]),
                ert_text(&c.cpu),
                num(c.evaluations.quantiles[2]),
                ert_text(&c.evaluations),
            ]
        })
        .collect();
    data_table(
        "success",
        "Per target and configuration: trials that reached the target, the median time to it \
         (<i>&ndash;</i> when fewer than half did) and the ERT (expected run time with restarts: \
         all time spent over the successes) with its bootstrap [10%, 90%] interval, in CPU \
         seconds and in sample-evaluations.",
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
        &[2, 3, 4, 5, 6],
    )
}

fn p_holm(p: Option<f64>, holm: Option<f64>) -> String {
    match (p, holm) {
        (Some(p), Some(h)) => format!("{} ({})", p_value(Some(p)), p_value(Some(h))),
        _ => "-".into(),
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
pub fn tests_table(report: &StatsReport, instance: &str, targets: &Targets) -> String {
    let order = page_order();
    let rows: Vec<Vec<String>> = report
        .tests
        .iter()
        .filter(|t| t.instance == instance)
        .map(|t| {
            let mut row = vec![
                targets.text(instance, t.target),
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
    let mut numeric = Vec::new();
    for test in &order {
        if test.p.is_some() {
            numeric.push(head.len());
            head.push(format!("{} p (Holm)", test.name));
            if let Some(e) = &test.effect {
                numeric.push(head.len());
                head.push(e.name.to_string());
            }
        } else {
            head.push(test.name.to_string());
        }
    }
    let about: Vec<String> = order
        .iter()
        .map(|t| format!("<i>{}</i>: {}", escape(t.name), escape(t.about)))
        .collect();
    let caption = format!(
        "Every pair of configurations per target and measure. p-values with their Holm-adjusted \
         value in brackets (over the pairs of one target and measure); below 1e-16 they read \
         &lt; 1e-16. {}.",
        about.join("; ")
    );
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    data_table("tests", &caption, &head, &rows, &numeric)
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
                format!("{} &ndash; {}", num(q.rmse_min), num(q.rmse_max)),
                num(q.end_cpu_median),
            ]
        })
        .collect();
    data_table(
        "finals",
        "The best full-data RMSE at the end of each trial (trials stop at the run target, at the \
         budget, or by themselves) and the CPU time at which they ended.",
        &[
            "configuration",
            "trials",
            "ended by themselves",
            "median final RMSE",
            "final RMSE range",
            "median end CPU s",
        ],
        &rows,
        &[1, 2, 3, 4, 5],
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
        "<p>Lowest final RMSE {} by {} (trial {}, seed {}).</p>\n",
        significant(r.result.best_rmse, 6),
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
                .map_or_else(|| "-".into(), |v| significant(v, 6));
            vec![escape(name), v, fixed.into()]
        })
        .collect();
    // As in `fit`'s output: a mirrored form of the same fit would otherwise read as another.
    let equivalent = layout
        .equivalence_note()
        .map(|n| format!("<p class=\"note\">{}</p>\n", escape(&n)))
        .unwrap_or_default();
    intro
        + &data_table(
            "params",
            "The parameters of that trial's best candidate in physical units (six significant \
             digits; the results file holds every digit).",
            &["parameter", "value", ""],
            &rows,
            &[1],
        )
        + &equivalent
}
