//! One run of an experiment as a library call, the sequence behind `brdf-sls run` and the
//! Python package's `brdf_sls.run`: prepare once (lock the results folder, read its results
//! file once, build each instance once, resolve the best-known RMSEs), build the executor from
//! what was prepared (the caller's: algorithms in this process, in worker processes, or both),
//! run or resume the plan, analyse once and write the statistics, the plots and `report.html`.
//!
//! ```no_run
//! use brdf_analysis::pipeline::{Request, run};
//! use brdf_experiment::run::{RunOptions, SlsExecutor};
//! use brdf_experiment::spec::Spec;
//!
//! let request = Request::new(Spec::default_experiment(), "runs/default".into(), 2);
//! let finished = run(request, |spec, built, kernel| {
//!     Ok(SlsExecutor::from_built(spec, built, kernel)?)
//! })?;
//! println!("{}", finished.report.table);
//! # Ok::<(), anyhow::Error>(())
//! ```

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use brdf_best_known::prepare::{PrepareError, prepare};
use brdf_experiment::instance::BuiltInstance;
use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{Executor, RunOptions, RunOutcome, run_locked};
use brdf_experiment::shard::Shard;
use brdf_experiment::spec::Spec;
use brdf_model::Kernel;

use crate::analysis::{Analysis, ChartSet};
use crate::folder::Folder;
use crate::report::{Report, write_analysis};

/// What to run, and how.
#[derive(Clone, Debug)]
pub struct Request {
    /// The experiment.
    pub spec: Spec,
    /// The results folder.
    pub out: PathBuf,
    /// Only this shard of the plan (`--shard K/N`).
    pub shard: Option<Shard>,
    /// Worker threads asked for (checked by the caller), capped with a note at the trials to
    /// run and the logical CPUs; move the old results aside (`fresh`); the progress display;
    /// at most this many new trials (`limit`).
    pub options: RunOptions,
    /// The evaluation kernel.
    pub kernel: Kernel,
    /// Draw the plots and write `report.html`.
    pub plots: bool,
    /// Print the plan, the notes and the closing line on standard error, as `brdf-sls run`
    /// does (the progress display is [`RunOptions::progress`]).
    pub notes: bool,
}

impl Request {
    /// A run of `spec` into `out` on `threads` threads: the whole plan, resumed, with the
    /// spec's kernel, plots, the notes and automatic progress.
    pub fn new(spec: Spec, out: PathBuf, threads: usize) -> Request {
        Request {
            kernel: spec.kernel,
            spec,
            out,
            shard: None,
            options: RunOptions {
                threads,
                ..RunOptions::default()
            },
            plots: true,
            notes: true,
        }
    }
}

/// What a run did and wrote.
#[derive(Clone, Debug)]
pub struct Finished {
    /// The spec as run (best-known RMSEs and relative targets resolved).
    pub spec: Spec,
    /// The trials: every record of the plan present now, counts, sessions, notes.
    pub outcome: RunOutcome,
    /// The statistics, the table and the files written (`report.html` among them when drawn).
    pub report: Report,
    /// Lines shown before the run: instances without a best-known RMSE, closeness warnings.
    pub warnings: Vec<String>,
    /// The worker threads used.
    pub threads: usize,
    /// `wrote N files to OUT (...)`: the run's last line.
    pub summary: String,
}

/// Configurations whose algorithm failed ([`RunOutcome::failures`]): the error a run ends with
/// after it has stored every other trial and written the statistics (bad input: exit status 2).
#[derive(Debug, thiserror::Error)]
#[error(
    "running experiment `{experiment}`: {}; trials missing: {missing}; the other \
     configurations ran and every finished trial is saved, with the statistics: fix the \
     algorithm and run again to resume",
    failures.join("; ")
)]
pub struct ConfigurationsFailed {
    /// The experiment.
    pub experiment: String,
    /// One message per failed configuration.
    pub failures: Vec<String>,
    /// Trials of the plan still missing.
    pub missing: usize,
}

