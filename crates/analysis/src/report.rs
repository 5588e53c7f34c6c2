//! Statistics and plots of a results directory, written atomically beside `trials.jsonl`.
//!
//! Output layout of `<out>/`:
//! - `trials.jsonl`: the raw results (see [`brdf_experiment::store`]);
//! - `summary.json`: experiment, fingerprint, machines, trial counts, files written;
//! - `stats.json`, `stats.csv`: per instance, configuration, target and measure
//!   ([`crate::stats::ConfigStats`]);
//! - `finals.csv`: final RMSE (mean, median, min, max) and end time per instance and
//!   configuration ([`crate::stats::FinalQuality`], the paper's Table 5);
//! - `tests.csv`: pairwise Mann-Whitney / KS tests with Holm-adjusted p-values;
//! - `table.txt`: the table printed at the end of a run;
//! - `plots/<instance>-<kind>[-<measure>][-q<target>].{png,svg}`.

use std::path::{Path, PathBuf};

use brdf_graphics::PlotError;
use brdf_graphics::chart::{self as plot, slug};

use crate::figures;
use crate::stats::{self, Group, Measure, StatsReport};
use brdf_experiment::spec::{PlotKind, Source, Spec};
use brdf_experiment::store::{Contents, Session, TrialRecord, write_atomic};

/// Errors writing a report.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A plot failed.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// A derived file could not be serialised.
    #[error("{path}: cannot serialise: {message}")]
    Serialize {
        /// The file.
        path: PathBuf,
        /// serde_json's message.
        message: String,
    },
}

