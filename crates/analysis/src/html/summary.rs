//! The answer first: the summary tables of a run (best configuration per instance and target
//! in bold, the others' ERT ratios, significance marks), one sentence per instance in words,
//! per-configuration aggregates, the ranking and the matrix of significant outcomes.

use super::format::{num, p_value, rate, ratio, target, target_digits};
use super::{data_table, escape};
use crate::analysis::summary::{ALPHA, Summary, SummaryRow};
use crate::stats::Measure;
use brdf_experiment::spec::Spec;

/// How a measure is named in sentences.
fn unit(m: Measure) -> &'static str {
    match m {
        Measure::CpuSeconds => "CPU seconds",
        Measure::Evaluations => "sample-evaluations",
    }
}

/// Each instance's target texts (`0.1005 (+1%)`), by (instance, target).
pub struct Targets {
    /// Per instance (as the summary names it): its digits and best-known RMSE.
    instances: Vec<(String, usize, Option<f64>)>,
}

impl Targets {
    /// The targets of `spec`'s instances, each named `prefix` and its name.
    pub fn new(spec: &Spec, prefix: &str) -> Targets {
        let mut t = Targets::none();
        t.add(spec, prefix);
        t
    }

    /// No instance yet.
    pub fn none() -> Targets {
        Targets {
            instances: Vec::new(),
        }
    }

    /// Adds `spec`'s instances, each named `prefix` and its name.
    pub fn add(&mut self, spec: &Spec, prefix: &str) {
        self.instances.extend(spec.instances.iter().map(|i| {
            (
                format!("{prefix}{}", i.name),
                target_digits(&i.targets),
                i.best_known.as_ref().map(|b| b.rmse),
            )
        }));
    }

    /// `t` of `instance` for reading, never broken across lines.
    pub fn text(&self, instance: &str, t: f64) -> String {
        let inst = self.instances.iter().find(|i| i.0 == instance);
        let (digits, best) = inst.map_or((4, None), |i| (i.1, i.2));
        format!("<span class=\"t\">{}</span>", target(t, best, digits))
    }
}

/// One cell of the summary table.
fn cell(s: &Summary, r: &SummaryRow, i: usize) -> String {
    let Some(c) = &r.cells[i] else {
        return String::new();
    };
    let tried = format!("{}/{}", c.successes, c.trials);
    let title = format!(
        "{}: ERT {} {}, {} trials reached the target{}",
        s.configs[i],
        num(c.ert),
        unit(s.measure),
        tried,
        c.p_holm
            .map(|p| format!(
                ", log-rank p (Holm) {} against the best",
                p_value(Some(p)).replace("&lt;", "<")
            ))
            .unwrap_or_default()
    );
    let title = escape(&title);
    if r.best == Some(i) {
        return format!(
            "<span title=\"{title}\"><b>{}</b> <span class=\"sr\">{}</span></span>",
            num(c.ert),
            rate(c.successes as f64 / c.trials.max(1) as f64)
        );
    }
    match c.ratio {
        None => format!("<span class=\"none\" title=\"{title}\">&ndash; {tried}</span>"),
        Some(q) => {
            let mark = if c.significant {
                "<sup class=\"sig\">*</sup>"
            } else {
                ""
            };
            let sr = if c.successes < c.trials {
                format!(
                    " <span class=\"sr\">{}</span>",
                    rate(c.successes as f64 / c.trials.max(1) as f64)
                )
            } else {
                String::new()
            };
            format!("<span title=\"{title}\">{}{mark}{sr}</span>", ratio(q))
        }
    }
}

