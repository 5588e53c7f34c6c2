//! `run` (an experiment spec, as `brdf-sls run`) and `read_results` (a results folder as
//! records for pandas).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::Context;
use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{
    Executor, Provenance, RunError, RunOptions, SlsExecutor, default_threads, run_experiment,
};
use brdf_experiment::spec::{PlannedTrial, Spec};
use brdf_experiment::store::{StoreError, read_results as read_store};
use brdf_model::Kernel;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sls::{Budget, TrialResult};

use crate::support::{chain, input_err, interruptible, run_err, to_python};

/// Options of [`run`] besides the spec.
struct RunArgs {
    out: PathBuf,
    threads: usize,
    fresh: bool,
    limit: Option<usize>,
    plots: bool,
    kernel: Kernel,
}

/// What a run did, for the result dict.
struct Ran {
    new_trials: usize,
    resumed: usize,
    missing: usize,
    notes: Vec<String>,
    table: String,
    files: Vec<PathBuf>,
}

/// Runs (or resumes) an experiment as `brdf-sls run SPEC` does: the same trials with the same
/// seeds, the same results folder (trials.jsonl, statistics, table, plots).
///
/// spec: the TOML file (None: the built-in default experiment); out: the results folder
/// (default `runs/<spec stem>/`, relative to the working directory, as the command line);
/// threads (default: the spec's, else all CPUs); fresh: move old results aside; limit: run at
/// most this many new trials; plots: draw the plots; kernel: overrides the spec's.
///
/// Returns a dict: out, new_trials, resumed, missing, notes, warnings (targets close to the
/// best-known RMSE), table, files. Releases the GIL;
/// Ctrl-C stops the trials in flight (none of them is stored) and raises KeyboardInterrupt;
/// running again resumes.
#[pyfunction]
#[pyo3(signature = (spec=None, out=None, *, threads=None, fresh=false, limit=None, plots=true, kernel=None))]
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
) -> PyResult<Py<PyAny>> {
    let mut loaded = match &spec {
        Some(p) => py
            .detach(|| Spec::from_file(p))
            .map_err(|e| input_err(chain(e.into())))?,
        None => Spec::default_experiment(),
    };
    let stem = spec
        .as_deref()
        .and_then(Path::file_stem)
        .map_or_else(|| "default".into(), |s| s.to_string_lossy().into_owned());
    let threads = threads.or(loaded.threads).unwrap_or_else(default_threads);
    if threads == 0 {
        return Err(input_err("threads must be at least 1"));
    }
    let kernel = match kernel {
        Some(k) => k.parse().map_err(input_err)?,
        None => loaded.kernel,
    };
    let out = out.unwrap_or_else(|| PathBuf::from(brdf_experiment::DEFAULT_RUNS_DIR).join(stem));
    // As `brdf-sls run`: relative targets need the best-known RMSEs (recorded or computed).
    let warnings = py
        .detach(|| brdf_experiment::best_known::resolve_for_run(&mut loaded, Some(&out)))
        .context("finding the best-known RMSEs")
        .map_err(classify)?;
    let args = RunArgs {
        out,
        threads,
        fresh,
        limit,
        plots,
        kernel,
    };
    let ran = interruptible(py, |flag| run_spec(&loaded, &args, flag))??;
    let d = PyDict::new(py);
    d.set_item("out", args.out.clone())?;
    d.set_item("new_trials", ran.new_trials)?;
    d.set_item("resumed", ran.resumed)?;
    d.set_item("missing", ran.missing)?;
    d.set_item("notes", ran.notes)?;
    d.set_item("warnings", warnings)?;
    d.set_item("table", ran.table)?;
    d.set_item("files", ran.files)?;
    Ok(d.into_any().unbind())
}

/// The work of [`run`] on the worker thread: the steps of `brdf-sls run` without printing.
fn run_spec(
    spec: &Spec,
    a: &RunArgs,
    flag: std::sync::Arc<std::sync::atomic::AtomicBool>,
) -> PyResult<Ran> {
    let (mut executor, _) = SlsExecutor::new(spec, a.kernel)
        .context("building the instances")
        .map_err(classify)?;
    executor.set_interrupt(flag);
    let executor = PyExecutor {
        inner: executor,
        spec,
        failures: Mutex::new(Vec::new()),
    };
    let options = RunOptions {
        threads: a.threads,
        fresh: a.fresh,
        progress: ProgressMode::Quiet,
        limit: a.limit,
    };
    let outcome = match run_experiment(spec, &a.out, &options, &executor) {
        Err(RunError::Interrupted) => {
            return Err(PyKeyboardInterrupt::new_err(
                RunError::Interrupted.to_string(),
            ));
        }
        r => r
            .with_context(|| format!("running experiment `{}`", spec.name))
            .map_err(classify)?,
    };
    let contents = read_store(&a.out)
        .context("reading back the results")
        .map_err(classify)?;
    let report = brdf_analysis::report::write_report(
        spec,
        &outcome.records,
        &contents.sessions,
        &a.out,
        a.plots,
    )
    .context("writing statistics and plots")
    .map_err(classify)?;
    if let Some(message) = executor.failure_message(outcome.missing) {
        return Err(input_err(message));
    }
    Ok(Ran {
        new_trials: outcome.new_trials,
        resumed: outcome.resumed,
        missing: outcome.missing,
        notes: outcome.notes,
        table: report.table,
        files: report.files,
    })
}

