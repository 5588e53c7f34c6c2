//! The comparison as a plain-text table (what `brdf-sls compare` prints).

use super::{Comparison, MeasureRow, Row};
use crate::stats::{fmt_num, pad_right};

/// A relative change as a signed percentage (`+inf%` when only A reached).
pub fn change_text(c: Option<f64>) -> String {
    match c {
        None => "-".into(),
        Some(x) if x.is_infinite() => "+inf%".into(),
        Some(x) => format!("{:+.1}%", x * 100.0),
    }
}

/// A p-value with its Holm-adjusted value, e.g. `0.0012 (Holm 0.0036)`.
pub fn p_text(m: &MeasureRow) -> String {
    match (m.test.p, m.test.p_holm) {
        (Some(p), Some(h)) => format!("{} (Holm {})", p_fmt(p), p_fmt(h)),
        _ => "-".into(),
    }
}

fn p_fmt(p: f64) -> String {
    if p < 1e-4 {
        format!("{p:.1e}")
    } else {
        format!("{p:.4}")
    }
}

fn measure_cells(m: &MeasureRow) -> Vec<String> {
    vec![
        format!(
            "{} -> {} ({})",
            fmt_num(m.a.quantiles[2]),
            fmt_num(m.b.quantiles[2]),
            change_text(m.median_change)
        ),
        format!(
            "{} -> {} ({})",
            fmt_num(m.a.ert),
            fmt_num(m.b.ert),
            change_text(m.ert_change)
        ),
        p_text(m),
    ]
}

fn row_cells(r: &Row) -> Vec<String> {
    let mut cells = vec![
        r.instance.clone(),
        r.config.clone(),
        r.target.map_or_else(|| "-".into(), |t| t.to_string()),
        r.verdict.text(),
    ];
    for m in &r.measures {
        cells.extend(measure_cells(m));
    }
    cells
}

/// The verdict table: one line per pair, the verdict's measure first, then the other.
pub fn table(c: &Comparison) -> String {
    let primary = c.options.measure.label();
    let other = crate::stats::Measure::ALL
        .into_iter()
        .find(|m| *m != c.options.measure)
        .map_or("", |m| m.label());
    let mut header: Vec<String> = ["instance", "configuration", "target", "verdict"]
        .map(String::from)
        .to_vec();
    for m in [primary, other] {
        header.push(format!("median {m} A -> B"));
        header.push(format!("ERT {m} A -> B"));
        header.push(format!("log-rank p ({m})"));
    }
    let rows: Vec<Vec<String>> = std::iter::once(header)
        .chain(c.rows.iter().map(row_cells))
        .collect();
    let widths: Vec<usize> = (0..rows[0].len())
        .map(|i| {
            rows.iter()
                .filter_map(|r| r.get(i))
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for r in &rows {
        let cells: Vec<String> = r
            .iter()
            .zip(&widths)
            .map(|(s, w)| pad_right(s, *w))
            .collect();
        out.push_str(cells.join("  ").trim_end());
        out.push('\n');
    }
    out.push_str(&format!(
        "{} pairs compared, {} not comparable; {} significantly slower in B (alpha {}, Holm over pairs, minimum change of the median {}%, verdicts on {})\n",
        c.comparable(),
        c.rows.len() - c.comparable(),
        c.slower(),
        c.options.alpha,
        c.options.min_effect * 100.0,
        primary
    ));
    out
}
