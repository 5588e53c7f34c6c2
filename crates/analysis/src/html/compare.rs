//! The comparison page: what was compared (A and B side by side), the options, the verdict
//! table and the RTDs of A and B overlaid per instance and target.

use brdf_graphics::chart::{Chart, Style};

use super::figures::figure;
use super::format::{num, p_value};
use super::{PageError, anchor, data_table, date, document, escape, para, section, table};
use crate::compare::text::change_text;
use crate::compare::{Comparison, Entry, MeasureRow, Row, Verdict, budget_text};
use crate::figures::Colors;
use crate::folder::Folder;
use crate::stats::{Group, Measure, MeasureSummary};

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
    body.push_str(&section(
        "per-configuration",
        2,
        "Per configuration",
        &per_configuration(c),
    ));
    body.push_str(&section("verdicts", 2, "Verdicts", &verdicts(c)));
    body.push_str(&section("sides", 2, "Results compared", &sides(a, b)));
    let colors = colors(a, b);
    body.push_str(&section(
        "rtds",
        2,
        "RTDs of A and B",
        &overlays(entries, c, &colors)?,
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

/// ERT with its bootstrap [10%, 90%] interval, as each side's own analysis has it.
fn ert_interval(m: &MeasureSummary) -> String {
    match m.ert {
        None => "&ndash;".into(),
        Some(e) => format!(
            "<span class=\"t\">{}</span> <span class=\"iv t\">[{}, {}]</span>",
            num(Some(e)),
            num(m.ert_p10),
            num(m.ert_p90)
        ),
    }
}

/// A p-value with its Holm-adjusted value.
fn p_cell(m: &MeasureRow) -> String {
    match (m.test.p, m.test.p_holm) {
        (Some(p), Some(h)) => format!(
            "<span class=\"t\">{}</span> <span class=\"t\">(Holm {})</span>",
            p_value(Some(p)),
            p_value(Some(h))
        ),
        _ => "-".into(),
    }
}

/// ERT of A and B with intervals and the change; median of A and B and the change; the
/// log-rank test with its hazard ratio; of one measure.
fn measure_cells(m: Option<&MeasureRow>) -> Vec<String> {
    let Some(m) = m else {
        return vec![String::new(); 3];
    };
    vec![
        format!(
            "A {}<br>B {}<br>{}",
            ert_interval(&m.a),
            ert_interval(&m.b),
            change_text(m.ert_change)
        ),
        format!(
            "<span class=\"t\">{} &rarr;</span> <span class=\"t\">{}</span><br>{}",
            num(m.a.quantiles[2]),
            num(m.b.quantiles[2]),
            change_text(m.median_change)
        ),
        format!("{}<br>HR {}", p_cell(m), num(m.test.effect)),
    ]
}

/// The other measure in one cell: changes of median and ERT, and the log-rank test.
fn other_cell(m: Option<&MeasureRow>) -> String {
    m.map_or_else(String::new, |m| {
        format!(
            "median {}<br>ERT {}<br>p {}",
            change_text(m.median_change),
            change_text(m.ert_change),
            p_cell(m)
        )
    })
}

fn row_cells(r: &Row, several: bool) -> Vec<String> {
    let success = r.measures.first().map_or_else(String::new, |m| {
        format!(
            "<span class=\"t\">{}/{} &rarr;</span> <span class=\"t\">{}/{}</span>",
            m.a.successes, m.a.trials, m.b.successes, m.b.trials
        )
    });
    let mut cells = Vec::new();
    if several {
        cells.push(escape(&r.instance));
    }
    cells.extend([
        escape(&r.config),
        r.target
            .map_or_else(|| "-".into(), crate::stats::fmt_target),
        verdict_cell(&r.verdict),
        success,
    ]);
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
    let several = {
        let mut names: Vec<&str> = c.rows.iter().map(|r| r.instance.as_str()).collect();
        names.dedup();
        names.len() > 1
    };
    let mut head: Vec<String> = Vec::new();
    if several {
        head.push("instance".into());
    }
    head.extend([
        "configuration".to_string(),
        "target".into(),
        "verdict".into(),
        "success A &rarr; B".into(),
        format!("ERT {main} [10%, 90%], change"),
        format!("median {main} A &rarr; B, change"),
        format!("log-rank p, hazard ratio A/B ({main})"),
        format!("{other}: changes, p"),
    ]);
    let first_num = head.len() - 5;
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let rows: Vec<Vec<String>> = c.rows.iter().map(|r| row_cells(r, several)).collect();
    let caption = format!(
        "One row per instance, configuration and target. The verdict uses {main}: the log-rank \
         test's p-value, Holm-adjusted over all compared pairs, below {}, a change of the median \
         of at least {}%, and a hazard ratio pointing the same way. ERTs carry their bootstrap \
         [10%, 90%] intervals from each side's own analysis; changes are B against A.",
        c.options.alpha,
        c.options.min_effect * 100.0
    );
    let numeric: Vec<usize> = (first_num..head.len()).collect();
    data_table("verdicts", &caption, &head, &rows, &numeric)
}

/// One line per configuration over all its instances and targets: verdicts counted, and the
/// geometric mean of B's ERT over A's in the verdict's measure.
fn per_configuration(c: &Comparison) -> String {
    let mut configs: Vec<&str> = Vec::new();
    for r in &c.rows {
        if !configs.contains(&r.config.as_str()) {
            configs.push(&r.config);
        }
    }
    let rows: Vec<Vec<String>> = configs
        .iter()
        .map(|cfg| {
            let rs: Vec<&Row> = c.rows.iter().filter(|r| r.config == *cfg).collect();
            let n = |v: &Verdict| rs.iter().filter(|r| &r.verdict == v).count();
            let incomparable = rs
                .iter()
                .filter(|r| matches!(r.verdict, Verdict::NotComparable(_)))
                .count();
            let logs: Vec<f64> = rs
                .iter()
                .filter_map(|r| r.measures.first())
                .filter_map(|m| m.ert_change)
                .filter(|x| x.is_finite() && *x > -1.0)
                .map(|x| (1.0 + x).ln())
                .collect();
            let geo = (!logs.is_empty())
                .then(|| (logs.iter().sum::<f64>() / logs.len() as f64).exp() - 1.0);
            vec![
                escape(cfg),
                (rs.len() - incomparable).to_string(),
                format!("<span class=\"faster\">{}</span>", n(&Verdict::Faster)),
                format!("<span class=\"slower\">{}</span>", n(&Verdict::Slower)),
                n(&Verdict::NoDifference).to_string(),
                incomparable.to_string(),
                change_text(geo),
            ]
        })
        .collect();
    let caption = format!(
        "Each configuration over all its instances and targets: verdicts counted, and the \
         geometric mean of B's ERT over A's (as a change) in {} over the pairs both reached.",
        c.options.measure.label()
    );
    data_table(
        "per-config",
        &caption,
        &[
            "configuration",
            "pairs compared",
            "faster",
            "slower",
            "no significant difference",
            "not comparable",
            "ERT change (geometric mean)",
        ],
        &rows,
        &[1, 2, 3, 4, 5, 6],
    )
}

/// One colour per configuration: A's order, then B's configurations A lacks.
fn colors(a: &Folder, b: &Folder) -> Colors {
    let mut labels = a.spec.config_labels();
    for l in b.spec.config_labels() {
        if !labels.contains(&l) {
            labels.push(l);
        }
    }
    Colors::new(&labels)
}

/// One chart per comparable (instance, target) and measure: each configuration's RTD in A
/// (solid) and B (dashed), in the configuration's colour.
fn overlays(
    entries: (&[Entry], &[Entry]),
    c: &Comparison,
    colors: &Colors,
) -> Result<String, PageError> {
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
            let chart = overlay_chart(entries, (inst, &configs), t, m, colors);
            let id = anchor(&["rtd", inst, m.short(), &t.to_string()]);
            let caption = format!(
                "Each configuration's RTD in A (solid) and in B (dashed), in its own colour: \
                 the fraction of trials that reached RMSE {} within a given number of {} \
                 (Kaplan-Meier; shaded: pointwise 95% bands). A dashed curve left of its solid \
                 one means B reaches the target sooner.",
                crate::stats::fmt_target(t),
                m.label()
            );
            s.push_str(&figure(&chart, &id, &caption)?);
        }
    }
    Ok(s)
}

fn overlay_chart(
    (ea, eb): (&[Entry], &[Entry]),
    (instance, configs): (&str, &[&str]),
    target: f64,
    measure: Measure,
    colors: &Colors,
) -> Chart {
    let mut groups = Vec::new();
    let mut sides: Vec<(&str, bool)> = Vec::new();
    for cfg in configs {
        for (es, side) in [(ea, "A"), (eb, "B")] {
            if let Some(g) = side_group(es, instance, cfg, side) {
                groups.push(g);
                sides.push((cfg, side == "A"));
            }
        }
    }
    let refs: Vec<&Group> = groups.iter().collect();
    let shown = crate::stats::target_text(target, None, 4);
    let mut chart =
        crate::figures::rtd_chart(instance, &refs, (target, &shown), measure, None, colors);
    chart.title = format!(
        "A (solid) vs B (dashed) - {instance}, target RMSE {}, {}",
        crate::stats::fmt_target(target),
        measure.label()
    );
    for (s, (config, is_a)) in chart.series.iter_mut().zip(sides) {
        s.color = colors.color(config);
        s.key = Some(config.to_string());
        s.style = if is_a { Style::Line } else { Style::Dashed };
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
