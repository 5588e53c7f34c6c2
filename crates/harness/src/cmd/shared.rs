//! Helpers several commands share: loading a spec, the default output folder, loading a data
//! set under the common data policy, and the RMSE of given parameters.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use brdf_model::{BrdfParams, DataSet, Evaluator, FilterReport, LobeKind};
use harness::spec::{DataFormat, Spec};

use super::{input_error, note};
use crate::cli::DataArgs;

/// Reads and validates a spec file.
pub fn load_spec(path: &Path) -> Result<Spec> {
    Ok(Spec::from_file(path)?)
}

/// Resolves every instance's best-known RMSE and the relative targets: the values recorded in
/// `dir`'s results when they were written by this spec, else computed (seeded, see
/// `harness::best_known`). Prints a warning for each absolute target within 1% of its
/// instance's best-known RMSE.
pub fn resolve_best_known(spec: &mut Spec, dir: Option<&Path>) -> Result<()> {
    let fingerprint = spec.fingerprint();
    let known = dir
        .and_then(|d| harness::store::read_results(d).ok())
        .filter(|c| c.header.fingerprint == fingerprint)
        .map(|c| c.best_known().clone())
        .unwrap_or_default();
    let resolved =
        harness::best_known::resolve(spec, &known).context("finding the best-known RMSEs")?;
    for n in resolved.notes {
        note!("note: {n}");
    }
    for w in harness::best_known::warnings(spec) {
        note!("{w}");
    }
    Ok(())
}

/// `runs/<spec file stem>/`, or `runs/default/` for the built-in experiment.
pub fn default_out(spec: Option<&Path>) -> PathBuf {
    let stem = spec
        .and_then(|p| p.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "default".into());
    PathBuf::from(harness::DEFAULT_RUNS_DIR).join(stem)
}

/// Loads the data set the flags name, under the shared data policy (see [`DataArgs`]), and
/// reports what the filters dropped on standard error.
pub fn load_data(args: &DataArgs) -> Result<(DataSet, FilterReport)> {
    let fs = args.file_spec();
    if fs.format.is_none() && DataFormat::from_path(&args.data).is_none() {
        return Err(input_error(format!(
            "{}: cannot tell the format from the extension; pass --format cornell|csv|merl",
            args.data.display()
        )));
    }
    if !(args.wavelength.is_finite() && args.wavelength > 0.0) {
        return Err(input_error(format!(
            "--wavelength {}: expected a positive number of nm",
            args.wavelength
        )));
    }
    let (data, rep) = harness::instance::load_file(&fs, &args.data)
        .with_context(|| format!("reading {}", args.data.display()))?;
    note!(
        "{}: {} samples kept ({rep})",
        args.data.display(),
        data.len()
    );
    Ok((data, rep))
}

/// [`load_data`], refusing a data set that the filters left empty.
pub fn load_non_empty(args: &DataArgs) -> Result<(DataSet, FilterReport)> {
    let (data, rep) = load_data(args)?;
    if data.is_empty() {
        return Err(input_error(format!(
            "{}: no samples left after filtering ({rep})",
            args.data.display()
        )));
    }
    Ok((data, rep))
}

/// RMSE of `params` on `data`, through the evaluator with a layout of as many anisotropic
/// lobes as `params` has (an isotropic lobe is the anisotropic one with `cx = cy`, pan 0).
pub fn params_rmse(params: &BrdfParams, data: &DataSet) -> Result<f64> {
    let kinds: Vec<LobeKind> = vec![LobeKind::Anisotropic; params.lobes.len()];
    let layout = brdf_model::Layout::builder(&kinds).build()?;
    let x = layout.encode(params);
    Ok(Evaluator::new(&layout).rmse(&x, data))
}
