//! One analysis of a run, computed once from a results folder or from the records a run holds
//! in memory, and rendered by every writer: the statistics files and the text table
//! ([`crate::report`]), the report page ([`crate::html`]), `compare` and the Python package.
//!
//! An [`Analysis`] holds, for the records of a spec's plan: per instance, configuration and
//! target the RTD statistics in both measures; the pairwise tests as lists of named test
//! results ([`crate::stats::TestResult`]); the final quality; and the charts' data
//! ([`NamedChart`]), each chart with the file stem it is drawn to.

use brdf_graphics::chart::{self as plot, slug};

use crate::figures;
use crate::stats::{self, Group, Measure, StatsReport};
use brdf_experiment::spec::{PlotKind, Spec};
use brdf_experiment::store::TrialRecord;

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

/// Everything computed from a run's records, once.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The statistics: RTD summaries, pairwise tests, final quality.
    pub stats: StatsReport,
    /// The charts of the kinds asked for, in page order (by instance: RTDs per target,
    /// sweeps, trace, scatter, error-time, ECDF).
    pub charts: Vec<NamedChart>,
    /// Trials of the plan present.
    pub present: usize,
    /// Targets within 1% of, or trials below, an instance's best-known RMSE.
    pub warnings: Vec<String>,
}

impl Analysis {
    /// The analysis of `records` (those of `spec`'s plan; others are left out), with the
    /// charts of `kinds` (none: statistics only).
    pub fn new(spec: &Spec, records: &[TrialRecord], kinds: &[PlotKind]) -> Analysis {
        let owned: Vec<TrialRecord> = plan_records(spec, records).into_iter().cloned().collect();
        let groups = stats::group(&owned, &spec.instance_names(), &spec.config_labels());
        let stats = stats::compute(&groups, &spec.targets(), spec.stats.bootstrap, spec.seed);
        let mut warnings = brdf_experiment::best_known::warnings(spec);
        warnings.extend(brdf_experiment::best_known::below_best_known(spec, &owned));
        Analysis {
            stats,
            charts: charts(spec, &groups, kinds),
            present: owned.len(),
            warnings,
        }
    }

    /// The charts the spec draws to files.
    pub fn file_charts<'a>(&'a self, spec: &'a Spec) -> impl Iterator<Item = &'a NamedChart> {
        self.charts
            .iter()
            .filter(|c| spec.plots.draw.contains(&c.kind))
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

/// One chart of an experiment and the file stem it is drawn to.
#[derive(Clone, Debug)]
pub struct NamedChart {
    /// The instance it shows.
    pub instance: String,
    /// Its kind.
    pub kind: PlotKind,
    /// File name without extension: `<instance>-<kind>[-<measure>][-q<target>]`.
    pub stem: String,
    /// The chart.
    pub chart: plot::Chart,
}

/// The charts of the given kinds for every instance with results, in the order of the plots
/// directory's listing by instance: RTDs per target, sweeps, trace, scatter, error-time, ECDF.
pub fn charts(spec: &Spec, groups: &[Group<'_>], kinds: &[PlotKind]) -> Vec<NamedChart> {
    let mut out = Vec::new();
    let wants = |k: PlotKind| kinds.contains(&k);
    for inst in &spec.instances {
        let gs: Vec<&Group> = groups.iter().filter(|g| g.instance == inst.name).collect();
        if gs.is_empty() {
            continue;
        }
        let mut push = |kind: PlotKind, name: String, chart: plot::Chart| {
            out.push(NamedChart {
                instance: inst.name.clone(),
                kind,
                stem: format!("{}-{name}", slug(&inst.name)),
                chart,
            });
        };
        for &t in &inst.targets {
            if wants(PlotKind::Rtd) {
                let c = figures::rtd_chart(
                    &inst.name,
                    &gs,
                    t,
                    Measure::CpuSeconds,
                    spec.budget.cpu_seconds,
                );
                push(
                    PlotKind::Rtd,
                    format!("rtd-cpu-q{}", inst.target_label(t)),
                    c,
                );
            }
            if wants(PlotKind::RtdEvaluations) {
                let c = figures::rtd_chart(
                    &inst.name,
                    &gs,
                    t,
                    Measure::Evaluations,
                    spec.budget.sample_evaluations.map(|e| e as f64),
                );
                let name = format!("rtd-evals-q{}", inst.target_label(t));
                push(PlotKind::RtdEvaluations, name, c);
            }
        }
        let t0 = inst.run_target();
        if wants(PlotKind::Sweep) {
            for (name, c) in sweep_charts(spec, &inst.name, &gs, t0) {
                push(PlotKind::Sweep, name, c);
            }
        }
        if wants(PlotKind::Trace) {
            let c = figures::trace_chart(&inst.name, &gs, spec.plots.trace_trials, &inst.targets);
            push(PlotKind::Trace, "trace".into(), c);
        }
        if wants(PlotKind::Scatter) {
            let c = figures::scatter_chart(&inst.name, &gs, t0);
            push(PlotKind::Scatter, "scatter".into(), c);
        }
        if wants(PlotKind::ErrorTime) || wants(PlotKind::Ecdf) {
            let (lo, hi) = error_range(spec, &gs, t0);
            let grid = figures::target_grid(lo, hi, spec.plots.error_steps);
            if wants(PlotKind::ErrorTime) {
                let c = figures::error_time_chart(&inst.name, &gs, &grid, Measure::CpuSeconds);
                push(PlotKind::ErrorTime, "error-time".into(), c);
            }
            if wants(PlotKind::Ecdf) {
                let c = figures::ecdf_targets_chart(&inst.name, &gs, &grid, Measure::CpuSeconds);
                push(PlotKind::Ecdf, "ecdf-targets".into(), c);
            }
        }
    }
    out
}

type SweepRow = (f64, Option<f64>, Option<f64>, Option<f64>, Option<f64>);

/// The sweep charts of one instance as (name without the instance, chart).
fn sweep_charts(
    spec: &Spec,
    instance: &str,
    groups: &[&Group<'_>],
    target: f64,
) -> Vec<(String, plot::Chart)> {
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
            let Some(g) = groups.iter().find(|g| g.config == c.label) else {
                continue;
            };
            let o = stats::group_outcomes(g, target, Measure::CpuSeconds);
            let s = stats::summarise(&o, spec.stats.bootstrap, spec.seed);
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
        let title = format!("{algo}: ERT and median vs {param} - {instance}, target RMSE {target}");
        let c = figures::sweep_chart(&title, &param, Measure::CpuSeconds, &rows, x_log);
        out.push((format!("sweep-{}-{}", slug(algo), slug(&param)), c));
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