/// How to read the summary tables (once, above both).
pub fn how_to_read_tables() -> String {
    format!(
        "<p class=\"tcap\">Per instance and target (rows) and configuration (columns): the \
         lowest ERT in <b>bold</b> with the share of trials that reached the target; every other \
         configuration's ERT as a multiple of it (&times;4.28 needs 4.28 times as much), with its \
         success rate when below 100%. <sup class=\"sig\">*</sup> the best reaches the target \
         significantly sooner (log-rank test, Holm-adjusted over the pairs of the target, p &lt; \
         {ALPHA}); &ndash; 0/20: no trial reached it. The last rows aggregate each configuration \
         over all rows. Hover a cell for its numbers.</p>\n"
    )
}

/// The caption of a summary table.
fn caption(s: &Summary) -> String {
    match s.measure {
        Measure::Evaluations => {
            "<b>ERT in sample-evaluations</b> (rows of data evaluated: the same on every machine)"
                .into()
        }
        Measure::CpuSeconds => "<b>ERT in CPU seconds</b> (this machine, this kernel)".into(),
    }
}

/// The summary table of one measure: rows (instance, target), columns configurations, and
/// per-configuration aggregates in the last rows when there are several rows.
pub fn table(s: &Summary, targets: &Targets, several_instances: bool) -> String {
    let mut head: Vec<String> = Vec::new();
    if several_instances {
        head.push("instance".into());
    }
    head.push("target RMSE".into());
    head.extend(s.configs.iter().map(|c| escape(c)));
    let first = head.len() - s.configs.len();
    let mut rows: Vec<Vec<String>> = Vec::new();
    for (k, r) in s.rows.iter().enumerate() {
        let mut row = Vec::new();
        if several_instances {
            // The instance once per group of its targets.
            let repeated = k > 0 && s.rows[k - 1].instance == r.instance;
            row.push(if repeated {
                String::new()
            } else {
                escape(&r.instance)
            });
        }
        row.push(targets.text(&r.instance, r.target));
        row.extend((0..s.configs.len()).map(|i| cell(s, r, i)));
        rows.push(row);
    }
    if s.rows.len() > 1 {
        let lead = |label: &str| {
            let mut row = vec![format!("<b>{label}</b>")];
            row.extend(std::iter::repeat_n(String::new(), first - 1));
            row
        };
        let mut solved = lead("targets reached");
        let mut best = lead("best on");
        let mut geo = lead("geometric-mean ratio");
        for a in &s.aggregates {
            solved.push(format!("{}/{}", a.solved, a.pairs));
            best.push(a.best.to_string());
            geo.push(a.geo_mean_ratio.map_or_else(|| "&ndash;".into(), ratio));
        }
        rows.extend([solved, best, geo]);
    }
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let numeric: Vec<usize> = (first..head.len()).collect();
    data_table("summary", &caption(s), &head, &rows, &numeric)
}

/// A range of values as text: `×4.28` or `×4.28 to ×6.02` (one value when both read alike).
fn range(lo: f64, hi: f64, f: impl Fn(f64) -> String) -> String {
    let (a, b) = (f(lo), f(hi));
    if a == b { a } else { format!("{a} to {b}") }
}

/// "all 4 targets", "3 of 4 targets", "the one target", "both targets".
fn of(k: usize, n: usize) -> String {
    match (k, n) {
        (1, 1) => "the one target".into(),
        (2, 2) => "both targets".into(),
        (k, n) if k == n => format!("all {n} targets"),
        (k, n) => format!("{k} of {n} targets"),
    }
}

