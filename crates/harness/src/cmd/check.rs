//! `brdf-sls check`: validate a spec and print its plan.

use anyhow::{Context, Result};
use brdf_best_known::{CHECK_MAX_SAMPLES, resolve_within, warnings};
use brdf_experiment::run::default_threads;

use super::shared::{default_out, load_spec};
use super::{input_error, note, say};
use crate::cli::CheckArgs;

/// `brdf-sls check`.
pub fn check(a: CheckArgs) -> Result<()> {
    let mut spec = load_spec(&a.spec)?;
    if let Some(n) = a.threads {
        brdf_experiment::threads::check(n, "--threads").map_err(input_error)?;
    }
    let threads = a.threads.or(spec.threads).unwrap_or_else(default_threads);
    say!("{}", spec.describe(threads).trim_end());
    for i in &spec.instances {
        if let brdf_experiment::spec::Source::File { resolved, .. } = &i.source
            && !resolved.exists()
        {
            return Err(input_error(format!(
                "instance `{}`: data file {} does not exist",
                i.name,
                resolved.display()
            )));
        }
    }
    // The best-known RMSE costs tens of seconds on a million samples: check computes it only
    // for instances up to the limit unless asked to, and says so.
    let limit = (!a.best_known).then_some(CHECK_MAX_SAMPLES);
    let resolved = resolve_within(&mut spec, &Default::default(), limit)
        .context("finding the best-known RMSEs")?;
    for n in &resolved.notes {
        note!("note: {n}");
    }
    for w in warnings(&spec) {
        note!("{w}");
    }
    say!(
        "best-known RMSE computed for {} of {} instance(s){}",
        resolved.known.len(),
        spec.instances.len(),
        if resolved.skipped > 0 {
            format!(
                "; {} skipped for size (over {CHECK_MAX_SAMPLES} samples; `run` computes them, \
                 `check --best-known` forces them)",
                resolved.skipped
            )
        } else {
            String::new()
        }
    );
    let summary = brdf_best_known::summary(&spec);
    if !summary.is_empty() {
        say!("{}", summary.trim_end());
    }
    // How many samples the best-known fit's lobes cover: a sharp lobe on a few samples of
    // many makes the best-known RMSE (and every target relative to it) fragile.
    for (name, (samples, uses)) in &resolved.lobes {
        say!(
            "  {name}: best-known fit's {} (a lobe is on a sample where it gives at least {}% \
             of its peak)",
            brdf_best_known::lobe_use::describe(uses, *samples),
            brdf_best_known::lobe_use::COVER * 100.0
        );
    }
    say!("fingerprint {}", spec.fingerprint());
    say!(
        "default results directory: {}",
        default_out(Some(&a.spec)).display()
    );
    Ok(())
}
