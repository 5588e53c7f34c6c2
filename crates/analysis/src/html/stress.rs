//! The page of a stress report (`stress.html`): what `stress.md` shows, with the checks'
//! verdicts in colour (failures highlighted), the charts inline, and where and when it ran.

use brdf_graphics::chart::Chart;
use brdf_stress::StressReport;

use super::figures::figure;
use super::{PageError, date, document, escape, key_values, markdown, section, table};
use brdf_experiment::machine::MachineInfo;

/// The whole stress page of `report`, with `charts` (those of
/// [`crate::stress_charts::charts`]) inline, run on `machine` (`None`: the page is rewritten
/// from stress.json, which does not record it) and written at `written_unix`.
pub fn stress_page(
    report: &StressReport,
    charts: &[Chart],
    machine: Option<&MachineInfo>,
    written_unix: u64,
) -> Result<String, PageError> {
    let title = "brdf-sls stress: numerical stress report";
    let mut body = format!("<h1>{}</h1>\n", escape(title));
    let failed = report.failures().len();
    let (class, verdict) = if failed == 0 {
        ("pass", "PASSED")
    } else {
        ("fail", "FAILED")
    };
    body.push_str(&format!(
        "<p class=\"verdict-summary {class}\"><strong class=\"{class}\">{verdict}</strong>: {} of \
         {} checks passed.</p>\n",
        report.checks.len() - failed,
        report.checks.len()
    ));
    body.push_str(&facts(report, machine, written_unix));
    body.push_str(&section("checks", 2, "Checks", &checks(report)));
    body.push_str(&section(
        "kernels",
        2,
        "1. Kernel accuracy against double-double",
        &kernels(report, charts.first())?,
    ));
    body.push_str(&section(
        "suite",
        2,
        "2. Solver suite",
        &suite(report, charts.get(1))?,
    ));
    let mut diag = String::new();
    for d in &report.diagnostics {
        diag.push_str(&format!(
            "<h3>{} ({})</h3>\n{}",
            escape(&d.name),
            escape(&d.layout),
            markdown::blocks(&d.diagnosis.to_markdown())
        ));
    }
    body.push_str(&section("diagnostics", 2, "3. Fit diagnostics", &diag));
    Ok(document(title, &body))
}

/// Mode, seed, threads, kernels, times, program version, machine and date.
fn facts(r: &StressReport, machine: Option<&MachineInfo>, written_unix: u64) -> String {
    let s = r.seconds;
    key_values(&[
        ("mode", if r.quick { "quick" } else { "full" }.into()),
        ("seed", r.seed.to_string()),
        ("threads", r.threads.to_string()),
        ("kernels this CPU runs", escape(&r.simd_levels.join(", "))),
        (
            "wall time",
            format!(
                "{:.1} s (kernels {:.1} s, solver suite {:.1} s, diagnostics {:.1} s)",
                s[3], s[0], s[1], s[2]
            ),
        ),
        match machine {
            Some(_) => ("program", escape(brdf_experiment::PROGRAM_VERSION)),
            None => (
                "page rewritten by",
                escape(brdf_experiment::PROGRAM_VERSION),
            ),
        },
        (
            "machine",
            machine.map_or_else(
                || "not recorded in stress.json (this page was rewritten from it)".into(),
                |m| escape(&super::machine_text(m)),
            ),
        ),
        ("written", date(written_unix)),
    ])
}

/// A verdict cell: `pass` or a highlighted `FAIL`.
fn verdict(passed: bool) -> &'static str {
    if passed {
        "<span class=\"pass\">pass</span>"
    } else {
        "<span class=\"fail\">FAIL</span>"
    }
}

/// Every check with its verdict, measured value, tolerance and reason; failed rows tinted.
fn checks(r: &StressReport) -> String {
    let mut s = String::from(
        "<div class=\"scroll\">\n<table class=\"checks\">\n<thead><tr><th>check</th><th>result</th><th>measured</th>\
         <th>tolerance</th><th>why this tolerance</th></tr></thead>\n<tbody>\n",
    );
    for c in &r.checks {
        let class = if c.passed { "" } else { " class=\"fail\"" };
        s.push_str(&format!(
            "<tr{class}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(&c.name),
            verdict(c.passed),
            escape(&c.measured),
            escape(&c.tolerance),
            escape(&c.reason)
        ));
    }
    s.push_str("</tbody>\n</table>\n</div>\n");
    s
}

