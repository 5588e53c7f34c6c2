//! `run` (an experiment spec, as `brdf-sls run`) and `read_results` (a results folder as
//! records for pandas).

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use anyhow::Context;
use brdf_analysis::folder::FolderError;
use brdf_analysis::pipeline::{Finished, Request};
use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunError, RunOptions, default_threads};
use brdf_experiment::shard::Shard;
use brdf_experiment::spec::Spec;
use brdf_experiment::store::{read_results as read_store, results_file};
use brdf_workers::pool::{PoolError, Routed, RoutedError, WorkerCommand};
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::support::{chain, input_err, interruptible, run_err, to_python};

/// How the Python algorithms of a run are run, besides the spec and the folder.
struct Workers {
    /// In worker processes (`python -m brdf_sls worker`), one per thread; else on the run's
    /// threads in this interpreter.
    processes: bool,
    /// This interpreter (`sys.executable`) and its module search path (`sys.path`), which the
    /// workers get, so they import the algorithms as this process does.
    python: OsString,
    path: OsString,
    /// What names the spec in messages.
    origin: String,
}

/// Runs (or resumes) an experiment as `brdf-sls run SPEC` does: the same trials with the same
/// seeds, the same results folder (trials.jsonl, statistics, table, plots, report.html), and
/// the same plan, notes and progress on standard error (`progress="quiet"`: none).
///
/// spec: the TOML file (None: the built-in default experiment); out: the results folder
/// (default `runs/<spec stem>/`, relative to the working directory, as the command line);
/// threads (default: the spec's, else all CPUs); fresh: move old results aside; limit: run at
/// most this many new trials; plots: draw the plots and the report page; kernel: overrides the
/// spec's; shard: "K/N", one shard of the plan (as `--shard`); progress: "auto", "bars",
/// "plain" or "quiet"; processes: run the algorithms written in Python in worker processes,
/// one per thread (default), else on threads of this interpreter (one core at a time).
///
/// Returns a dict: out, new_trials, resumed, missing, notes, warnings (targets close to the
/// best-known RMSE), table, files, summary, threads. Releases the GIL; Ctrl-C stops the trials
/// in flight (none of them is stored) and raises KeyboardInterrupt; running again resumes.
#[pyfunction]
#[pyo3(signature = (spec=None, out=None, *, threads=None, fresh=false, limit=None, plots=true, kernel=None, shard=None, progress="auto", processes=true))]
#[allow(clippy::too_many_arguments)]
pub fn run(
    py: Python<'_>,
    spec: Option<PathBuf>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    fresh: bool,
    limit: Option<usize>,
    plots: bool,
    kernel: Option<&str>,
    shard: Option<&str>,
    progress: &str,
    processes: bool,
) -> PyResult<Py<PyAny>> {
    let loaded = match &spec {
        Some(p) => py
            .detach(|| Spec::from_file(p))
            .map_err(|e| input_err(chain(e.into())))?,
        None => Spec::default_experiment(),
    };
    let shard: Option<Shard> = match shard {
        Some(s) => Some(
            s.parse()
                .map_err(|e| input_err(format!("shard={s}: {e}")))?,
        ),
        None => None,
    };
    let stem = spec
        .as_deref()
        .and_then(Path::file_stem)
        .map_or_else(|| "default".into(), |s| s.to_string_lossy().into_owned());
    let threads = threads.or(loaded.threads).unwrap_or_else(default_threads);
    brdf_experiment::threads::check(threads, "threads").map_err(input_err)?;
    let kernel = match kernel {
        Some(k) => k.parse().map_err(input_err)?,
        None => loaded.kernel,
    };
    let progress: ProgressMode = progress
        .parse()
        .map_err(|e| input_err(format!("progress={progress}: {e}")))?;
    let out = out.unwrap_or_else(|| {
        let base = PathBuf::from(brdf_experiment::DEFAULT_RUNS_DIR).join(stem);
        match shard {
            Some(s) => base.join(s.dir_name()),
            None => base,
        }
    });
    let sys = py.import("sys")?;
    let workers = Workers {
        processes,
        python: sys
            .getattr("executable")?
            .extract::<PathBuf>()?
            .into_os_string(),
        path: std::env::join_paths(sys.getattr("path")?.extract::<Vec<PathBuf>>()?)
            .map_err(run_err)?,
        origin: spec
            .as_deref()
            .map_or_else(|| "<built-in default>".into(), |p| p.display().to_string()),
    };
    let request = Request {
        kernel,
        shard,
        options: RunOptions {
            threads,
            fresh,
            progress,
            limit,
        },
        plots,
        notes: progress != ProgressMode::Quiet,
        spec: loaded,
        out: out.clone(),
    };
    let finished = interruptible(py, |flag| run_spec(request, &workers, flag))??;
    let d = PyDict::new(py);
    let outcome = &finished.outcome;
    d.set_item("out", out)?;
    d.set_item("new_trials", outcome.new_trials)?;
    d.set_item("resumed", outcome.resumed)?;
    d.set_item("missing", outcome.missing)?;
    d.set_item("notes", outcome.notes.clone())?;
    d.set_item("warnings", finished.warnings.clone())?;
    d.set_item("table", finished.report.table.clone())?;
    d.set_item("files", finished.report.files.clone())?;
    d.set_item("summary", finished.summary.clone())?;
    d.set_item("threads", finished.threads)?;
    Ok(d.into_any().unbind())
}

