//! `brdf-sls run` of a spec with algorithms written in Python (`kind = "python"`): the command
//! line cannot call Python, so it hands the run to `python -m brdf_sls run` (the Python package
//! runs the same trials with the same seeds into the same folder), or says what to install.

use std::ffi::OsString;
use std::path::Path;
use std::process::{Command, Stdio};

use anyhow::Result;

use super::input_error;
use crate::cli::RunArgs;
use brdf_experiment::spec::Spec;

/// The environment variable naming the interpreter (default `python3` on the `PATH`).
const PYTHON_VAR: &str = "BRDF_SLS_PYTHON";

/// Whether the spec has an algorithm of `kind = "python"` (read with the read-only kind that
/// [`super::dispatch`] registers: checked for form, never run here).
pub fn uses_python(spec: &Spec) -> bool {
    spec.configurations
        .iter()
        .any(|c| c.algorithm.kind_name() == brdf_experiment::python_kind::KIND)
}

/// Runs `python -m brdf_sls run` with the same flags and exits with its status, or fails with
/// what to install when the interpreter cannot import `brdf_sls`.
pub fn delegate_run(a: &RunArgs, spec: &Path) -> Result<()> {
    if a.shard.is_some() {
        return Err(input_error(format!(
            "{}: --shard is not available for specs with `kind = \"python\"` algorithms (they \
             run in the brdf_sls Python package, whose `run` has no shards)",
            spec.display()
        )));
    }
    let python = std::env::var_os(PYTHON_VAR).unwrap_or_else(|| OsString::from("python3"));
    let check = Command::new(&python)
        .args(["-c", "import brdf_sls"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output();
    let reason = match check {
        Ok(out) if out.status.success() => None,
        Ok(out) => Some(
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("import failed")
                .trim()
                .to_string(),
        ),
        Err(e) => Some(format!("cannot run it: {e}")),
    };
    if let Some(reason) = reason {
        return Err(input_error(format!(
            "{}: algorithms of `kind = \"python\"` run in the brdf_sls Python package, and `{}` \
             cannot import it ({reason}). Install the package in that interpreter, e.g. from \
             this repository in a virtual environment: `pip install maturin && maturin develop \
             --release -m crates/py/Cargo.toml` (docs/python.md); or set {PYTHON_VAR} to an \
             interpreter that has it. Then run again, or run `python -m brdf_sls run` directly.",
            spec.display(),
            python.to_string_lossy(),
        )));
    }
    let mut args: Vec<OsString> = vec!["-m".into(), "brdf_sls".into(), "run".into()];
    args.push(spec.into());
    if let Some(out) = &a.out {
        args.extend(["--out".into(), out.into()]);
    }
    if let Some(n) = a.threads {
        args.extend(["--threads".into(), n.to_string().into()]);
    }
    if a.fresh {
        args.push("--fresh".into());
    }
    if let Some(n) = a.limit {
        args.extend(["--limit".into(), n.to_string().into()]);
    }
    if a.no_plots {
        args.push("--no-plots".into());
    }
    if let Some(k) = a.kernel {
        args.extend(["--kernel".into(), k.to_string().into()]);
    }
    let status = Command::new(&python)
        .args(&args)
        .status()
        .map_err(|e| anyhow::anyhow!("running {}: {e}", python.to_string_lossy()))?;
    // The Python command printed its own messages and chose the status (0, 1, 2 or 130):
    // pass the status on without printing anything more.
    std::process::exit(status.code().unwrap_or(1));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_kinds_are_found_among_the_configurations() {
        brdf_experiment::python_kind::register_read_only();
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
