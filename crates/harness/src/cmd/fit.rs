//! `brdf-sls fit`: one fit of one data set with one algorithm (the logic is the library's
//! [`brdf_experiment::fit`], shared with the Python package).

use std::sync::Arc;

use anyhow::{Context, Result};
use brdf_experiment::progress::ProgressMode;
use brdf_fit::{
    FitProgress, FitRequest, Surface, algorithm_config, check_budget, model_spec, with_bounds,
};

use super::shared::load_non_empty;
use super::{input_error, say};
use crate::cli::FitArgs;

/// `brdf-sls fit`.
pub fn fit(a: FitArgs) -> Result<()> {
    check_budget(Surface::Cli, a.cpu_seconds, a.target)?;
    if a.bootstrap > brdf_experiment::spec::limits::MAX_BOOTSTRAP {
        return Err(input_error(format!(
            "--bootstrap {}: at most {}",
            a.bootstrap,
            brdf_experiment::spec::limits::MAX_BOOTSTRAP
        )));
    }
    let algorithm = algorithm_config(Surface::Cli, &a.algorithm, a.set.iter().cloned())?;
    let m = &a.model;
    let model = model_spec(
        Surface::Cli,
        m.family.clone(),
        m.lobes,
        m.kind(),
        m.exponent,
        m.fixed.iter().cloned(),
    )?;
    let model = with_bounds(Surface::Cli, model, m.bounds.iter().cloned())?;
    let (data, _) = load_non_empty(&a.data)?;
    let data = Arc::new(data);
    let request = FitRequest {
        model,
        algorithm,
        seed: a.seed,
        cpu_seconds: a.cpu_seconds,
        target: a.target,
        kernel: a.kernel,
        descent: a.descent,
        polish: !a.no_polish,
        progress: fit_progress(a.progress),
        surface: Surface::Cli,
    };
    let fit = brdf_fit::fit(data.clone(), &request, None)?;
    let (r, layout) = (&fit.result, &fit.layout);
    say!(
        "algorithm {} (seed {}, kernel {}, descent {}, brdf-sls {}), stop: {:?}",
        request.algorithm.kind_name(),
        a.seed,
        fit.kernel,
        request.descent,
        brdf_experiment::PROGRAM_VERSION,
        r.stop
    );
    say!(
        "RMSE {:.17} after {:.4} CPU s ({:.4} wall s, {} sample-evaluations)",
        fit.rmse,
        r.ended_at.cpu_seconds,
        r.ended_at.wall_seconds,
        r.ended_at.evaluations.total()
    );
    if let Some(at) = r.reached_at {
        say!("target {} reached at {:.4} CPU s", a.target, at.cpu_seconds);
    }
    match &fit.polish {
        Some(p) => say!(
            "polish: the search's best RMSE {:.17} became {:.17} after {} full-data \
             descent(s) with the solver's robust preset ({:.4} wall s); the last ended with {}, {}",
            p.rmse_before,
            p.rmse_after,
            p.descents,
            p.wall_seconds,
            p.rest.end_text(),
            if p.rest.at_rest {
                "at rest".to_string()
            } else {
                format!(
                    "NOT at rest after {} descents (the limit): refit from the JSON below, or \
                     check with --diagnose",
                    p.descents
                )
            }
        ),
        None => say!("polish: off (--no-polish): the search's best, not necessarily at rest"),
    }
    say!("fitted parameters:");
    // Lafortune's names fit in 10 columns; other families' may be longer (`lobe12.alpha`).
    let width = layout
        .all_names()
        .iter()
        .map(|n| n.len())
        .max()
        .unwrap_or(0)
        .max(10);
    for name in layout.all_names() {
        let v = fit.params.get(name).unwrap_or(f64::NAN);
        let tag = if layout.fixed_value(name).is_some() {
            " (fixed)"
        } else {
            ""
        };
        say!("  {name:<width$} {v:>22.17}{tag}");
    }
    // Another seed may land on a mirrored form of the same fit (a lobe turned by 90 degrees
    // with its x and y swapped, the lobes in another order); without this line it reads as
    // another answer.
    if let Some(note) = layout.equivalence_note() {
        say!("{note}");
    }
    say!("{}", lobes_line(&fit, data.len()));
    let json = serde_json::to_string(&fit.params).context("serialising the parameters")?;
    say!("json: {json}");
    if a.diagnose {
        let options = brdf_stress::DiagnoseOptions {
            bootstrap: a.bootstrap,
            seed: a.seed,
            ..brdf_stress::DiagnoseOptions::default()
        };
        let d =
            brdf_stress::diagnose(layout, &data, &fit.x, &options).context("diagnosing the fit")?;
        say!("\n{}", d.to_markdown().trim_end());
    }
    Ok(())
}

/// One line on the lobes: the samples each covers, and a warning naming the dead ones
/// (brdf_best_known::lobe_use).
fn lobes_line(fit: &brdf_fit::FitOutcome, samples: usize) -> String {
    use brdf_best_known::lobe_use::{COVER, DEAD_LOBE, describe};
    let mut line = format!(
        "lobes: {} (a lobe is on a sample where it gives at least {}% of its peak)",
        describe(&fit.lobes, samples),
        COVER * 100.0
    );
    let dead = fit.dead_lobes();
    if !dead.is_empty() {
        let names: Vec<String> = dead.iter().map(|k| format!("lobe{k}")).collect();
        line.push_str(&format!(
            "\nwarning: {} dead (at most {DEAD_LOBE:e} of the data's RMS value on every \
             sample): the fit has {} working lobe(s) of {}; another seed, a longer \
             --cpu-seconds or a restarting search (rpls, the default, or aed with --set \
             stall_limit=10) may revive it, unless fixed parameters hold it dead",
            names.join(", ") + if dead.len() == 1 { " is" } else { " are" },
            fit.lobes.len() - dead.len(),
            fit.lobes.len()
        ));
    }
    line
}

/// `--progress` for a fit: on a terminal one line updated in place; `auto` shows nothing
/// elsewhere (a fit's output is its result, not a log).
fn fit_progress(mode: ProgressMode) -> FitProgress {
    match mode {
        ProgressMode::Auto => match mode.resolve() {
            ProgressMode::Bars => FitProgress::Line,
            _ => FitProgress::Quiet,
        },
        ProgressMode::Bars => FitProgress::Line,
        ProgressMode::Plain => FitProgress::Lines,
        ProgressMode::Quiet => FitProgress::Quiet,
    }
}