/// Runs `request` (see the module docs); `make` builds the executor from the spec (targets
/// resolved), the instances built once (`built[i]` is `spec.instances[i]`) and the kernel.
/// Errors carry the command line's context (`building the instances`, `running experiment
/// ...`, `writing statistics and plots`); a run in which configurations failed ends with
/// [`ConfigurationsFailed`] once everything else is written.
pub fn run<E, F>(request: Request, make: F) -> Result<Finished>
where
    E: Executor,
    F: FnOnce(&Spec, &[BuiltInstance], Kernel) -> Result<E>,
{
    let say = |line: &str| {
        if request.notes {
            let line = brdf_experiment::terminal::safe(line);
            let _ = writeln!(std::io::stderr().lock(), "{line}");
        }
    };
    let Request {
        spec, out, shard, ..
    } = request.clone();
    let threads = useful_threads(&request, &spec, &say);
    let prepared = prepare(spec, &out).map_err(|e| match e {
        PrepareError::Store(e) => anyhow::Error::new(e),
        PrepareError::Instance(e) => anyhow::Error::new(e).context("building the instances"),
    })?;
    for line in &prepared.notes {
        say(line);
    }
    let before = prepared.folder.contents().map(last_session);
    let spec = &prepared.spec;
    say(&spec.describe(threads));
    say(&format!("results: {}", out.display()));
    let machine = brdf_experiment::machine::MachineInfo::current(threads);
    say(&format!(
        "machine: {}, {} logical CPUs, {} worker thread(s)",
        machine.cpu_model, machine.logical_cpus, threads
    ));
    let executor = make(spec, &prepared.built, request.kernel)?;
    let provenance = executor.provenance();
    say(&format!(
        "evaluation kernel: {}, solver kernel: {}",
        provenance.kernel, provenance.solver_kernel
    ));
    let mut warnings = prepared.notes.clone();
    if let Some(before) = before.filter(|_| !request.options.fresh) {
        for line in changes_since(&before, &provenance) {
            say(&format!("note: {line}"));
            warnings.push(line);
        }
    }
    for (i, b) in spec.instances.iter().zip(&prepared.built) {
        let rep = b
            .filter_report
            .map(|r| format!(" ({r})"))
            .unwrap_or_default();
        say(&format!(
            "instance {}: {} samples{rep}",
            i.name,
            b.data.len()
        ));
    }
    if let Some(s) = shard {
        say(&format!(
            "shard {s}: {} of the {} trials",
            s.select(spec.trials_plan()).len(),
            spec.trials_plan().len()
        ));
    }
    let options = RunOptions {
        threads,
        progress: if request.notes {
            request.options.progress
        } else {
            ProgressMode::Quiet
        },
        ..request.options.clone()
    };
    let outcome = run_locked(spec, shard, prepared.folder, &options, &executor)
        .with_context(|| format!("running experiment `{}`", spec.name))?;
    drop(executor);
    for n in &outcome.notes {
        say(&format!("note: {n}"));
    }
    say(&format!(
        "{} new trials in {} wall on {} thread(s) ({} resumed){}",
        outcome.new_trials,
        brdf_experiment::spec::human_seconds(outcome.wall_seconds),
        threads,
        outcome.resumed,
        if outcome.missing > 0 {
            format!(
                "; {} trials still to run (run again to resume)",
                outcome.missing
            )
        } else {
            String::new()
        }
    ));
    // One analysis for the files and the page: statistics and charts are computed once.
    let charts = if request.plots {
        ChartSet::Page
    } else {
        ChartSet::None
    };
    let analysis = Analysis::new(spec, &outcome.records, charts);
    let mut report = write_analysis(spec, analysis, &outcome.sessions, &out, request.plots)
        .context("writing statistics and plots")?;
    if request.plots {
        let folder = Folder::from_run(&out, spec.clone(), &outcome);
        let page = crate::html::report_page_of(&[(&folder, &report.analysis)], &out)
            .context("building the report page")?;
        let path = out.join("report.html");
        brdf_experiment::store::write_atomic(&path, page.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        report.files.push(path);
    }
    if !outcome.failures.is_empty() {
        return Err(ConfigurationsFailed {
            experiment: spec.name.clone(),
            failures: outcome.failures.iter().map(|f| f.message.clone()).collect(),
            missing: outcome.missing,
        }
        .into());
    }
    let summary = written_summary(report.files.len(), &out, request.plots, request.plots);
    Ok(Finished {
        spec: prepared.spec,
        outcome,
        report,
        warnings,
        threads,
        summary,
    })
}

/// What wrote the results so far: the program, its version and the custom kinds' schemas of
/// the last session (of the header in files without sessions).
struct Written {
    program: String,
    version: String,
    schemas: std::collections::BTreeMap<String, String>,
}

fn last_session(c: &brdf_experiment::store::Contents) -> Written {
    match c.sessions.last() {
        Some(s) => Written {
            program: s.program.clone(),
            version: s.program_version.clone(),
            schemas: s.schemas.clone(),
        },
        None => Written {
            program: c.header.program.clone(),
            version: c.header.program_version.clone(),
            schemas: c.header.schemas.clone(),
        },
    }
}

/// Notes on what changed since the results so far were written: the program (a custom
/// binary's name and version, the workspace's version and commit) and the settings schema of
/// each custom kind. Nothing for files that did not record them.
fn changes_since(before: &Written, now: &brdf_experiment::run::Provenance) -> Vec<String> {
    let mut lines = Vec::new();
    let version = brdf_experiment::PROGRAM_VERSION;
    let was = format!("{} (brdf-sls {})", before.program, before.version);
    let is = format!("{} (brdf-sls {version})", now.program);
    if (!before.version.is_empty() && before.version != version)
        || (!before.program.is_empty() && before.program != now.program)
    {
        lines.push(format!(
            "the results so far were written by {}; this session runs {}: the code may have \
             changed in between",
            was.trim(),
            is.trim()
        ));
    }
    for (kind, hash) in &now.schemas {
        if let Some(old) = before.schemas.get(kind)
            && old != hash
        {
            lines.push(format!(
                "the settings schema of kind `{kind}` changed since the results so far were \
                 written (schema {old}, now {hash}): its fields or defaults differ"
            ));
        }
    }
    lines
}

/// The worker threads of a run: the request's, capped (with a note) at the trials of the plan
/// (or shard, or limit) and the logical CPUs.
fn useful_threads(request: &Request, spec: &Spec, say: &dyn Fn(&str)) -> usize {
    let planned = match request.shard {
        Some(s) => s.select(spec.trials_plan()).len(),
        None => spec.trials_plan().len(),
    };
    let trials = request.options.limit.map_or(planned, |l| planned.min(l));
    let cpus = brdf_experiment::run::default_threads();
    let (threads, capped) = brdf_experiment::threads::useful(request.options.threads, trials, cpus);
    if let Some(c) = capped {
        say(&format!("note: {c}"));
    }
    threads
}

/// The last line of `run` and `merge`: how many files went where, naming plots/ (and the
/// report page) only when they were drawn.
pub fn written_summary(files: usize, out: &Path, plots: bool, page: bool) -> String {
    format!(
        "wrote {files} files to {} (statistics: stats.csv, tests.csv{})",
        out.display(),
        match (plots, page) {
            (true, true) => "; plots: plots/; page: report.html",
            (true, false) => "; plots: plots/",
            _ => "",
        }
    )
}
