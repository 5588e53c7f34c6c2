//! Before and after: the matching instances, configurations and targets of two results folders
//! (`A`, the reference, and `B`), each pair judged faster, slower, not significantly different
//! or not comparable (and why).
//!
//! Rules:
//! - Results are matched by instance name, configuration label and target RMSE. Two results
//!   are comparable only under the same [`Conditions`]: the same instance data (data hash), the
//!   same model (coordinates, start distribution, lobes, bounds), the same budget (cutoff), the
//!   same algorithm settings and the same counting rule (results format). Seeds, trial counts,
//!   kernels, machines and program versions may differ: that is what a comparison is for.
//! - Each comparable pair gets a log-rank test of its RTDs in both measures (censored runs at
//!   their own censoring times, [`crate::stats::log_rank`]); the p-values of each measure are
//!   Holm-adjusted over all comparable pairs.
//! - The verdict uses one measure (sample-evaluations unless asked otherwise; CPU time is
//!   reported beside it): B is *slower* (or *faster*) when the Holm-adjusted p-value is below
//!   `alpha`, the median time-to-target changed by at least `min_effect` (relative to A's), and
//!   the hazard ratio points the same way. A median not reached counts as infinite; when
//!   neither side reaches its median, the ERT change is used instead.

use serde::Serialize;

use crate::stats::{Measure, MeasureSummary, Outcome, TestResult, holm, pairwise, summarise};

mod conditions;
pub mod text;

pub use conditions::{
    Conditions, Entry, TARGET_ROUND_OFF, budget_text, differences, entries, same_target,
};
pub use text::table;

/// How pairs are judged.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Options {
    /// Significance level of the Holm-adjusted log-rank p-values.
    pub alpha: f64,
    /// Smallest relative change of the median time-to-target that counts (0.05 = 5%).
    pub min_effect: f64,
    /// The measure the verdict uses (the other is reported beside it).
    pub measure: Measure,
    /// Bootstrap resamples of the ERT intervals.
    pub bootstrap: usize,
    /// Seed of the bootstrap.
    pub seed: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            alpha: 0.05,
            min_effect: 0.05,
            measure: Measure::Evaluations,
            bootstrap: 1000,
            seed: 1,
        }
    }
}

/// The verdict on one pair: how B fares against A.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "verdict", content = "reason", rename_all = "snake_case")]
pub enum Verdict {
    /// B reaches the target significantly sooner.
    Faster,
    /// B reaches the target significantly later.
    Slower,
    /// No significant difference of at least the minimum effect.
    NoDifference,
    /// The two results cannot be compared; the reason says why.
    NotComparable(String),
}

impl Verdict {
    /// The verdict as printed.
    pub fn text(&self) -> String {
        match self {
            Verdict::Faster => "faster".into(),
            Verdict::Slower => "slower".into(),
            Verdict::NoDifference => "no significant difference".into(),
            Verdict::NotComparable(why) => format!("not comparable: {why}"),
        }
    }
}

/// One measure of one comparable pair.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasureRow {
    /// The measure.
    pub measure: Measure,
    /// A's summary (success, quantiles, ERT with bootstrap interval).
    pub a: MeasureSummary,
    /// B's summary.
    pub b: MeasureSummary,
    /// B's median over A's, minus 1 (`inf` when only A reaches its median, -1 when only B
    /// does); `None` when neither does.
    pub median_change: Option<f64>,
    /// B's ERT over A's, minus 1, in the same way.
    pub ert_change: Option<f64>,
    /// The primary test ([`pairwise::primary`], the log-rank test) of A against B, its p-value
    /// Holm-adjusted over all comparable pairs of the measure; its effect (the hazard ratio)
    /// above 1 means A reaches the target sooner.
    pub test: TestResult,
}

/// One (instance, configuration, target) of the comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// Instance name.
    pub instance: String,
    /// Configuration label.
    pub config: String,
    /// Target RMSE (`None` when no target could be matched).
    pub target: Option<f64>,
    /// The verdict.
    pub verdict: Verdict,
    /// The verdict's measure first, then the other; empty when not comparable.
    pub measures: Vec<MeasureRow>,
}

/// A whole comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// The options it was judged with.
    pub options: Options,
    /// Every pair, in A's order of instances and configurations, then B's extra ones.
    pub rows: Vec<Row>,
}

impl Comparison {
    /// Rows with the given verdict kind.
    fn count(&self, pred: impl Fn(&Verdict) -> bool) -> usize {
        self.rows.iter().filter(|r| pred(&r.verdict)).count()
    }

    /// Pairs where B is significantly slower.
    pub fn slower(&self) -> usize {
        self.count(|v| *v == Verdict::Slower)
    }

    /// Pairs that could be compared.
    pub fn comparable(&self) -> usize {
        self.count(|v| !matches!(v, Verdict::NotComparable(_)))
    }
}

/// Compares the entries of A and B (see the module rules).
pub fn compare(a: &[Entry], b: &[Entry], options: Options) -> Comparison {
    let mut rows = Vec::new();
    for (ea, eb) in pairs(a, b) {
        match (ea, eb) {
            (Some(x), Some(y)) => rows.extend(compare_entry(x, y, &options)),
            (Some(x), None) => rows.push(one_sided(x, "only in A")),
            (None, Some(y)) => rows.push(one_sided(y, "only in B")),
            (None, None) => {}
        }
    }
    adjust(&mut rows);
    for r in &mut rows {
        if !matches!(r.verdict, Verdict::NotComparable(_)) {
            r.verdict = judge(&r.measures[0], &options);
        }
    }
    Comparison { options, rows }
}