/// The work of [`run`] on the worker thread: the pipeline of `brdf-sls run`.
fn run_spec(
    request: Request,
    workers: &Workers,
    flag: std::sync::Arc<std::sync::atomic::AtomicBool>,
) -> PyResult<Finished> {
    let result = brdf_analysis::pipeline::run(request, |spec, built, kernel| {
        let is_python = |c: &brdf_experiment::spec::Configuration| {
            workers.processes && c.algorithm.kind_name() == brdf_experiment::python_kind::KIND
        };
        let command = || WorkerCommand {
            program: workers.python.clone(),
            args: ["-m", "brdf_sls", "worker"].map(OsString::from).to_vec(),
            env: vec![("PYTHONPATH".into(), workers.path.clone())],
        };
        let mut executor = Routed::new(spec, built, kernel, is_python, command, &workers.origin)
            .map_err(|e| match e {
                RoutedError::Instance(e) => anyhow::Error::new(e).context("building the instances"),
                RoutedError::Pool(PoolError::Refused(m)) => anyhow::Error::new(Refused(m)),
                RoutedError::Pool(e) => anyhow::Error::new(e).context("starting the workers"),
            })?;
        executor.set_interrupt(flag);
        Ok(executor)
    });
    match result {
        Ok(finished) => Ok(finished),
        Err(e) if matches!(e.downcast_ref::<RunError>(), Some(RunError::Interrupted)) => Err(
            PyKeyboardInterrupt::new_err(RunError::Interrupted.to_string()),
        ),
        Err(e) => Err(classify(e)),
    }
}

/// A spec or instance refused in a worker: bad input.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct Refused(String);

/// An error of a run as InputError (what the command line treats as bad input, exit status
/// 2) or RunError (status 1), with the command line's message. The classification is the
/// command line's own ([`brdf_analysis::errors::is_input_cause`]), so an edited seed or
/// target or a negative time in a results file is bad input here as there; only a spec or
/// instance refused in a worker process is the package's own.
fn classify(e: anyhow::Error) -> PyErr {
    let input = e
        .chain()
        .any(|c| c.is::<Refused>() || brdf_analysis::errors::is_input_cause(c));
    if input {
        input_err(chain(e))
    } else {
        run_err(chain(e))
    }
}

/// Reads a results folder (a plain or packed `trials.jsonl`) for the Python package: the
/// header, every trial record and the statistics `brdf-sls stats` computes, as JSON-like
/// Python objects (`brdf_sls.read_results` flattens them into records).
///
/// Returns a dict: header, spec_name, planned, records (one dict per trial: key, instance,
/// config, trial, seed, target, budget, result), stats (configs, tests, finals), stats_rows
/// (the per-configuration statistics as flat records, the columns of `stats.csv`), torn,
/// warnings.
#[pyfunction]
pub fn read_results(py: Python<'_>, dir: PathBuf) -> PyResult<Py<PyAny>> {
    let (contents, spec, stats, warnings) = py.detach(|| load_stats(&dir))?;
    let d = PyDict::new(py);
    d.set_item("header", to_python(py, &contents.header)?)?;
    d.set_item("spec_name", spec.name.clone())?;
    d.set_item("planned", spec.trials_plan().len())?;
    let present = brdf_analysis::report::plan_records(&spec, &contents.records).len();
    d.set_item("present", present)?;
    d.set_item("records", to_python(py, &contents.records)?)?;
    d.set_item("stats", to_python(py, &stats)?)?;
    d.set_item("stats_rows", to_python(py, &stats.config_records())?)?;
    d.set_item("torn", contents.torn.as_ref().map(Vec::len))?;
    d.set_item("warnings", warnings)?;
    Ok(d.into_any().unbind())
}

/// A folder's contents, its spec, its statistics and warnings.
type Loaded = (
    brdf_experiment::store::Contents,
    Spec,
    brdf_analysis::stats::StatsReport,
    Vec<String>,
);

/// The folder's contents, its spec and its statistics, as `brdf-sls stats DIR` computes them
/// (and refuses them: a missing results file, or a stored trial whose seed or target is not
/// the plan's, is bad input).
fn load_stats(dir: &Path) -> PyResult<Loaded> {
    let file = if dir.is_dir() {
        results_file(dir)
    } else {
        dir.to_path_buf()
    };
    if !file.is_file() {
        return Err(classify(FolderError::Missing(dir.to_path_buf()).into()));
    }
    let contents = read_store(dir)
        .with_context(|| format!("reading results in {}", dir.display()))
        .map_err(classify)?;
    let mut spec = brdf_analysis::report::stored_spec(&contents, dir).map_err(input_err)?;
    // As `brdf-sls stats`: the recorded best-known RMSEs (computed for older folders). Only
    // relative targets need them; without those, a folder whose data cannot be found again
    // (older folders store data paths relative to the spec) is still read, with a warning.
    let mut warnings = Vec::new();
    match brdf_best_known::resolve(&mut spec, contents.best_known()) {
        // Instances left without a best-known RMSE (their data is not found again) are named.
        Ok(resolved) => warnings.extend(resolved.notes),
        Err(e) => {
            let e = anyhow::Error::from(e).context("finding the best-known RMSEs");
            if spec
                .instances
                .iter()
                .any(|i| !i.relative_targets.is_empty())
            {
                return Err(classify(e));
            }
            warnings.push(format!("no best-known RMSEs: {}", chain(e)));
        }
    }
    // As `brdf-sls stats`: an edited seed, or a target other than the plan's (once resolved),
    // is refused rather than mixed into statistics that claim to be seeded.
    brdf_experiment::seed_check::check_stored(&file, &contents.records, &contents.lines, &spec)
        .map_err(|e| classify(e.into()))?;
    let stats = brdf_analysis::report::compute_stats(&spec, &contents.records);
    Ok((contents, spec, stats, warnings))
}
