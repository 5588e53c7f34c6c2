//! The comparison page: what was compared (A and B side by side), the options, the verdict
//! table and the RTDs of A and B overlaid per instance and target.

use brdf_graphics::chart::{Chart, Style, color};

use super::figures::figure;
use super::{PageError, anchor, date, document, escape, para, section, table};
use crate::compare::text::{change_text, p_text};
use crate::compare::{Comparison, Entry, MeasureRow, Row, Verdict, budget_text};
use crate::folder::Folder;
use crate::stats::{Group, Measure, fmt_num};

/// The comparison page of `a` (before) and `b` (after), with their entries and the verdicts.
pub fn compare_page(
    a: &Folder,
    b: &Folder,
    entries: (&[Entry], &[Entry]),
    c: &Comparison,
) -> Result<String, PageError> {
    let title = format!(
        "brdf-sls compare: {} vs {}",
        a.dir.display(),
        b.dir.display()
    );
    let mut body = format!("<h1>{}</h1>\n", escape(&title));
    body.push_str(&summary(c));
    body.push_str(&section("sides", 2, "Results compared", &sides(a, b)));
    body.push_str(&section("verdicts", 2, "Verdicts", &verdicts(c)));
    body.push_str(&section(
        "rtds",
        2,
        "RTDs of A and B",
        &overlays(entries, c)?,
    ));
    body.push_str(&para(
        "note",
        &format!("Written by brdf-sls {}.", brdf_experiment::PROGRAM_VERSION),
    ));
    Ok(document(&title, &body))
}

fn summary(c: &Comparison) -> String {
    let n = |v: Verdict| c.rows.iter().filter(|r| r.verdict == v).count();
    let text = format!(
        "{} pairs compared: {} faster in B, {} slower in B, {} without a significant difference; {} not comparable. \
Verdicts on {}: log-rank test, Holm-adjusted over the pairs at alpha {}, and a change of the median of at least {}%.",
        c.comparable(),
        n(Verdict::Faster),
        n(Verdict::Slower),
        n(Verdict::NoDifference),
        c.rows.len() - c.comparable(),
        c.options.measure.label(),
        c.options.alpha,
        c.options.min_effect * 100.0
    );
    para("verdict-summary", &text)
}

/// A and B side by side: folder, experiment, provenance, plan.
fn sides(a: &Folder, b: &Folder) -> String {
    let side = |f: &Folder| {
        let h = &f.contents.header;
        let kernels: Vec<&str> = f
            .contents
            .sessions
            .iter()
            .map(|s| s.kernel.as_str())
            .collect();
        let (present, planned) = f.progress();
        vec![
            escape(&f.dir.display().to_string()),
            escape(&h.experiment),
            escape(&h.fingerprint),
            escape(&h.program_version),
            escape(&kernels.join(", ")),
            escape(&super::provenance::machine_text(&h.machine)),
            date(h.created_unix),
            f.spec.seed.to_string(),
            format!("{present} / {planned}"),
            escape(&budget_text(&f.spec.budget)),
        ]
    };
    let keys = [
        "results",
        "experiment",
        "spec fingerprint",
        "program version",
        "kernel (per session)",
        "machine",
        "created",
        "master seed",
        "trials present / planned",
        "budget per trial",
    ];
    let (sa, sb) = (side(a), side(b));
    let rows: Vec<Vec<String>> = keys
        .iter()
        .zip(sa.into_iter().zip(sb))
        .map(|(k, (x, y))| vec![(*k).to_string(), x, y])
        .collect();
    let mut s = table("sides", &["", "A (before)", "B (after)"], &rows);
    for (name, f) in [("A", a), ("B", b)] {
        for n in &f.notes {
            s.push_str(&para("partial", &format!("{name}: {n}.")));
        }
    }
    s
}

fn verdict_cell(v: &Verdict) -> String {
    let class = match v {
        Verdict::Faster => "faster",
        Verdict::Slower => "slower",
        Verdict::NoDifference => "same",
        Verdict::NotComparable(_) => "incomparable",
    };
    format!("<span class=\"{class}\">{}</span>", escape(&v.text()))
}

/// Median and ERT of A and B with their changes, and the log-rank test, of one measure.
fn measure_cells(m: Option<&MeasureRow>) -> Vec<String> {
    let Some(m) = m else {
        return vec![String::new(); 3];
    };
    vec![
        format!(
            "{} &rarr; {} ({})",
            fmt_num(m.a.quantiles[2]),
            fmt_num(m.b.quantiles[2]),
            change_text(m.median_change)
        ),
        format!(
            "{} &rarr; {} ({})",
            fmt_num(m.a.ert),
            fmt_num(m.b.ert),
            change_text(m.ert_change)
        ),
        format!("{}; HR {}", p_text(m), fmt_num(m.test.effect)),
    ]
}