fn to_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<String, ReportError> {
    serde_json::to_string_pretty(value).map_err(|e| ReportError::Serialize {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// What [`write_report`] produced.
#[derive(Clone, Debug)]
pub struct Report {
    /// The statistics.
    pub stats: StatsReport,
    /// The printable table.
    pub table: String,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// Why a results folder's own spec could not be read.
#[derive(Debug, thiserror::Error)]
pub enum StoredSpecError {
    /// The results file predates stored spec texts.
    #[error("{0}: the header holds no spec text; pass the spec file")]
    NoSpecText(PathBuf),
    /// The stored text does not parse (or no longer validates).
    #[error(transparent)]
    Spec(#[from] brdf_experiment::spec::SpecError),
}

/// The spec a results folder was last run with (its latest session's, else the header's), as
/// `stats` and `plot` use it when given the folder alone.
pub fn stored_spec(contents: &Contents, dir: &Path) -> Result<Spec, StoredSpecError> {
    let text = contents.current_spec_text();
    if text.is_empty() {
        return Err(StoredSpecError::NoSpecText(dir.to_path_buf()));
    }
    let mut spec = Spec::parse(
        text,
        &format!("{} (stored spec)", dir.display()),
        &contents.header.experiment,
        dir,
    )?;
    spec.adopt_stored_settings(&contents.header.spec);
    Ok(spec)
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

fn write(path: &Path, bytes: &[u8], files: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    write_atomic(path, bytes).map_err(|source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    files.push(path.to_path_buf());
    Ok(())
}

/// Computes statistics only (no files).
pub fn compute_stats(spec: &Spec, records: &[TrialRecord]) -> StatsReport {
    let owned: Vec<TrialRecord> = plan_records(spec, records).into_iter().cloned().collect();
    let groups = stats::group(&owned, &spec.instance_names(), &spec.config_labels());
    stats::compute(&groups, &spec.targets(), spec.stats.bootstrap, spec.seed)
}

/// Writes statistics (JSON, CSV, table) and, when `plots` is set, the spec's plots.
pub fn write_report(
    spec: &Spec,
    records: &[TrialRecord],
    sessions: &[Session],
    out: &Path,
    plots: bool,
) -> Result<Report, ReportError> {
    let owned: Vec<TrialRecord> = plan_records(spec, records).into_iter().cloned().collect();
    let groups = stats::group(&owned, &spec.instance_names(), &spec.config_labels());
    let report = stats::compute(&groups, &spec.targets(), spec.stats.bootstrap, spec.seed);
    let table = with_python_note(spec, with_best_known(spec, &owned, stats::table(&report)));
    let mut files = Vec::new();
    let stats_path = out.join("stats.json");
    let json = to_json(&stats_path, &report)?;
    write(&stats_path, json.as_bytes(), &mut files)?;
    write(
        &out.join("stats.csv"),
        stats::configs_csv(&report).as_bytes(),
        &mut files,
    )?;
    write(
        &out.join("tests.csv"),
        stats::tests_csv(&report).as_bytes(),
        &mut files,
    )?;
    write(
        &out.join("finals.csv"),
        stats::finals_csv(&report).as_bytes(),
        &mut files,
    )?;
    write(&out.join("table.txt"), table.as_bytes(), &mut files)?;
    if plots {
        files.extend(draw_plots(spec, &groups, &out.join("plots"))?);
    }
    let planned = spec.trials_plan().len();
    let mut warnings = brdf_experiment::best_known::warnings(spec);
    warnings.extend(brdf_experiment::best_known::below_best_known(spec, &owned));
    // `stats` writes no plots: the summary still lists those an earlier run drew.
    let mut listed = files.clone();
    if !plots {
        listed.extend(plots_listed_before(out));
    }
    let summary = serde_json::json!({
        "experiment": spec.name,
        "description": spec.description,
        "fingerprint": spec.fingerprint(),
        "trials_planned": planned,
        "trials_present": owned.len(),
        "complete": owned.len() == planned,
        "budget": spec.budget,
        "sessions": sessions,
        "configurations": spec.config_labels(),
        "instances": spec.instance_names(),
        "best_known": spec.best_known(),
        "warnings": warnings,
        "files": listed.iter().map(|f| f.strip_prefix(out).unwrap_or(f).display().to_string()).collect::<Vec<_>>(),
    });
    let summary_path = out.join("summary.json");
    let summary = to_json(&summary_path, &summary)?;
    write(&summary_path, summary.as_bytes(), &mut files)?;
    Ok(Report {
        stats: report,
        table,
        files,
    })
}

/// The plot files the folder's summary.json lists that are still on disk (none when it is
/// missing or unreadable: the summary is then rewritten without them).
fn plots_listed_before(out: &Path) -> Vec<PathBuf> {
    let Ok(text) = std::fs::read_to_string(out.join("summary.json")) else {
        return Vec::new();
    };
    let Ok(summary) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    let listed = summary["files"].as_array().map_or(&[][..], Vec::as_slice);
    listed
        .iter()
        .filter_map(serde_json::Value::as_str)
        .filter(|f| f.starts_with("plots/"))
        .map(|f| out.join(f))
        .filter(|f| f.is_file())
        .collect()
}

/// The statistics table followed by each instance's best-known RMSE (with every target
/// relative to it) and the warnings about targets close to it, when they are known.
fn with_best_known(spec: &Spec, records: &[TrialRecord], mut table: String) -> String {
    if spec.instances.iter().all(|i| i.best_known.is_none()) {
        return table;
    }
    if !table.ends_with('\n') {
        table.push('\n');
    }
    table.push_str(&brdf_experiment::best_known::summary(spec));
    let below = brdf_experiment::best_known::below_best_known(spec, records);
    for w in brdf_experiment::best_known::warnings(spec)
        .into_iter()
        .chain(below)
    {
        table.push_str(&w);
        table.push('\n');
    }
    table
}

/// The table with a note when configurations run in Python: their CPU seconds include the
/// interpreter's overhead, so the table's evaluation columns are the fair comparison.
fn with_python_note(spec: &Spec, mut table: String) -> String {
    let python: Vec<&str> = spec
        .configurations
        .iter()
        .filter(|c| c.algorithm.kind_name() == brdf_experiment::python_kind::KIND)
        .map(|c| c.label.as_str())
        .collect();
    if python.is_empty() {
        return table;
    }
    if !table.ends_with('\n') {
        table.push('\n');
    }
    table.push_str(&format!(
        "note: {} run in Python: their CPU seconds include the interpreter's overhead; compare \
         the evaluation columns (sample-evaluations) beside them\n",
        python.join(", ")
    ));
    table
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

/// Draws the plots the spec asks for; returns the files written.
pub fn draw_plots(
    spec: &Spec,
    groups: &[Group<'_>],
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let mut files = Vec::new();
    for c in charts(spec, groups, &spec.plots.draw) {
        files.extend(plot::draw(
            &c.chart,
            &dir.join(&c.stem),
            &spec.plots.formats,
        )?);
    }
    Ok(files)
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

/// A short description of where an instance's data comes from (for messages).
pub fn source_text(source: &Source) -> String {
    match source {
        Source::Synthetic {
            name,
            samples,
            sigma,
            ..
        } => format!(
            "synthetic {} ({samples} samples, sigma {sigma})",
            name.as_deref().unwrap_or("custom")
        ),
        Source::File { resolved, .. } => resolved.display().to_string(),
    }
}
