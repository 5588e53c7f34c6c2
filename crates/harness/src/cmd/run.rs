//! `brdf-sls run`: run or resume an experiment, then write its statistics, table and plots.

use anyhow::{Context, Result};
use brdf_analysis::analysis::ChartSet;
use brdf_experiment::prepare::{PrepareError, prepare};
use brdf_experiment::run::{Executor, RunOptions, SlsExecutor, default_threads, run_locked};
use brdf_experiment::spec::Spec;

use super::shared::{default_out, load_spec};
use super::{input_error, note, say};
use crate::cli::RunArgs;

/// `brdf-sls run`: checks the flags, [`prepare`]s (lock, one read of the results, each instance
/// built once, best-known RMSEs), runs, then writes statistics and plots.
pub fn run(a: RunArgs) -> Result<()> {
    let spec = match &a.spec {
        Some(p) => load_spec(p)?,
        None => Spec::default_experiment(),
    };
    if let Some(p) = &a.spec
        && super::python::uses_python(&spec)
    {
        return super::python::delegate_run(&a, p);
    }
    let out = a.out.clone().unwrap_or_else(|| {
        let base = default_out(a.spec.as_deref());
        match a.shard {
            Some(s) => base.join(s.dir_name()),
            None => base,
        }
    });
    brdf_experiment::input_file::check_out_dir(&out)
        .map_err(|e| input_error(format!("--out {}: {e}", out.display())))?;
    let threads = useful_threads(&a, &spec)?;
    let kernel = a.kernel.unwrap_or(spec.kernel);
    let prepared = prepare(spec, &out).map_err(|e| match e {
        PrepareError::Store(e) => anyhow::Error::new(e),
        PrepareError::Instance(e) => anyhow::Error::new(e).context("building the instances"),
    })?;
    for line in &prepared.notes {
        note!("{line}");
    }
    let spec = &prepared.spec;
    note!("{}", spec.describe(threads));
    note!("results: {}", out.display());
    let machine = brdf_experiment::machine::MachineInfo::current(threads);
    note!(
        "machine: {}, {} logical CPUs, {} worker thread(s)",
        machine.cpu_model,
        machine.logical_cpus,
        threads
    );
    let executor =
        SlsExecutor::from_built(spec, &prepared.built, kernel).context("building the instances")?;
    let provenance = executor.provenance();
    note!(
        "evaluation kernel: {}, solver kernel: {}",
        provenance.kernel,
        provenance.solver_kernel
    );
    for (i, b) in spec.instances.iter().zip(&prepared.built) {
        let rep = b
            .filter_report
            .map(|r| format!(" ({r})"))
            .unwrap_or_default();
        note!("instance {}: {} samples{rep}", i.name, b.data.len());
    }
    let options = RunOptions {
        threads,
        fresh: a.fresh,
        progress: a.progress,
        limit: a.limit,
    };
    if let Some(s) = a.shard {
        note!(
            "shard {s}: {} of the {} trials",
            s.select(spec.trials_plan()).len(),
            spec.trials_plan().len()
        );
    }
    let outcome = run_locked(spec, a.shard, prepared.folder, &options, &executor)
        .with_context(|| format!("running experiment `{}`", spec.name))?;
    for n in &outcome.notes {
        note!("note: {n}");
    }
    note!(
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
    );
    // One analysis for the files and the page.
    let charts = if a.no_plots {
        ChartSet::None
    } else {
        ChartSet::Page
    };
    let analysis = brdf_analysis::analysis::Analysis::new(spec, &outcome.records, charts);
    let report =
        brdf_analysis::report::write_analysis(spec, analysis, &outcome.sessions, &out, !a.no_plots)
            .context("writing statistics and plots")?;
    let mut written = report.files.len();
    if !a.no_plots {
        let folder = brdf_analysis::folder::Folder::from_run(&out, spec.clone(), &outcome);
        let page = out.join("report.html");
        super::report::write_report_page_of(&[(&folder, &report.analysis)], &page)?;
        written += 1;
    }
    say!("{}", report.table);
    say!(
        "{}",
        super::written_summary(written, &out, !a.no_plots, !a.no_plots)
    );
    Ok(())
}

/// The worker threads of a run: the flag's, else the spec's, else all CPUs; refused above
/// [`brdf_experiment::threads::MAX_THREADS`], and capped (with a note) at the trials of the
/// plan (or shard, or `--limit`) and the logical CPUs.
fn useful_threads(a: &RunArgs, spec: &Spec) -> Result<usize> {
    let requested = match a.threads {
        Some(n) => {
            brdf_experiment::threads::check(n, "--threads").map_err(input_error)?;
            n
        }
        None => spec.threads.unwrap_or_else(default_threads),
    };
    let planned = match a.shard {
        Some(s) => s.select(spec.trials_plan()).len(),
        None => spec.trials_plan().len(),
    };
    let trials = a.limit.map_or(planned, |l| planned.min(l));
    let (threads, capped) = brdf_experiment::threads::useful(requested, trials, default_threads());
    if let Some(c) = capped {
        note!("note: {c}");
    }
    Ok(threads)
}