/// The run's executor: [`SlsExecutor`], plus the failures of Python algorithms. A trial whose
/// algorithm failed ends as interrupted; its configuration's trials are skipped from then on
/// (neither that one nor the others are stored) while the other configurations run to the end,
/// and [`PyExecutor::failure_message`] names the configuration afterwards.
struct PyExecutor<'a> {
    inner: SlsExecutor,
    spec: &'a Spec,
    /// The failed configurations (by index) and the first failure of each.
    failures: Mutex<Vec<(usize, String)>>,
}

impl PyExecutor<'_> {
    fn failures(&self) -> std::sync::MutexGuard<'_, Vec<(usize, String)>> {
        self.failures.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The error of a run in which configurations failed, `missing` trials left unrun.
    fn failure_message(&self, missing: usize) -> Option<String> {
        let failures = self.failures();
        if failures.is_empty() {
            return None;
        }
        let each: Vec<&str> = failures.iter().map(|(_, m)| m.as_str()).collect();
        Some(format!(
            "running experiment `{}`: {}; trials missing: {missing}; the other configurations \
             ran and every finished trial is saved, with the statistics: fix the algorithm and \
             run again to resume",
            self.spec.name,
            each.join("; ")
        ))
    }
}

impl Executor for PyExecutor<'_> {
    fn provenance(&self) -> Provenance {
        self.inner.provenance()
    }

    fn run(&self, trial: &PlannedTrial, target: f64, budget: Budget) -> TrialResult {
        let result = crate::algorithm::with_cpu_cutoff(budget.cpu_seconds, || {
            self.inner.run(trial, target, budget)
        });
        if let Some(message) = crate::algorithm::take_failure() {
            let mut failures = self.failures();
            // Trials of the configuration that were in flight may fail too: the first says it.
            if !failures.iter().any(|(c, _)| *c == trial.config) {
                let label = &self.spec.configurations[trial.config].label;
                let message = format!(
                    "configuration `{label}` failed in trial {} (seed {}): {message}",
                    trial.key, trial.seed
                );
                failures.push((trial.config, message));
            }
        }
        result
    }

    fn skip(&self, trial: &PlannedTrial) -> bool {
        self.failures().iter().any(|(c, _)| *c == trial.config)
    }
}

/// An error of a run as InputError (what the command line treats as bad input, exit status
/// 2) or RunError (status 1), with the command line's message.
fn classify(e: anyhow::Error) -> PyErr {
    let input = e.chain().any(|c| {
        c.is::<brdf_experiment::spec::SpecError>()
            || c.is::<brdf_experiment::instance::InstanceError>()
            || c.is::<brdf_model::KernelError>()
            || matches!(
                c.downcast_ref::<RunError>(),
                Some(
                    RunError::ShardMismatch { .. }
                        | RunError::Store(
                            StoreError::FingerprintMismatch { .. } | StoreError::DataChanged { .. }
                        )
                )
            )
            || matches!(
                c.downcast_ref::<StoreError>(),
                Some(StoreError::FingerprintMismatch { .. } | StoreError::DataChanged { .. })
            )
    });
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

/// The folder's contents, its spec and its statistics, as `brdf-sls stats DIR` computes them.
fn load_stats(dir: &Path) -> PyResult<Loaded> {
    let contents = read_store(dir)
        .with_context(|| format!("reading results in {}", dir.display()))
        .map_err(|e| {
            let input = e.chain().any(|c| c.is::<StoreError>());
            let message = chain(e);
            if input {
                input_err(message)
            } else {
                run_err(message)
            }
        })?;
    let mut spec = brdf_analysis::report::stored_spec(&contents, dir).map_err(input_err)?;
    // As `brdf-sls stats`: the recorded best-known RMSEs (computed for older folders). Only
    // relative targets need them; without those, a folder whose data cannot be found again
    // (older folders store data paths relative to the spec) is still read, with a warning.
    let mut warnings = Vec::new();
    match brdf_experiment::best_known::resolve(&mut spec, contents.best_known()) {
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
    let stats = brdf_analysis::report::compute_stats(&spec, &contents.records);
    Ok((contents, spec, stats, warnings))
}
