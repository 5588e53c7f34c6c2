//! One analysis of a run, computed once from a results folder or from the records a run holds
//! in memory, and rendered by every writer: the statistics files and the text table
//! ([`crate::report`]), the report page ([`crate::html`]), `compare` and the Python package.
//!
//! An [`Analysis`] holds, for the records of a spec's plan: per instance, configuration and
//! target the RTD statistics in both measures; the pairwise tests as lists of named test
//! results ([`crate::stats::TestResult`]); the final quality; the summary that answers first
//! ([`summary`]: the best configuration per instance and target, ratios, significance,
//! aggregates); and the charts' data ([`NamedChart`]), each chart with the file stem it is
//! drawn to and its caption.

use brdf_graphics::chart::{self as plot, slug};

use crate::figures;
use crate::stats::{self, Group, Measure, StatsReport};

mod captions;
pub mod summary;

use brdf_experiment::spec::{PlotKind, Spec};
use brdf_experiment::store::TrialRecord;
pub use summary::Summary;

/// Charts every page shows, whatever the spec draws to files: RTDs in both measures, tuning
/// sweeps (where the spec sweeps), traces and error-time curves.
pub const PAGE_KINDS: [PlotKind; 5] = [
    PlotKind::Rtd,
    PlotKind::RtdEvaluations,
    PlotKind::Sweep,
    PlotKind::Trace,
    PlotKind::ErrorTime,
];

/// The chart kinds of a page of `spec`: [`PAGE_KINDS`], then those the spec draws to files.
pub fn page_kinds(spec: &Spec) -> Vec<PlotKind> {
    let mut kinds = PAGE_KINDS.to_vec();
    kinds.extend(spec.plots.draw.iter().filter(|k| !PAGE_KINDS.contains(k)));
    kinds
}

/// Which charts an analysis holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChartSet {
    /// None: statistics only (`stats`, `compare`, the Python package).
    None,
    /// The kinds the spec draws to files (`[plots] draw`).
    Files,
    /// A page's: [`page_kinds`], plus the page's own views (the fixed-budget view per
    /// instance, the runtime ECDFs over all instances and targets).
    Page,
}

/// Everything computed from a run's records, once.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The statistics: RTD summaries, pairwise tests, final quality.
    pub stats: StatsReport,
    /// The answer first, in sample-evaluations, then in CPU seconds.
    pub summaries: Vec<Summary>,
    /// The charts asked for, in page order (per instance: RTDs per target, sweeps, trace,
    /// scatter, error-time, ECDF, fixed budget; then the charts over all instances).
    pub charts: Vec<NamedChart>,
    /// Trials of the plan present.
    pub present: usize,
    /// Targets within 1% of, or trials below, an instance's best-known RMSE.
    pub warnings: Vec<String>,
}

impl Analysis {
    /// The analysis of `records` (those of `spec`'s plan; others are left out), with the
    /// charts of `set`.
    pub fn new(spec: &Spec, records: &[TrialRecord], set: ChartSet) -> Analysis {
        let owned: Vec<TrialRecord> = plan_records(spec, records).into_iter().cloned().collect();
        let groups = stats::group(&owned, &spec.instance_names(), &spec.config_labels());
        let stats = stats::compute(&groups, &spec.targets(), spec.stats.bootstrap, spec.seed);
        let mut warnings = brdf_best_known::warnings(spec);
        warnings.extend(brdf_best_known::below_best_known(spec, &owned));
        let (instances, labels) = (spec.instance_names(), spec.config_labels());
        let summaries = [Measure::Evaluations, Measure::CpuSeconds]
            .map(|m| summary::summarise(&stats, &instances, &labels, m))
            .to_vec();
        let charts = match set {
            ChartSet::None => Vec::new(),
            ChartSet::Files => charts(spec, &groups, &stats, &spec.plots.draw, false),
            ChartSet::Page => charts(spec, &groups, &stats, &page_kinds(spec), true),
        };
        Analysis {
            stats,
            summaries,
            charts,
            present: owned.len(),
            warnings,
        }
    }

    /// The charts the spec draws to files.
    pub fn file_charts<'a>(&'a self, spec: &'a Spec) -> impl Iterator<Item = &'a NamedChart> {
        self.charts
            .iter()
            .filter(|c| c.kind.is_some_and(|k| spec.plots.draw.contains(&k)))
    }
}

/// The records that belong to `spec`'s plan (its instances, configurations and trial count).
pub fn plan_records<'a>(spec: &Spec, records: &'a [TrialRecord]) -> Vec<&'a TrialRecord> {
    let inst = spec.instance_names();
    let cfg = spec.config_labels();
    records
        .iter()
        .filter(|r| r.trial < spec.trials && inst.contains(&r.instance) && cfg.contains(&r.config))
        .collect()
}

