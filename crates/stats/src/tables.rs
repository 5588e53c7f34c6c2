//! The statistics as CSV files and as the table printed after a run.

use super::{Cell, Direction, Measure, PairTest, StatsReport, TESTS, TestResult};

/// The per-configuration statistics as CSV (one row per instance, configuration, target,
/// measure); the columns after `measure` are [`MeasureSummary::cells`](super::MeasureSummary::cells).
pub fn configs_csv(report: &StatsReport) -> String {
    let mut s = String::new();
    for c in &report.configs {
        for (m, ms) in [
            (Measure::CpuSeconds, &c.cpu),
            (Measure::Evaluations, &c.evaluations),
        ] {
            let cells = ms.cells();
            if s.is_empty() {
                s = header(&["instance", "config", "target", "measure"], &cells);
            }
            let mut fields = vec![
                csv_field(&c.instance),
                csv_field(&c.config),
                c.target.to_string(),
                m.short().to_string(),
            ];
            fields.extend(cells.iter().map(|(_, v)| v.csv()));
            s.push_str(&fields.join(","));
            s.push('\n');
        }
    }
    if s.is_empty() {
        let empty = super::summarise(&[], 0, 0);
        s = header(&["instance", "config", "target", "measure"], &empty.cells());
    }
    s
}

