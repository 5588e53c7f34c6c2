//! Helpers several commands share: loading a spec, the default output folder, loading a data
//! set under the common data policy, and the RMSE of given parameters.

use std::path::{Path, PathBuf};

use anyhow::Result;
use brdf_experiment::spec::Spec;
use brdf_model::{DataSet, Evaluator, FilterReport, Params};

use super::{input_error, note};
use crate::cli::DataArgs;

/// The suite a spec argument names (`suite:NAME`), if it does.
fn suite_name(path: &Path) -> Option<&str> {
    path.to_str()?
        .strip_prefix(brdf_experiment::spec::SUITE_PREFIX)
}

/// Reads and validates a spec file, or builds a suite's built-in experiment for `suite:NAME`
/// (an unknown name is an error listing the suites).
pub fn load_spec(path: &Path) -> Result<Spec> {
    match suite_name(path) {
        Some(name) => Ok(Spec::suite_experiment(name)?),
        None => Ok(Spec::from_file(path)?),
    }
}

/// `runs/<spec file stem>/`, `runs/suite-NAME/` for `suite:NAME`, or `runs/default/` for the
/// built-in experiment.
pub fn default_out(spec: Option<&Path>) -> PathBuf {
    let stem = match spec.and_then(suite_name) {
        Some(name) => format!("suite-{name}"),
        None => spec
            .and_then(|p| p.file_stem())
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "default".into()),
    };
    PathBuf::from(brdf_experiment::DEFAULT_RUNS_DIR).join(stem)
}

/// Loads the data set the flags name, under the shared data policy (see [`DataArgs`]), and
/// reports what the filters dropped on standard error.
pub fn load_data(args: &DataArgs) -> Result<(DataSet, FilterReport)> {
    let (data, rep) = brdf_fit::load_data(&args.file_spec())?;
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

/// RMSE of `params` on `data`, through the evaluator with a layout of as many lobes as
/// `params` has, each of the family's fullest kind (an isotropic lobe is the anisotropic one
/// with its pairs tied, pan 0), so every field of `params` is used as given.
pub fn params_rmse(params: &Params, data: &DataSet) -> Result<f64> {
    let layout = brdf_model::Layout::of_params(params)?;
    let x = layout.encode(params);
    Ok(Evaluator::new(&layout).rmse(&x, &layout.prepare(data)))
}

/// The spec a results folder was last run with (`brdf_analysis::report::stored_spec`): a
/// stored text that no longer parses is that spec's error; a folder without one is an input
/// error whose message starts with `what` (the flag or folder the user named) and says what is
/// unknown.
pub fn stored_spec(
    contents: &brdf_experiment::store::Contents,
    dir: &Path,
    what: &str,
    unknown: &str,
) -> Result<Spec> {
    match brdf_analysis::report::stored_spec(contents, dir) {
        Ok(spec) => Ok(spec),
        Err(brdf_analysis::report::StoredSpecError::Spec(e)) => Err(e.into()),
        Err(brdf_analysis::report::StoredSpecError::NoSpecText(_)) => Err(super::input_error(
            format!("{what}: the header holds no spec text, so {unknown} unknown"),
        )),
    }
}

/// Refuses, before anything runs, a configuration this program cannot run in its own process
/// (`kind = "python"`: its trials run only in worker processes of `brdf-sls run`, or from
/// Python): `command` runs one trial here.
pub fn refuse_unrunnable(
    config: &brdf_experiment::spec::Configuration,
    command: &str,
) -> Result<()> {
    if config.algorithm.can_run() {
        return Ok(());
    }
    Err(input_error(format!(
        "configuration `{}` is of kind `{}`, which `{command}` cannot run: it runs each trial \
         in this process, and algorithms of that kind run only in `brdf-sls run` (in worker \
         processes of the Python package, shards and `slurm` included) or from Python \
         (`brdf_sls.fit`, `brdf_sls.run`)",
        config.label,
        config.algorithm.kind_name()
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_out_names_suites_and_files() {
        let runs = PathBuf::from(brdf_experiment::DEFAULT_RUNS_DIR);
        let out = |p: &str| default_out(Some(Path::new(p)));
        assert_eq!(out("suite:ngan-ward"), runs.join("suite-ngan-ward"));
        assert_eq!(out("experiments/fig16.toml"), runs.join("fig16"));
        assert_eq!(default_out(None), runs.join("default"));
    }
}