/// One chart of an experiment, the file stem it is drawn to and its caption.
#[derive(Clone, Debug)]
pub struct NamedChart {
    /// The instance it shows (`None`: all instances of the run).
    pub instance: Option<String>,
    /// Its kind (`None`: a page's own view, never drawn to a file).
    pub kind: Option<PlotKind>,
    /// File name without extension: `<instance>-<kind>[-<measure>][-q<target>]`.
    pub stem: String,
    /// The chart.
    pub chart: plot::Chart,
    /// What it shows and how to read it.
    pub caption: String,
}

/// The charts of the given kinds for every instance with results, in the order of the plots
/// directory's listing by instance: RTDs per target, sweeps, trace, scatter, error-time, ECDF;
/// with `page`, each instance's fixed-budget view and (for several instances) the runtime
/// ECDFs over all of them. Configurations keep their colours in every chart.
pub fn charts(
    spec: &Spec,
    groups: &[Group<'_>],
    stats: &StatsReport,
    kinds: &[PlotKind],
    page: bool,
) -> Vec<NamedChart> {
    let colors = figures::Colors::new(&spec.config_labels());
    let mut out = Vec::new();
    let wants = |k: PlotKind| kinds.contains(&k);
    for inst in &spec.instances {
        let gs: Vec<&Group> = groups.iter().filter(|g| g.instance == inst.name).collect();
        if gs.is_empty() {
            continue;
        }
        let name = &inst.name;
        let mut push = |kind: Option<PlotKind>, stem: String, chart: plot::Chart, caption| {
            out.push(NamedChart {
                instance: Some(name.clone()),
                kind,
                stem: format!("{}-{stem}", slug(name)),
                chart,
                caption,
            });
        };
        let digits = stats::target_digits(&inst.targets);
        let best = inst.best_known.as_ref().map(|b| b.rmse);
        let text = |t: f64| stats::target_text(t, best, digits);
        for &t in &inst.targets {
            let shown = text(t);
            for (kind, m, cutoff, short) in [
                (
                    PlotKind::Rtd,
                    Measure::CpuSeconds,
                    spec.budget.cpu_seconds,
                    "cpu",
                ),
                (
                    PlotKind::RtdEvaluations,
                    Measure::Evaluations,
                    spec.budget.sample_evaluations.map(|e| e as f64),
                    "evals",
                ),
            ] {
                if wants(kind) {
                    let c = figures::rtd_chart(name, &gs, (t, &shown), m, cutoff, &colors);
                    let caption = captions::rtd(&c, name, &shown, m, cutoff.is_some());
                    let stem = format!("rtd-{short}-q{}", inst.target_label(t));
                    push(Some(kind), stem, c, caption);
                }
            }
        }
        let t0 = inst.run_target();
        if wants(PlotKind::Sweep) {
            for (stem, c, param) in sweep_charts(spec, stats, name, (t0, &text(t0))) {
                let caption = captions::sweep(&c, &param, &text(t0));
                push(Some(PlotKind::Sweep), stem, c, caption);
            }
        }
        if wants(PlotKind::Trace) {
            let n = spec.plots.trace_trials;
            let c = figures::trace_chart(name, &gs, n, &inst.targets, &colors);
            let caption = captions::trace(&c, n);
            push(Some(PlotKind::Trace), "trace".into(), c, caption);
        }
        if wants(PlotKind::Scatter) {
            let c = figures::scatter_chart(name, &gs, (t0, &text(t0)), &colors);
            let caption = captions::scatter(&c, &text(t0));
            push(Some(PlotKind::Scatter), "scatter".into(), c, caption);
        }
        if wants(PlotKind::ErrorTime) || wants(PlotKind::Ecdf) {
            let (lo, hi) = error_range(spec, &gs, t0);
            let grid = figures::target_grid(lo, hi, spec.plots.error_steps);
            let m = Measure::CpuSeconds;
            if wants(PlotKind::ErrorTime) {
                let c = figures::error_time_chart(name, &gs, &grid, m, &colors);
                let caption = captions::error_time(&c, m);
                push(Some(PlotKind::ErrorTime), "error-time".into(), c, caption);
            }
            if wants(PlotKind::Ecdf) {
                let c = figures::ecdf_targets_chart(name, &gs, &grid, m, &colors);
                let caption = captions::ecdf_targets(&c, grid.len());
                push(Some(PlotKind::Ecdf), "ecdf-targets".into(), c, caption);
            }
        }
        if page {
            let m = Measure::Evaluations;
            let c = figures::fixed_budget_chart(name, &gs, &inst.targets, m, &colors);
            let caption = captions::fixed_budget(&c, m, &text(t0));
            push(None, "fixed-budget".into(), c, caption);
        }
    }
    if page && spec.instances.len() > 1 {
        out.extend(aggregate_charts(spec, groups, &colors));
    }
    out
}

/// The runtime ECDFs over every (instance, target) pair of the run, in both measures.
fn aggregate_charts(
    spec: &Spec,
    groups: &[Group<'_>],
    colors: &figures::Colors,
) -> Vec<NamedChart> {
    let mut out = Vec::new();
    for (m, short) in [
        (Measure::Evaluations, "evals"),
        (Measure::CpuSeconds, "cpu"),
    ] {
        let mut pairs: Vec<(String, Vec<Vec<stats::Outcome>>)> = Vec::new();
        for label in spec.config_labels() {
            let mut per_pair = Vec::new();
            for inst in &spec.instances {
                let Some(g) = groups
                    .iter()
                    .find(|g| g.instance == inst.name && g.config == label)
                else {
                    continue;
                };
                for &t in &inst.targets {
                    per_pair.push(stats::group_outcomes(g, t, m));
                }
            }
            if !per_pair.is_empty() {
                pairs.push((label, per_pair));
            }
        }
        let title = format!(
            "Runtime ECDF over all instances and targets - {}",
            spec.name
        );
        let c = figures::aggregate_ecdf_chart(&title, &pairs, m, colors);
        out.push(NamedChart {
            instance: None,
            kind: None,
            stem: format!("all-ecdf-{short}"),
            caption: captions::aggregate(&c, m),
            chart: c,
        });
    }
    out
}

type SweepRow = (f64, Option<f64>, Option<f64>, Option<f64>, Option<f64>);

/// The sweep charts of one instance as (name without the instance, chart, swept parameter),
/// from the statistics at `target` in CPU seconds.
fn sweep_charts(
    spec: &Spec,
    stats: &StatsReport,
    instance: &str,
    (target, shown): (f64, &str),
) -> Vec<(String, plot::Chart, String)> {
    let mut out = Vec::new();
    let mut algos: Vec<&str> = Vec::new();
    for c in &spec.configurations {
        if !c.swept.is_empty() && !algos.contains(&c.algorithm_label.as_str()) {
            algos.push(&c.algorithm_label);
        }
    }
    for algo in algos {
        let cfgs: Vec<_> = spec
            .configurations
            .iter()
            .filter(|c| c.algorithm_label == algo && !c.swept.is_empty())
            .collect();
        let param = cfgs[0].swept[0].0.clone();
        // One series per combination of the other swept values.
        let mut rows: Vec<(String, Vec<SweepRow>)> = Vec::new();
        for c in &cfgs {
            let others: Vec<String> = c.swept[1..]
                .iter()
                .map(|(k, v)| format!("{k}={}", brdf_experiment::spec::format_value(*v)))
                .collect();
            let key = others.join(" ");
            let Some(cs) = stats
                .configs
                .iter()
                .find(|s| s.instance == instance && s.config == c.label && s.target == target)
            else {
                continue;
            };
            let s = &cs.cpu;
            let row = (c.swept[0].1, s.ert, s.ert_p10, s.ert_p90, s.quantiles[2]);
            match rows.iter_mut().find(|r| r.0 == key) {
                Some(r) => r.1.push(row),
                None => rows.push((key, vec![row])),
            }
        }
        for r in &mut rows {
            r.1.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        let xs: Vec<f64> = rows.iter().flat_map(|r| r.1.iter().map(|p| p.0)).collect();
        let (mn, mx) = xs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        let x_log = mn > 0.0 && mx / mn >= 10.0;
        let title = format!("{algo}: ERT and median vs {param} - {instance}, target RMSE {shown}");
        let c = figures::sweep_chart(&title, &param, Measure::CpuSeconds, &rows, x_log);
        out.push((format!("sweep-{}-{}", slug(algo), slug(&param)), c, param));
    }
    out
}

/// Default target range of the error-time and ECDF plots: from the lowest target to the median
/// first-trace RMSE, clamped to [1.2, 5] times the lowest target.
fn error_range(spec: &Spec, groups: &[&Group<'_>], lo: f64) -> (f64, f64) {
    if let Some([a, b]) = spec.plots.error_range {
        return (a, b);
    }
    let mut first: Vec<f64> = groups
        .iter()
        .flat_map(|g| g.records.iter())
        .filter_map(|r| r.result.trace.first().map(|p| p.rmse))
        .filter(|x| x.is_finite())
        .collect();
    first.sort_by(f64::total_cmp);
    let med = first.get(first.len() / 2).copied().unwrap_or(lo * 2.0);
    let lo = lo.max(1e-12);
    (lo, med.clamp(lo * 1.2, lo * 5.0))
}
