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
use brdf_graphics::chart as plot;

use crate::analysis::{Analysis, ChartSet};
pub use crate::analysis::{NamedChart, charts, plan_records};
use crate::stats::{self, StatsReport};
use brdf_experiment::spec::{Source, Spec};
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
    /// The analysis the files render (the page renders it too).
    pub analysis: Analysis,
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

fn write(path: &Path, bytes: &[u8], files: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    write_atomic(path, bytes).map_err(|source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    files.push(path.to_path_buf());
    Ok(())
}

/// Computes statistics only (no files, no charts).
pub fn compute_stats(spec: &Spec, records: &[TrialRecord]) -> StatsReport {
    Analysis::new(spec, records, ChartSet::None).stats
}

/// The files (and the `plots/` folder) `run`, `stats`, `plot` and `report` derive in a results
/// folder: none of them may be a symbolic link there
/// ([`brdf_graphics::target::refuse_links_in`]).
pub const DERIVED_FILES: &[&str] = &[
    "stats.json",
    "stats.csv",
    "tests.csv",
    "finals.csv",
    "table.txt",
    "summary.json",
    "report.html",
    "compare.html",
    "plots",
];

/// Writes statistics (JSON, CSV, table) and, when `plots` is set, the spec's plots.
pub fn write_report(
    spec: &Spec,
    records: &[TrialRecord],
    sessions: &[Session],
    out: &Path,
    plots: bool,
) -> Result<Report, ReportError> {
    let charts = if plots {
        ChartSet::Files
    } else {
        ChartSet::None
    };
    write_analysis(
        spec,
        Analysis::new(spec, records, charts),
        sessions,
        out,
        plots,
    )
}

/// Writes the files of `analysis` (computed once, e.g. for the files and the page of a run):
/// statistics (JSON, CSV, table) and, when `plots` is set, the spec's plots.
pub fn write_analysis(
    spec: &Spec,
    analysis: Analysis,
    sessions: &[Session],
    out: &Path,
    plots: bool,
) -> Result<Report, ReportError> {
    // Links among the derived files of a results folder are never written through.
    brdf_graphics::target::refuse_links_in(out, DERIVED_FILES).map_err(|source| {
        ReportError::Io {
            path: out.to_path_buf(),
            source,
        }
    })?;
    let report = &analysis.stats;
    let table = table(spec, &analysis);
    let mut files = Vec::new();
    let stats_path = out.join("stats.json");
    let json = to_json(&stats_path, report)?;
    write(&stats_path, json.as_bytes(), &mut files)?;
    write(
        &out.join("stats.csv"),
        stats::configs_csv(report).as_bytes(),
        &mut files,
    )?;
    write(
        &out.join("tests.csv"),
        stats::tests_csv(report).as_bytes(),
        &mut files,
    )?;
    write(
        &out.join("finals.csv"),
        stats::finals_csv(report).as_bytes(),
        &mut files,
    )?;
    write(&out.join("table.txt"), table.as_bytes(), &mut files)?;
    if plots {
        files.extend(draw_plots(spec, &analysis, &out.join("plots"))?);
    }
    let planned = spec.trials_plan().len();
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
        "trials_present": analysis.present,
        "complete": analysis.present == planned,
        "budget": spec.budget,
        "sessions": sessions,
        "configurations": spec.config_labels(),
        "instances": spec.instance_names(),
        "best_known": spec.best_known(),
        "warnings": analysis.warnings,
        "files": listed.iter().map(|f| f.strip_prefix(out).unwrap_or(f).display().to_string()).collect::<Vec<_>>(),
    });
    let summary_path = out.join("summary.json");
    let summary = to_json(&summary_path, &summary)?;
    write(&summary_path, summary.as_bytes(), &mut files)?;
    Ok(Report {
        analysis,
        table,
        files,
    })
}

/// The table `run` and `stats` print: the statistics, each instance's best-known RMSE with
/// the warnings about targets close to it, and a note on configurations run in Python.
pub fn table(spec: &Spec, analysis: &Analysis) -> String {
    with_python_note(
        spec,
        with_best_known(spec, analysis, stats::table(&analysis.stats)),
    )
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
fn with_best_known(spec: &Spec, analysis: &Analysis, mut table: String) -> String {
    if spec.instances.iter().all(|i| i.best_known.is_none()) {
        return table;
    }
    if !table.ends_with('\n') {
        table.push('\n');
    }
    table.push_str(&brdf_best_known::summary(spec));
    for w in &analysis.warnings {
        table.push_str(w);
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

/// Draws the charts of `analysis` that the spec asks for; returns the files written.
pub fn draw_plots(spec: &Spec, analysis: &Analysis, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let mut files = Vec::new();
    for c in analysis.file_charts(spec) {
        files.extend(plot::draw(
            &c.chart,
            &dir.join(&c.stem),
            &spec.plots.formats,
        )?);
    }
    Ok(files)
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