/// A's entries in order, each with B's match, then B's entries A lacks.
fn pairs<'e>(a: &'e [Entry], b: &'e [Entry]) -> Vec<(Option<&'e Entry>, Option<&'e Entry>)> {
    let same = |x: &Entry, y: &Entry| x.instance == y.instance && x.config == y.config;
    let mut out: Vec<_> = a
        .iter()
        .map(|x| (Some(x), b.iter().find(|y| same(x, y))))
        .collect();
    out.extend(
        b.iter()
            .filter(|y| !a.iter().any(|x| same(x, y)))
            .map(|y| (None, Some(y))),
    );
    out
}

fn one_sided(e: &Entry, why: &str) -> Row {
    Row {
        instance: e.instance.clone(),
        config: e.config.clone(),
        target: None,
        verdict: Verdict::NotComparable(format!("instance and configuration {why}")),
        measures: Vec::new(),
    }
}

fn targets_text(t: &[f64]) -> String {
    let v: Vec<String> = t.iter().map(|x| x.to_string()).collect();
    v.join(", ")
}

/// The rows of one matched (instance, configuration).
fn compare_entry(a: &Entry, b: &Entry, options: &Options) -> Vec<Row> {
    let row = |target: Option<f64>, verdict: Verdict| Row {
        instance: a.instance.clone(),
        config: a.config.clone(),
        target,
        verdict,
        measures: Vec::new(),
    };
    let diffs = differences(&a.conditions, &b.conditions);
    if !diffs.is_empty() {
        return vec![row(None, Verdict::NotComparable(diffs.join("; ")))];
    }
    // Each of A's targets with B's same target (up to round-off, see `same_target`).
    let matched = |t: f64| b.targets.iter().copied().find(|&u| same_target(t, u));
    if a.targets.iter().all(|&t| matched(t).is_none()) {
        let why = format!(
            "different targets (A: {}; B: {})",
            targets_text(&a.targets),
            targets_text(&b.targets)
        );
        return vec![row(None, Verdict::NotComparable(why))];
    }
    let mut rows = Vec::new();
    for &t in &a.targets {
        let Some(u) = matched(t) else {
            rows.push(row(
                Some(t),
                Verdict::NotComparable("target only in A".into()),
            ));
            continue;
        };
        let mut r = row(Some(t), Verdict::NoDifference);
        let others = Measure::ALL.into_iter().filter(|m| *m != options.measure);
        for m in std::iter::once(options.measure).chain(others) {
            let (oa, ob) = (a.outcomes(t, m), b.outcomes(u, m));
            let sa = a
                .summary(t, m)
                .unwrap_or_else(|| summarise(&oa, options.bootstrap, options.seed));
            let sb = b
                .summary(u, m)
                .unwrap_or_else(|| summarise(&ob, options.bootstrap, options.seed ^ 0xb));
            r.measures.push(measure_row(&oa, &ob, m, (sa, sb)));
        }
        rows.push(r);
    }
    let in_a = |u: f64| a.targets.iter().any(|&t| same_target(t, u));
    for &u in b.targets.iter().filter(|&&u| !in_a(u)) {
        rows.push(row(
            Some(u),
            Verdict::NotComparable("target only in B".into()),
        ));
    }
    rows
}

/// B's value over A's, minus 1, with `None` (not reached) as infinite.
pub fn relative_change(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) if x > 0.0 => Some(y / x - 1.0),
        (Some(x), Some(y)) => Some(if y > x { f64::INFINITY } else { 0.0 }),
        (Some(_), None) => Some(f64::INFINITY),
        (None, Some(_)) => Some(-1.0),
        (None, None) => None,
    }
}

/// Changes and the primary test of A's and B's outcomes in one measure, with their summaries
/// (each side's own analysis when it has one).
pub fn measure_row(
    a: &[Outcome],
    b: &[Outcome],
    measure: Measure,
    (sa, sb): (MeasureSummary, MeasureSummary),
) -> MeasureRow {
    MeasureRow {
        measure,
        median_change: relative_change(sa.quantiles[2], sb.quantiles[2]),
        ert_change: relative_change(sa.ert, sb.ert),
        a: sa,
        b: sb,
        test: TestResult::run(pairwise::primary(), a, b),
    }
}

/// Holm's adjustment of each measure's p-values over all comparable rows.
fn adjust(rows: &mut [Row]) {
    for m in Measure::ALL {
        let mut slots: Vec<&mut TestResult> = rows
            .iter_mut()
            .flat_map(|r| r.measures.iter_mut())
            .filter(|x| x.measure == m && x.test.p.is_some())
            .map(|x| &mut x.test)
            .collect();
        let p: Vec<f64> = slots.iter().filter_map(|x| x.p).collect();
        for (slot, adj) in slots.iter_mut().zip(holm(&p)) {
            slot.p_holm = Some(adj);
        }
    }
}

/// The verdict of one comparable pair from its verdict measure (see the module rules).
pub fn judge(m: &MeasureRow, o: &Options) -> Verdict {
    if !m.test.significant(o.alpha) {
        return Verdict::NoDifference;
    }
    let change = if m.a.quantiles[2].is_none() && m.b.quantiles[2].is_none() {
        m.ert_change
    } else {
        m.median_change
    };
    let Some(change) = change.filter(|c| c.abs() >= o.min_effect) else {
        return Verdict::NoDifference;
    };
    // The hazard ratio (A against B) must agree: above 1, A reaches the target sooner.
    let hr = m.test.effect.unwrap_or(1.0);
    match (change > 0.0, hr) {
        (true, h) if h >= 1.0 => Verdict::Slower,
        (false, h) if h <= 1.0 => Verdict::Faster,
        _ => Verdict::NoDifference,
    }
}