/// Section 1: the summary per kernel, the chart, then per kernel its regimes and Jacobian
/// columns (numbers formatted as in the Markdown).
fn kernels(r: &StressReport, chart: Option<&Chart>) -> Result<String, PageError> {
    let k = &r.kernels;
    let mut s = super::para(
        "",
        &format!(
            "{} batches of {} direction pairs over the layouts {}. Errors in ulps of the \
             reference value; \"normalised\" is the error over its forward-error bound (see the \
             crate docs of `reference`).",
            k.batches,
            k.batch_size,
            k.layouts.join("; ")
        ),
    );
    let rows: Vec<Vec<String>> = k
        .kernels
        .iter()
        .map(|ks| {
            vec![
                escape(&ks.kernel),
                ks.values.to_string(),
                format!("{:.2}", ks.median_ulps),
                format!("{:.1}", ks.p999_ulps),
                format!("{:.3e}", ks.max_ulps),
                format!("{:.3}", ks.max_normalised),
                ks.class_mismatches.to_string(),
                ks.missed_overflow.to_string(),
                ks.spurious_failures.to_string(),
                ks.jacobian_nonfinite_on_success.to_string(),
            ]
        })
        .collect();
    s.push_str(&table(
        "kernels",
        &[
            "kernel",
            "values",
            "median ulps",
            "p99.9 ulps",
            "max ulps",
            "max normalised",
            "class mismatches",
            "missed overflow",
            "spurious failures",
            "non-finite J on success",
        ],
        &rows,
    ));
    if let Some(c) = chart {
        s.push_str(&figure(
            c,
            "kernel-ulps-histogram",
            "The share of each kernel's values whose error against the double-double reference \
             falls in each bin of ulps (units in the last place); further left is more accurate. \
             Kernels that agree bin for bin lie on top of each other (distinct dash patterns \
             keep each visible).",
        )?);
    }
    for ks in &k.kernels {
        let mut body = String::new();
        let rows: Vec<Vec<String>> = ks
            .by_regime
            .iter()
            .map(|g| {
                vec![
                    format!("{:?}", g.regime),
                    g.count.to_string(),
                    format!("{:.1}", g.p999_ulps),
                    format!("{:.3e}", g.max_ulps),
                    format!("{:.3}", g.max_normalised),
                ]
            })
            .collect();
        body.push_str(&table(
            "regimes",
            &[
                "regime",
                "values",
                "p99.9 ulps",
                "max ulps",
                "max normalised",
            ],
            &rows,
        ));
        if !ks.columns.is_empty() {
            let rows: Vec<Vec<String>> = ks
                .columns
                .iter()
                .map(|c| {
                    vec![
                        escape(&c.role),
                        c.columns.to_string(),
                        format!("{:.2e}", c.p999_rel_error),
                        format!("{:.2e}", c.max_rel_error),
                        format!("{:.3}", c.max_normalised),
                        c.excluded_near_clamp.to_string(),
                    ]
                })
                .collect();
            body.push_str(&table(
                "columns",
                &[
                    "Jacobian column",
                    "batch-columns",
                    "p99.9 rel. error",
                    "max rel. error",
                    "max normalised",
                    "excluded (at the clamp)",
                ],
                &rows,
            ));
        }
        body.push_str(&super::para(
            "",
            &format!("Worst value: {}", ks.worst_value),
        ));
        if let Some(m) = &ks.first_mismatch {
            body.push_str(&super::para("fail", &format!("First mismatch: {m}")));
        }
        s.push_str(&section(
            &super::anchor(&["kernel", &ks.kernel]),
            3,
            &ks.kernel,
            &body,
        ));
    }
    Ok(s)
}