/// Names joined for a sentence: `A`, `A and B`, `A, B and C`.
fn names(v: &[String]) -> String {
    match v {
        [] => String::new(),
        [a] => a.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// One sentence on `instance`: which configuration is best at which targets, by how much the
/// others trail (as ratios of ERT, smallest first) and where the difference is significant.
pub fn sentence(s: &Summary, instance: &str, targets: &Targets) -> String {
    let rows: Vec<&SummaryRow> = s.instance_rows(instance).collect();
    let n = rows.len();
    let reached: Vec<&SummaryRow> = rows.iter().copied().filter(|r| r.best.is_some()).collect();
    let inst = escape(instance);
    if reached.is_empty() {
        return format!("On {inst}, no configuration reached any target within the budget.");
    }
    let mut bests: Vec<usize> = Vec::new();
    for r in &reached {
        let b = r.best.unwrap_or(0);
        if !bests.contains(&b) {
            bests.push(b);
        }
    }
    let mut out = format!("On {inst}, ");
    if let [b] = bests[..] {
        let erts: Vec<f64> = reached
            .iter()
            .filter_map(|r| r.cells[b].as_ref().and_then(|c| c.ert))
            .collect();
        let (lo, hi) = erts
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, z), &e| (a.min(e), z.max(e)));
        out.push_str(&format!(
            "<b>{}</b> has the lowest ERT at {} ({} {})",
            escape(&s.configs[b]),
            of(reached.len(), n),
            range(lo, hi, |x| num(Some(x))),
            unit(s.measure)
        ));
        if reached.len() < n {
            out.push_str(&format!(
                " and no configuration reached the other {}",
                n - reached.len()
            ));
        }
    } else {
        let parts: Vec<String> = bests
            .iter()
            .map(|&b| {
                let at: Vec<String> = reached
                    .iter()
                    .filter(|r| r.best == Some(b))
                    .map(|r| targets.text(instance, r.target))
                    .collect();
                format!("<b>{}</b> at {}", escape(&s.configs[b]), names(&at))
            })
            .collect();
        out.push_str(&format!("the lowest ERT is {}", parts.join(", ")));
    }
    // Every other configuration: its ratios where another is best, and where it is slower
    // significantly.
    let (mut trail, mut none) = (Vec::new(), Vec::new());
    let (mut all_sig, mut some_sig, mut no_sig) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..s.configs.len() {
        let mine: Vec<&SummaryRow> = reached
            .iter()
            .copied()
            .filter(|r| r.best != Some(i) && r.cells[i].is_some())
            .collect();
        if mine.is_empty() {
            continue;
        }
        let name = escape(&s.configs[i]);
        let ratios: Vec<f64> = mine
            .iter()
            .filter_map(|r| r.cells[i].as_ref().and_then(|c| c.ratio))
            .collect();
        if ratios.is_empty() {
            none.push(name);
            continue;
        }
        let (lo, hi) = ratios
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, z), &e| (a.min(e), z.max(e)));
        let missed = mine.len() - ratios.len();
        let mut t = format!("{name} {}", range(lo, hi, ratio));
        if missed > 0 {
            t.push_str(&format!(" (no success at {})", of(missed, mine.len())));
        }
        trail.push((lo, t));
        let sig = mine
            .iter()
            .filter(|r| r.cells[i].as_ref().is_some_and(|c| c.significant))
            .count();
        match sig {
            0 => no_sig.push(name),
            k if k == mine.len() => all_sig.push(name),
            _ => some_sig.push(name),
        }
    }
    trail.sort_by(|a, b| a.0.total_cmp(&b.0));
    let trail: Vec<String> = trail.into_iter().map(|t| t.1).collect();
    if !trail.is_empty() {
        out.push_str(&format!("; the others need {}", names(&trail)));
    }
    if !none.is_empty() {
        let verb = if none.len() == 1 { "reaches" } else { "reach" };
        out.push_str(&format!("; {} {verb} none of them", names(&none)));
    }
    out.push('.');
    let tested = all_sig.len() + some_sig.len() + no_sig.len();
    if tested > 0 {
        if some_sig.is_empty() && no_sig.is_empty() {
            out.push_str(" Every difference is significant.");
        } else if all_sig.is_empty() && some_sig.is_empty() {
            out.push_str(" No difference is significant.");
        } else {
            let mut parts = Vec::new();
            if !all_sig.is_empty() {
                parts.push(format!("significantly slower: {}", names(&all_sig)));
            }
            if !some_sig.is_empty() {
                parts.push(format!("at some targets: {}", names(&some_sig)));
            }
            if !no_sig.is_empty() {
                parts.push(format!("not significantly: {}", names(&no_sig)));
            }
            let mut p = parts.join("; ");
            if let Some(c) = p.get(..1) {
                p = c.to_uppercase() + &p[1..];
            }
            out.push_str(&format!(" {p}."));
        }
    }
    out
}