/// A CSV header: the leading columns, then the cells' names.
fn header(first: &[&str], cells: &[(&'static str, Cell)]) -> String {
    let mut names: Vec<&str> = first.to_vec();
    names.extend(cells.iter().map(|c| c.0));
    names.join(",") + "\n"
}

/// The pairwise tests as CSV: the pair, then every test's columns in [`TESTS`] order.
pub fn tests_csv(report: &StatsReport) -> String {
    let mut names = vec!["instance", "target", "measure", "a", "b"];
    for t in TESTS {
        names.extend(TestResult::empty(t).cells().iter().map(|c| c.0));
    }
    let mut s = names.join(",") + "\n";
    for t in &report.tests {
        let mut fields = vec![
            csv_field(&t.instance),
            t.target.to_string(),
            t.measure.short().to_string(),
            csv_field(&t.a),
            csv_field(&t.b),
        ];
        for r in &t.results {
            fields.extend(r.cells().iter().map(|(_, v)| v.csv()));
        }
        s.push_str(&fields.join(","));
        s.push('\n');
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

/// A target RMSE for titles and headings: at most six significant digits, so a relative
/// target (1% above a best-known RMSE of 0.09954...) reads 0.100538, not 0.10053773452859388;
/// a target written in the spec (0.11) stays as written.
pub fn fmt_target(t: f64) -> String {
    let rounded: f64 = format!("{t:.5e}").parse().unwrap_or(t);
    format!("{rounded}")
}

/// `t` with `digits` significant digits, trailing zeros dropped; in exponent form below 1e-4
/// and from 1e6 on (`1.23457e7`).
pub fn significant(t: f64, digits: usize) -> String {
    if t == 0.0 || !t.is_finite() {
        return format!("{t}");
    }
    let e = format!("{t:.*e}", digits.max(1) - 1);
    if t.abs() < 1e-4 || t.abs() >= 1e6 {
        let (m, x) = e.split_once('e').unwrap_or((&e, "0"));
        let m = if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.')
        } else {
            m
        };
        return format!("{m}e{x}");
    }
    let rounded: f64 = e.parse().unwrap_or(t);
    format!("{rounded}")
}

/// The fewest significant digits (4 to 8) that keep the targets of one instance apart.
pub fn target_digits(targets: &[f64]) -> usize {
    (4..=8)
        .find(|&d| {
            let shown: Vec<String> = targets.iter().map(|&t| significant(t, d)).collect();
            shown
                .iter()
                .enumerate()
                .all(|(i, s)| shown[..i].iter().all(|o| o != s))
        })
        .unwrap_or(8)
}

/// A relative change in percent with two significant digits: `+1%`, `+2.5%`, `+0.38%`.
fn percent(r: f64) -> String {
    let p = r * 100.0;
    let s = if p.abs() >= 10.0 {
        format!("{p:.0}")
    } else {
        significant(p, 2)
    };
    if p >= 0.0 {
        format!("+{s}%")
    } else {
        format!("{s}%")
    }
}

/// A target RMSE for reading: `digits` significant digits ([`target_digits`] of its
/// instance) and, when the best-known RMSE is known and the target within 10 times it, how far
/// above it: `0.1005 (+1%)` (a noiseless instance's best-known RMSE is near 0, where a
/// percentage means nothing).
pub fn target_text(t: f64, best_known: Option<f64>, digits: usize) -> String {
    let shown = significant(t, digits);
    match best_known.filter(|b| *b > 0.0 && b.is_finite() && t / b <= 10.0) {
        Some(b) => format!("{shown} ({})", percent(t / b - 1.0)),
        None => shown,
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
        .map(|c| c.config.chars().count())
        .max()
        .unwrap_or(6)
        .max(13);
    for c in &report.configs {
        if last != Some((c.instance.as_str(), c.target)) {
            out.push_str(&format!(
                "\n{} - target RMSE {}\n{}  {:>9}  {:>9} {:>9} {:>9}  {:>9} {:>21}  {:>10} {:>10}\n",
                c.instance,
                fmt_target(c.target),
                pad_right("configuration", width),
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
            "{}  {:>9}  {:>9} {:>9} {:>9}  {:>9} {:>21}  {:>10} {:>10}\n",
            pad_right(&c.config, width),
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
            "\n{} pairwise tests (Mann-Whitney, KS, log-rank, Holm-adjusted): see tests.csv\n",
            sig.len()
        ));
    } else if !sig.is_empty() {
        out.push_str("\nPairwise (CPU time; Holm-adjusted p-values; censored runs = +inf)\n");
        for t in sig {
            out.push_str(&format!(
                "  {} q={}: {} vs {}: {}\n",
                t.instance,
                t.target,
                t.a,
                t.b,
                pair_text(t)
            ));
        }
    }
    out
}

/// A pair's tests in one line: each p-value test's Holm-adjusted p-value (with its effect),
/// then each direction-only test's outcome.
fn pair_text(t: &PairTest) -> String {
    let mut parts = Vec::new();
    for r in t.results.iter().filter(|r| r.test.p.is_some()) {
        let mut s = format!("{} p={}", r.test.name, fmt_p(r.p_holm));
        if let Some(e) = &r.test.effect {
            s.push_str(&format!(" ({} {})", e.short, fmt_num(r.effect)));
        }
        parts.push(s);
    }
    for r in t.results.iter().filter(|r| r.test.p.is_none()) {
        parts.push(direction_text(r, &t.a, &t.b));
    }
    parts.join(", ")
}

/// A direction-only test's outcome in words (`AED dominates`, `curves cross`).
pub fn direction_text(r: &TestResult, a: &str, b: &str) -> String {
    let [sooner, neither] = r.test.direction_words;
    match r.direction {
        Direction::A => format!("{a} {sooner}"),
        Direction::B => format!("{b} {sooner}"),
        Direction::Neither => neither.to_string(),
    }
}

fn finals_table(report: &StatsReport, width: usize) -> String {
    let mut out = String::new();
    let mut last: Option<&str> = None;
    for q in &report.finals {
        if last != Some(q.instance.as_str()) {
            out.push_str(&format!(
                "\n{} - final RMSE per trial\n{}  {:>7}  {:>9} {:>9} {:>9} {:>9}  {:>11} {:>9}\n",
                q.instance,
                pad_right("configuration", width),
                "trials",
                "mean",
                "median",
                "min",
                "max",
                "median end s",
                "finished"
            ));
            last = Some(q.instance.as_str());
        }
        let r = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |x| format!("{x:.6}"));
        out.push_str(&format!(
            "{}  {:>7}  {:>9} {:>9} {:>9} {:>9}  {:>11} {:>9}\n",
            pad_right(&q.config, width),
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

/// `s` left-aligned in `width` characters. Unlike `format!("{s:<width$}")`, which panics for
/// widths from 65,536 on, this takes any width (labels of older results are not limited).
pub fn pad_right(s: &str, width: usize) -> String {
    let fill = width.saturating_sub(s.chars().count());
    let mut out = String::with_capacity(s.len() + fill);
    out.push_str(s);
    out.extend(std::iter::repeat_n(' ', fill));
    out
}

fn fmt_p(p: Option<f64>) -> String {
    match p {
        None => "-".into(),
        // The tests' tails underflow only below about 1e-300.
        Some(0.0) => "<1e-300".into(),
        Some(p) if p < 1e-4 => format!("{p:.1e}"),
        Some(p) => format!("{p:.4}"),
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ConfigStats, FinalQuality, summarise};
    use super::*;

    #[test]
    fn targets_read_with_at_most_six_significant_digits() {
        assert_eq!(fmt_target(0.10053773452859388), "0.100538");
        assert_eq!(fmt_target(0.11), "0.11");
        assert_eq!(fmt_target(0.037), "0.037");
        assert_eq!(fmt_target(5e-5), "0.00005");
        assert_eq!(fmt_target(12345678.9), "12345700");
    }

    fn report_with_labels(labels: &[String]) -> StatsReport {
        let summary = summarise(&[], 0, 0);
        StatsReport {
            bootstrap: 0,
            configs: labels
                .iter()
                .map(|l| ConfigStats {
                    instance: "i".into(),
                    config: l.clone(),
                    target: 0.1,
                    cpu: summary.clone(),
                    evaluations: summary.clone(),
                })
                .collect(),
            tests: vec![],
            finals: labels
                .iter()
                .map(|l| FinalQuality {
                    instance: "i".into(),
                    config: l.clone(),
                    trials: 0,
                    rmse_mean: None,
                    rmse_median: None,
                    rmse_min: None,
                    rmse_max: None,
                    end_cpu_median: None,
                    end_cpu_max: None,
                    finished: 0,
                })
                .collect(),
        }
    }

    /// `format!("{:<width$}")` panics from width 65,536 on; results written before labels
    /// were limited may hold such labels.
    #[test]
    fn table_takes_labels_of_any_length() {
        let long = "L".repeat(70_000);
        let t = table(&report_with_labels(&[long.clone(), "AED".into()]));
        let rows: Vec<&str> = t.lines().filter(|l| l.starts_with("AED ")).collect();
        assert_eq!(rows.len(), 2, "{}", &t[..200]);
        // Columns stay aligned: the short label is padded to the long one's width.
        for row in rows {
            assert_eq!(row[70_000..].chars().next(), Some(' '));
            assert!(row[3..70_000].chars().all(|c| c == ' '));
        }
        assert_eq!(t.matches(&long).count(), 2);
    }

    #[test]
    fn padding_counts_characters() {
        assert_eq!(pad_right("AED", 5), "AED  ");
        assert_eq!(pad_right("φ=1", 4), "φ=1 ");
        assert_eq!(pad_right("toolong", 3), "toolong");
    }
}
