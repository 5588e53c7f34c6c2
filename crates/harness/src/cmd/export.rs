//! `brdf-sls export --format ioh DIR`: stored results in IOHprofiler's format.

use std::path::Path;

use anyhow::{Context, Result};
use brdf_experiment::store::read_results;

use super::{input_error, note, say};
use crate::cli::{ExportArgs, ExportFormat};

/// `brdf-sls export`.
pub fn export(a: ExportArgs) -> Result<()> {
    let dir = if a.dir.is_dir() {
        a.dir.clone()
    } else if a.dir.exists() {
        match a.dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => Path::new(".").to_path_buf(),
        }
    } else {
        return Err(input_error(format!(
            "{}: no such results directory or file",
            a.dir.display()
        )));
    };
    let contents =
        read_results(&dir).with_context(|| format!("reading results in {}", dir.display()))?;
    let spec = super::shared::stored_spec(
        &contents,
        &dir,
        &dir.display().to_string(),
        "instances and configurations are",
    )?;
    // Seeds are checked here; targets too when none is relative (export resolves no
    // best-known RMSE, so a relative target is not known here).
    let file = brdf_experiment::store::results_file(&dir);
    brdf_experiment::seed_check::check_stored(&file, &contents.records, &contents.lines, &spec)?;
    let records = brdf_analysis::report::plan_records(&spec, &contents.records);
    let planned = spec.trials_plan().len();
    if records.len() < planned {
        note!(
            "note: partial results: {} of {planned} trials present; exporting those",
            records.len()
        );
    }
    let out = a.out.clone().unwrap_or_else(|| dir.join("ioh"));
    brdf_experiment::input_file::check_out_dir(&out)
        .map_err(|e| input_error(format!("--out {}: {e}", out.display())))?;
    let done = match a.format {
        ExportFormat::Ioh => {
            brdf_analysis::export::export_ioh(&spec, &records, &out).map_err(|e| match e {
                brdf_analysis::export::ExportError::NameClash { .. } => input_error(e.to_string()),
                other => anyhow::Error::new(other),
            })?
        }
    };
    if done.unevaluated > 0 {
        note!(
            "note: {} runs never evaluated a point; written with y = {:e} (JSON has no infinity)",
            done.unevaluated,
            f64::MAX
        );
    }
    let runs: usize = done.runs.values().sum();
    say!(
        "wrote {runs} runs of {} (configuration, instance) pairs in IOHprofiler format to {} ({} files)",
        done.runs.len(),
        out.display(),
        done.files.len()
    );
    Ok(())
}
