//! `brdf-sls run` of a spec with algorithms written in Python (`kind = "python"`): the command
//! line cannot call Python itself, so those configurations run in worker processes of the
//! Python package (`python -m brdf_sls worker`, [`brdf_workers`]), one per thread, while the
//! other configurations run here; or it says what to install.

use std::ffi::OsString;
use std::path::Path;
use std::process::{Command, Stdio};

use anyhow::Result;
use brdf_experiment::instance::BuiltInstance;
use brdf_experiment::spec::Spec;
use brdf_model::Kernel;
use brdf_workers::pool::{PoolError, Routed, RoutedError, WorkerCommand};

use super::input_error;

/// The environment variable naming the interpreter (default `python3` on the `PATH`).
const PYTHON_VAR: &str = "BRDF_SLS_PYTHON";

/// Whether the spec has an algorithm of `kind = "python"` (read with the kind's schema,
/// which [`super::dispatch`] registers).
pub fn uses_python(spec: &Spec) -> bool {
    spec.configurations
        .iter()
        .any(|c| c.algorithm.kind_name() == brdf_experiment::python_kind::KIND)
}

/// The executor of a run: every configuration in this process, except those of `kind =
/// "python"`, which run in worker processes of `$BRDF_SLS_PYTHON -m brdf_sls worker`. Fails
/// with what to install when that interpreter cannot import `brdf_sls`.
pub fn executor(
    spec: &Spec,
    origin: Option<&Path>,
    built: &[BuiltInstance],
    kernel: Kernel,
) -> Result<Routed> {
    let python = std::env::var_os(PYTHON_VAR).unwrap_or_else(|| OsString::from("python3"));
    if uses_python(spec) {
        check_python(&python, origin)?;
    }
    let origin = origin.map_or_else(|| "<built-in default>".into(), |p| p.display().to_string());
    let command = || WorkerCommand {
        program: python.clone(),
        args: ["-m", "brdf_sls", "worker"].map(OsString::from).to_vec(),
        env: Vec::new(),
    };
    let is_python = |c: &brdf_experiment::spec::Configuration| {
        c.algorithm.kind_name() == brdf_experiment::python_kind::KIND
    };
    Routed::new(spec, built, kernel, is_python, command, &origin).map_err(|e| match e {
        RoutedError::Instance(e) => anyhow::Error::new(e).context("building the instances"),
        RoutedError::Pool(PoolError::Refused(message)) => input_error(message),
        RoutedError::Pool(e) => anyhow::Error::new(e).context("starting the Python workers"),
    })
}

/// Fails with what to install when `python` cannot import `brdf_sls`.
fn check_python(python: &OsString, spec: Option<&Path>) -> Result<()> {
    let check = Command::new(python)
        .args(["-c", "import brdf_sls"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output();
    let reason = match check {
        Ok(out) if out.status.success() => return Ok(()),
        Ok(out) => String::from_utf8_lossy(&out.stderr)
            .lines()
            .last()
            .unwrap_or("import failed")
            .trim()
            .to_string(),
        Err(e) => format!("cannot run it: {e}"),
    };
    Err(input_error(format!(
        "{}: algorithms of `kind = \"python\"` run in the brdf_sls Python package, and `{}` \
         cannot import it ({reason}). Install the package in that interpreter, e.g. from this \
         repository in a virtual environment: `pip install maturin && maturin develop \
         --release -m crates/py/Cargo.toml` (docs/python.md); or set {PYTHON_VAR} to an \
         interpreter that has it.",
        spec.map_or_else(|| "the experiment".into(), |p| p.display().to_string()),
        python.to_string_lossy(),
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_kinds_are_found_among_the_configurations() {
        brdf_experiment::python_kind::register_schema();
        let spec = |algorithms: &str| {
            let text = format!(
                "name = \"t\"\nseed = 1\ntrials = 1\n[budget]\nevaluations = 1000\n[[instance]]\nname = \"i\"\n\
                 targets = [0.1]\n[instance.synthetic]\nparams = \"tuning\"\nsamples = 50\n\
                 {algorithms}"
            );
            Spec::parse(&text, "test", "t", std::path::Path::new(".")).unwrap()
        };
        let python = "[[algorithm]]\nkind = \"aed\"\n[[algorithm]]\nkind = \"python\"\n\
                      entry = \"m:f\"\n";
        assert!(uses_python(&spec(python)));
        assert!(!uses_python(&spec("[[algorithm]]\nkind = \"aed\"\n")));
    }
}