/// Section 2: the counts, the map, every case (suite failures tinted) and the criteria.
fn suite(r: &StressReport, chart: Option<&Chart>) -> Result<String, PageError> {
    let su = &r.suite;
    let mut s = super::para(
        "",
        &format!(
            "NIST StRD: {}/{} right. Moré-Garbow-Hillstrom: {}. BRDF hostile cases: {}/{} right.",
            su.nist_right, su.nist_total, su.mgh_status, su.brdf_right, su.brdf_total
        ),
    );
    if let Some(c) = chart {
        s.push_str(&figure(
            c,
            "solver-suite-map",
            "Every case of the solver suite, one point per case in suite order within its group: \
             filled green where the solver got it right, hollow where it returned a failure code, \
             filled where the suite counts a failure.",
        )?);
    }
    s.push_str(
        "<div class=\"scroll\">\n<table class=\"cases\">\n<thead><tr><th>group</th><th>case</th><th>code</th>\
         <th>outcome</th><th>right</th><th>measured</th><th>iterations</th>\
         <th>evaluations (r / J)</th><th>suite failure</th></tr></thead>\n<tbody>\n",
    );
    for c in &su.cases {
        // A suite failure fails a check; a wrong answer with a failure code is expected of
        // some hard cases, so only the former is tinted.
        let class = if c.failure.is_some() {
            " class=\"fail\""
        } else {
            ""
        };
        let cells = [
            escape(&c.group),
            escape(&c.name),
            c.code.map_or("-".into(), |v| v.to_string()),
            escape(&c.outcome),
            if c.right { "yes" } else { "no" }.into(),
            escape(&c.measured),
            c.iterations.to_string(),
            format!("{} / {}", c.residual_evaluations, c.jacobian_evaluations),
            escape(c.failure.as_deref().unwrap_or("")),
        ];
        s.push_str(&format!(
            "<tr{class}><td>{}</td></tr>\n",
            cells.join("</td><td>")
        ));
    }
    s.push_str("</tbody>\n</table>\n</div>\n");
    let mut crit: Vec<&str> = su.cases.iter().map(|c| c.criterion.as_str()).collect();
    crit.sort_unstable();
    crit.dedup();
    s.push_str("<p>Criteria:</p>\n<ul>\n");
    for c in crit {
        s.push_str(&format!("<li>{}</li>\n", escape(c)));
    }
    s.push_str("</ul>\n");
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_model::{named_params, synthetic};
    use brdf_stress::{NamedData, Sizes, StressOptions};

    /// A quick run at reduced sizes (every section runs): the page names every check, shows
    /// every kernel and case, inlines both charts, and its markup balances.
    #[test]
    fn the_quick_runs_page_names_every_check_and_is_well_formed() {
        let data = synthetic(&named_params("tuning").unwrap(), 200, 0.01, 3);
        let opts = StressOptions {
            quick: true,
            data: vec![NamedData {
                name: "tiny <synthetic>".into(),
                data,
            }],
            seed: 7,
            threads: Some(2),
            sizes: Some(Sizes {
                batches: 96,
                subsamples: 2,
                bootstrap: 8,
                starts: 2,
                synthetic_samples: 300,
            }),
            progress: None,
        };
        let mut report = brdf_stress::run(&opts).unwrap();
        // One failed check to see it highlighted.
        report.checks[0].passed = false;
        let charts: Vec<Chart> = crate::stress_charts::charts(&report)
            .into_iter()
            .map(|(_, c)| c)
            .collect();
        let page = stress_page(&report, &charts, Some(&MachineInfo::current(2)), 0).unwrap();
        super::super::wellformed::check(&page).unwrap();
        for c in &report.checks {
            assert!(
                page.contains(&escape(&c.name)),
                "page lacks check {}",
                c.name
            );
        }
        for k in &report.kernels.kernels {
            assert!(page.contains(&format!("<h3>{}</h3>", escape(&k.kernel))));
        }
        for c in &report.suite.cases {
            assert!(
                page.contains(&escape(&c.name)),
                "page lacks case {}",
                c.name
            );
        }
        assert!(page.contains("tiny &lt;synthetic&gt;") && !page.contains("<synthetic>"));
        assert_eq!(page.matches("<svg role=\"img\"").count(), 2);
        assert!(page.contains("<tr class=\"fail\"><td>"));
        assert!(page.contains("FAILED</strong>"));
        assert!(page.contains("1970-01-01T00:00:00Z"));
    }
}