/// The other measure in one cell: changes of median and ERT, and the log-rank test.
fn other_cell(m: Option<&MeasureRow>) -> String {
    m.map_or_else(String::new, |m| {
        format!(
            "median {}, ERT {}; p {}",
            change_text(m.median_change),
            change_text(m.ert_change),
            p_text(m)
        )
    })
}

fn row_cells(r: &Row) -> Vec<String> {
    let success = r.measures.first().map_or_else(String::new, |m| {
        format!(
            "{}/{} &rarr; {}/{}",
            m.a.successes, m.a.trials, m.b.successes, m.b.trials
        )
    });
    let mut cells = vec![
        escape(&r.instance),
        escape(&r.config),
        r.target.map_or_else(|| "-".into(), |t| t.to_string()),
        verdict_cell(&r.verdict),
        success,
    ];
    cells.extend(measure_cells(r.measures.first()));
    cells.push(other_cell(r.measures.get(1)));
    cells
}

fn verdicts(c: &Comparison) -> String {
    let main = c.options.measure.label();
    let other = Measure::ALL
        .into_iter()
        .find(|m| *m != c.options.measure)
        .map_or("", |m| m.label());
    let head = [
        "instance".to_string(),
        "configuration".into(),
        "target".into(),
        "verdict".into(),
        "success A &rarr; B".into(),
        format!("median {main} A &rarr; B (change)"),
        format!("ERT {main} A &rarr; B (change)"),
        format!("log-rank p (Holm), hazard ratio A/B, {main}"),
        format!("{other}: changes, log-rank p (Holm)"),
    ];
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let rows: Vec<Vec<String>> = c.rows.iter().map(row_cells).collect();
    format!(
        "<div class=\"wide\">\n{}</div>\n",
        table("verdicts", &head, &rows)
    )
}

/// One chart per comparable (instance, target) and measure: each configuration's RTD in A
/// (solid) and B (dashed), in the configuration's colour.
fn overlays(entries: (&[Entry], &[Entry]), c: &Comparison) -> Result<String, PageError> {
    let mut keys: Vec<(&str, f64)> = Vec::new();
    for r in c.rows.iter().filter(|r| !r.measures.is_empty()) {
        let t = r.target.unwrap_or(f64::NAN);
        if !keys.iter().any(|(i, x)| *i == r.instance && *x == t) {
            keys.push((&r.instance, t));
        }
    }
    if keys.is_empty() {
        return Ok(para("note", "Nothing comparable: no RTDs to overlay."));
    }
    let mut s = String::new();
    for (inst, t) in keys {
        let configs: Vec<&str> = c
            .rows
            .iter()
            .filter(|r| r.instance == inst && r.target == Some(t) && !r.measures.is_empty())
            .map(|r| r.config.as_str())
            .collect();
        let others = Measure::ALL.into_iter().filter(|m| *m != c.options.measure);
        for m in std::iter::once(c.options.measure).chain(others) {
            let chart = overlay_chart(entries, inst, &configs, t, m);
            let id = anchor(&["rtd", inst, m.short(), &t.to_string()]);
            s.push_str(&figure(&chart, &id)?);
        }
    }
    Ok(s)
}

fn overlay_chart(
    (ea, eb): (&[Entry], &[Entry]),
    instance: &str,
    configs: &[&str],
    target: f64,
    measure: Measure,
) -> Chart {
    let mut groups = Vec::new();
    for cfg in configs {
        groups.extend(side_group(ea, instance, cfg, "A"));
        groups.extend(side_group(eb, instance, cfg, "B"));
    }
    let refs: Vec<&Group> = groups.iter().collect();
    let mut chart = crate::figures::rtd_chart(instance, &refs, target, measure, None);
    chart.title = format!(
        "A (solid) vs B (dashed) - {instance}, target RMSE {target}, {}",
        measure.label()
    );
    for (i, s) in chart.series.iter_mut().enumerate() {
        s.color = color(i / 2);
        s.style = if i % 2 == 0 {
            Style::Line
        } else {
            Style::Dashed
        };
    }
    chart
}

/// The trials of `instance` and `config` in one side's entries, labelled with the side.
fn side_group<'e>(es: &'e [Entry], instance: &str, config: &str, side: &str) -> Option<Group<'e>> {
    es.iter()
        .find(|e| e.instance == instance && e.config == config)
        .map(|e| Group {
            instance: e.instance.clone(),
            config: format!("{config} {side}"),
            records: e.records.iter().collect(),
        })
}