/// The ranking over all (instance, target) pairs in the summary's measure.
pub fn ranking(s: &Summary) -> String {
    let rows: Vec<Vec<String>> = s
        .ranking()
        .into_iter()
        .enumerate()
        .map(|(k, i)| {
            let a = &s.aggregates[i];
            vec![
                (k + 1).to_string(),
                escape(&s.configs[i]),
                format!("{:.2}", a.mean_rank),
                a.geo_mean_ratio.map_or_else(|| "&ndash;".into(), ratio),
                format!("{}/{}", a.solved, a.pairs),
                a.best.to_string(),
                a.wins.to_string(),
                a.losses.to_string(),
            ]
        })
        .collect();
    let caption = format!(
        "<b>Ranking in {}</b> over every (instance, target) pair: mean rank by ERT (1 is the \
         lowest; a configuration without success ranks last), the geometric mean of its ERT \
         ratio to the best over the pairs it solved, pairs with a success, pairs where it is \
         best, and how often it is significantly sooner or later than another configuration \
         (log-rank, Holm, p &lt; {ALPHA}; counted over pairs and opponents).",
        unit(s.measure)
    );
    data_table(
        "ranking",
        &caption,
        &[
            "rank",
            "configuration",
            "mean rank",
            "geometric-mean ratio",
            "targets reached",
            "best on",
            "significantly sooner",
            "significantly later",
        ],
        &rows,
        &[0, 2, 3, 4, 5, 6, 7],
    )
}

/// The matrix of significant outcomes as a heatmap: row configuration against column
/// configuration, the pairs where the row is significantly sooner, shaded by the balance of
/// wins and losses (blue: the row is better, orange: the column).
pub fn matrix(s: &Summary) -> String {
    let order = s.ranking();
    let mut head: Vec<String> = vec!["row sooner than column".into()];
    head.extend(order.iter().map(|&j| escape(&s.configs[j])));
    let rows: Vec<Vec<String>> = order
        .iter()
        .map(|&i| {
            let mut row = vec![escape(&s.configs[i])];
            for &j in &order {
                if i == j {
                    row.push("<span class=\"diag\">&middot;</span>".into());
                    continue;
                }
                let (w, l, n) = (s.matrix[i][j], s.matrix[j][i], s.compared[i][j]);
                let balance = if n == 0 {
                    0.0
                } else {
                    (w as f64 - l as f64) / n as f64
                };
                let (r, g, b) = if balance >= 0.0 {
                    (0.0, 114.0, 178.0)
                } else {
                    (213.0, 94.0, 0.0)
                };
                let alpha = (balance.abs() * 0.55).min(0.55);
                row.push(format!(
                    "<span class=\"heat\" style=\"background: rgba({r}, {g}, {b}, {alpha:.2})\" \
                     title=\"{}\">{w}/{n}</span>",
                    escape(&format!(
                        "{} significantly sooner than {} at {w} of {n} pairs, later at {l}",
                        s.configs[i], s.configs[j]
                    ))
                ));
            }
            row
        })
        .collect();
    let caption = format!(
        "<b>Significance matrix in {}</b>: in row A and column B, the (instance, target) pairs \
         where A reaches the target significantly sooner than B, of the pairs both ran \
         (log-rank test, Holm-adjusted, p &lt; {ALPHA}). Blue: A wins more than it loses against \
         B; orange: the reverse; the deeper, the more one-sided.",
        unit(s.measure)
    );
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let numeric: Vec<usize> = (1..head.len()).collect();
    data_table("matrix", &caption, &head, &rows, &numeric)
}
