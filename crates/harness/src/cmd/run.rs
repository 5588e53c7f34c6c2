//! `brdf-sls run`: run or resume an experiment, then write its statistics, table and plots.

use anyhow::{Context, Result};
use harness::run::{Executor, RunOptions, SlsExecutor, default_threads, run_shard};
use harness::spec::Spec;
use harness::store::read_results;

use super::shared::{default_out, load_spec, resolve_best_known};
use super::{input_error, note, say};
use crate::cli::RunArgs;

/// `brdf-sls run`.
pub fn run(a: RunArgs) -> Result<()> {
    let mut spec = match &a.spec {
        Some(p) => load_spec(p)?,
        None => Spec::default_experiment(),
    };
    let out = a.out.clone().unwrap_or_else(|| {
        let base = default_out(a.spec.as_deref());
        match a.shard {
            Some(s) => base.join(s.dir_name()),
            None => base,
        }
    });
    resolve_best_known(&mut spec, Some(&out))?;
    let threads = a.threads.or(spec.threads).unwrap_or_else(default_threads);
    if threads == 0 {
        return Err(input_error("--threads must be at least 1"));
    }
    note!("{}", spec.describe(threads));
    note!("results: {}", out.display());
    let machine = harness::machine::MachineInfo::current(threads);
    note!(
        "machine: {}, {} logical CPUs, {} worker thread(s)",
        machine.cpu_model,
        machine.logical_cpus,
        threads
    );
    let kernel = a.kernel.unwrap_or(spec.kernel);
    let (executor, built) = SlsExecutor::new(&spec, kernel).context("building the instances")?;
    let provenance = executor.provenance();
    note!(
        "evaluation kernel: {}, solver kernel: {}",
        provenance.kernel,
        provenance.solver_kernel
    );
    for (i, b) in spec.instances.iter().zip(&built) {
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
    let outcome = run_shard(&spec, a.shard, &out, &options, &executor)
        .with_context(|| format!("running experiment `{}`", spec.name))?;
    for n in &outcome.notes {
        note!("note: {n}");
    }
    note!(
        "{} new trials in {} wall on {} thread(s) ({} resumed){}",
        outcome.new_trials,
        harness::spec::human_seconds(outcome.wall_seconds),
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
    let contents = read_results(&out).context("reading back the results")?;
    let report = harness::report::write_report(
        &spec,
        &outcome.records,
        &contents.sessions,
        &out,
        !a.no_plots,
    )
    .context("writing statistics and plots")?;
    say!("{}", report.table);
    say!(
        "{}",
        super::written_summary(report.files.len(), &out, !a.no_plots)
    );
    Ok(())
}
