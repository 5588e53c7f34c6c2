//! `brdf-sls stats` and `brdf-sls plot`: statistics and plots of stored results.

use std::path::Path;

use anyhow::{Context, Result};
use brdf_experiment::store::read_results;

use super::shared::{default_out, load_spec};
use super::{input_error, note, say};
use crate::cli::ResultsArgs;

/// `brdf-sls plot` (`plots` true) and `brdf-sls stats`.
pub fn results(a: ResultsArgs, plots: bool) -> Result<()> {
    if plots && a.print_only {
        return Err(input_error(
            "--print-only belongs to `stats`; `plot` writes plots",
        ));
    }
    let target = a.target.clone().unwrap_or_else(|| default_out(None));
    if !target.exists() {
        return Err(input_error(format!(
            "{}: no such file or folder (expected a results folder, a file in one, or the \
             spec .toml that wrote it)",
            target.display()
        )));
    }
    let is_spec = target.extension().is_some_and(|e| e == "toml");
    let (spec, dir) = if is_spec {
        let spec = load_spec(&target)?;
        let dir = a.out.clone().unwrap_or_else(|| default_out(Some(&target)));
        (Some(spec), dir)
    } else {
        let dir = if target.is_dir() {
            target.clone()
        } else {
            match target.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => Path::new(".").to_path_buf(),
            }
        };
        (None, dir)
    };
    let contents =
        read_results(&dir).with_context(|| format!("reading results in {}", dir.display()))?;
    let mut spec = match spec {
        Some(s) => {
            if s.fingerprint() != contents.header.fingerprint {
                return Err(input_error(format!(
                    "{} was written by a different spec (fingerprint {} vs {}): pass the spec that produced it, or the results directory alone",
                    dir.display(),
                    contents.header.fingerprint,
                    s.fingerprint()
                )));
            }
            s
        }
        None => match brdf_analysis::report::stored_spec(&contents, &dir) {
            Ok(s) => s,
            Err(brdf_analysis::report::StoredSpecError::Spec(e)) => return Err(e.into()),
            Err(e) => return Err(input_error(e.to_string())),
        },
    };
    // Recorded best-known RMSEs when the folder has them; computed (seeded) for older folders.
    let resolved = brdf_best_known::resolve(&mut spec, contents.best_known())
        .context("finding the best-known RMSEs")?;
    for n in resolved.notes {
        note!("note: {n}");
    }
    let file = brdf_experiment::store::results_file(&dir);
    brdf_experiment::seed_check::check_stored(&file, &contents.records, &contents.lines, &spec)?;
    let below = brdf_best_known::below_best_known(&spec, &contents.records);
    for w in brdf_best_known::warnings(&spec).into_iter().chain(below) {
        note!("{w}");
    }
    if let Some(t) = &contents.torn {
        note!("note: ignoring a torn last line ({} bytes)", t.len());
    }
    let planned = spec.trials_plan().len();
    let present = brdf_analysis::report::plan_records(&spec, &contents.records).len();
    if present < planned {
        note!(
            "note: partial results: {present} of {planned} trials present (run the spec again to resume)"
        );
    }
    if a.print_only {
        let stats = brdf_analysis::report::compute_stats(&spec, &contents.records);
        say!("{}", brdf_analysis::stats::table(&stats));
        let summary = brdf_best_known::summary(&spec);
        if !summary.is_empty() {
            say!("{}", summary.trim_end());
        }
        return Ok(());
    }
    // With a results folder or file, --out names where to write (default: that folder); with
    // a spec it names the results folder, which is also where the files go.
    let out = match (&a.out, is_spec) {
        (Some(o), false) => o.clone(),
        _ => dir.clone(),
    };
    brdf_experiment::input_file::check_out_dir(&out)
        .map_err(|e| input_error(format!("--out {}: {e}", out.display())))?;
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    // The lock of a results folder written into: a running `run` holds it (and would rewrite
    // these files when it ends), so writing now would race with it.
    let what = if plots { "plots" } else { "statistics" };
    let _lock = super::report::lock_if_results(&out)
        .with_context(|| format!("not writing {what} into {}", out.display()))?;
    let report = brdf_analysis::report::write_report(
        &spec,
        &contents.records,
        &contents.sessions,
        &out,
        plots,
    )?;
    say!("{}", report.table);
    say!("wrote {} files to {}", report.files.len(), out.display());
    Ok(())
}
