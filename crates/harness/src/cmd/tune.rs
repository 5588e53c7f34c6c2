//! `brdf-sls tune`: writes irace's files for the spec's `[tune]` table, runs irace (each of
//! its trials is a `brdf-sls trial` call), reads the elites and writes a validation spec that
//! compares them with the defaults on the held-out instances.

use std::io::{BufRead as _, BufReader, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result, bail};
use brdf_experiment::spec::Spec;
use brdf_experiment::spec::tune::{MAX_BUDGET, TuneSpec};
use brdf_tune::irace::{self, Elite};
use brdf_tune::validation::{TuningSource, elite_label, validation_spec};

use super::shared::{default_out, load_spec};
use super::{bail_input, input_error, note, say};
use crate::cli::TuneArgs;

/// Writes `text` to `path` atomically, naming the file in errors.
fn write(path: &Path, text: &str) -> Result<()> {
    brdf_experiment::store::write_atomic(path, text.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}

/// An absolute form of `p` (canonical when it exists).
fn absolute(p: &Path) -> Result<PathBuf> {
    if let Ok(c) = p.canonicalize() {
        return Ok(c);
    }
    Ok(std::env::current_dir()
        .context("reading the current directory")?
        .join(p))
}

/// Writes parameters, instances, scenario and target-runner into `dir`; returns the scenario.
fn write_irace_files(
    spec_path: &Path,
    tune: &TuneSpec,
    dir: &Path,
    parallel: usize,
) -> Result<PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let dir = absolute(dir)?;
    let binary = std::env::current_exe().context("finding this program's path")?;
    write(
        &dir.join(irace::PARAMETER_FILE),
        &irace::parameter_file(tune),
    )?;
    write(&dir.join(irace::INSTANCE_FILE), &irace::instance_file(tune))?;
    let runner = dir.join(irace::TARGET_RUNNER);
    write(
        &runner,
        &irace::target_runner(&binary, &absolute(spec_path)?),
    )?;
    {
        use std::os::unix::fs::PermissionsExt as _;
        std::fs::set_permissions(&runner, std::fs::Permissions::from_mode(0o755))
            .with_context(|| format!("making {} executable", runner.display()))?;
    }
    let scenario = dir.join(irace::SCENARIO_FILE);
    write(&scenario, &irace::scenario_file(tune, &dir, parallel))?;
    Ok(scenario)
}

/// Runs irace on `scenario`, keeping its output in `dir`; returns the output.
fn run_irace(
    cmd: &irace::IraceCommand,
    scenario: &Path,
    dir: &Path,
    verbose: bool,
) -> Result<String> {
    let err_path = dir.join("irace.err");
    let err_file = std::fs::File::create(&err_path)
        .with_context(|| format!("creating {}", err_path.display()))?;
    let mut child = Command::new(&cmd.program)
        .args(&cmd.prefix)
        .arg("--scenario")
        .arg(scenario)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(err_file)
        .spawn()
        .with_context(|| format!("starting irace ({})", cmd.display()))?;
    let out_path = dir.join(irace::OUTPUT_FILE);
    let mut out_file = std::fs::File::create(&out_path)
        .with_context(|| format!("creating {}", out_path.display()))?;
    let mut output = String::new();
    if let Some(stdout) = child.stdout.take() {
        for line in BufReader::new(stdout).lines() {
            let line = line.context("reading irace's output")?;
            writeln!(out_file, "{line}")
                .with_context(|| format!("writing {}", out_path.display()))?;
            if verbose || irace::is_progress(&line) {
                note!("irace: {line}");
            }
            output.push_str(&line);
            output.push('\n');
        }
    }
    let status = child.wait().context("waiting for irace")?;
    if !status.success() {
        let err = std::fs::read_to_string(&err_path).unwrap_or_default();
        let tail: Vec<&str> = output.lines().chain(err.lines()).collect();
        let tail = tail[tail.len().saturating_sub(15)..].join("\n");
        bail!(
            "irace failed ({status}); its output is in {} and {}. Last lines:\n{tail}",
            out_path.display(),
            err_path.display()
        );
    }
    Ok(output)
}

/// Writes the elites as CSV (rank, irace id, one column per tuned parameter).
fn elites_csv(tune: &TuneSpec, elites: &[Elite]) -> String {
    let mut s = String::from("rank,label,irace_id");
    for p in &tune.parameters {
        s.push(',');
        s.push_str(&p.name);
    }
    s.push('\n');
    for (i, e) in elites.iter().enumerate() {
        s.push_str(&format!(
            "{},{},{}",
            i + 1,
            brdf_analysis::stats::csv_field(&elite_label(&tune.algorithm, i + 1)),
            e.id
        ));
        for p in &tune.parameters {
            let v = e
                .values
                .iter()
                .find(|(n, _)| *n == p.name)
                .map(|(_, v)| match v {
                    toml::Value::String(s) => s.clone(),
                    other => other.to_string(),
                })
                .unwrap_or_else(|| "NA".into());
            s.push(',');
            s.push_str(&v);
        }
        s.push('\n');
    }
    s
}

/// `brdf-sls tune`.
pub fn tune(a: TuneArgs) -> Result<()> {
    let spec = load_spec(&a.spec)?;
    let Some(mut tune) = spec.tune.clone() else {
        bail_input!(
            "{}: no [tune] table (see docs/tuning.md for its keys)",
            a.spec.display()
        );
    };
    if let Some(c) = spec
        .configurations
        .iter()
        .find(|c| c.label == tune.algorithm || c.algorithm_label == tune.algorithm)
    {
        super::shared::refuse_unrunnable(c, "brdf-sls tune")?;
    }
    if let Some(b) = a.budget {
        if !(1..=MAX_BUDGET).contains(&b) {
            bail_input!("--budget {b}: expected 1 to {MAX_BUDGET} experiments");
        }
        tune.budget = b;
    }
    let parallel = a
        .parallel
        .or(tune.parallel)
        .or(spec.threads)
        .unwrap_or_else(brdf_experiment::run::default_threads);
    if parallel == 0 {
        return Err(input_error("--parallel must be at least 1"));
    }
    let out = a.out.clone().unwrap_or_else(|| default_out(Some(&a.spec)));
    let dir = out.join("irace");
    let scenario = write_irace_files(&a.spec, &tune, &dir, parallel)?;
    let dir = absolute(&dir)?;
    note!(
        "tuning `{}` of {}: {} parameter(s) on {} training instance(s), {} experiments, cost {} \
         (cutoff {} {}, PAR{}), {} in parallel",
        tune.algorithm,
        spec.name,
        tune.parameters.len(),
        tune.train.len(),
        tune.budget,
        tune.cost.kind.name(),
        tune.cost.cutoff,
        tune.cost.kind.cutoff_unit(),
        tune.cost.penalty,
        parallel
    );
    note!("irace files: {}", dir.display());
    let output = if let Some(path) = &a.from_output {
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?
    } else {
        let cmd = irace::find_irace();
        if a.dry_run {
            let shown = cmd.map_or_else(|| "irace".to_string(), |c| c.display());
            say!(
                "{shown} --scenario {}",
                irace::shell_quote(&scenario.display().to_string())
            );
            return Ok(());
        }
        let Some(cmd) = cmd else {
            bail!(
                "irace not found (looked at $IRACE, the PATH, R's irace package); install it with \
                 scripts/install-irace.sh (Debian's r-cran-irace) or set IRACE=/path/to/irace"
            );
        };
        note!(
            "running {} --scenario {}",
            cmd.display(),
            scenario.display()
        );
        run_irace(&cmd, &scenario, &dir, a.verbose)?
    };
    let elites = irace::parse_elites(&output, &tune)
        .map_err(|e| anyhow::anyhow!("reading irace's elites: {e}"))?;
    write(&out.join("elites.csv"), &elites_csv(&tune, &elites))?;
    let name = format!("{}-validation", spec.name);
    let source = TuningSource::of(&spec, &tune.algorithm).ok_or_else(|| {
        anyhow::anyhow!(
            "writing the validation spec: no configuration labelled `{}`",
            tune.algorithm
        )
    })?;
    let text = validation_spec(&spec.text, &source, &tune, &elites, &name)
        .map_err(|e| anyhow::anyhow!("writing the validation spec: {e}"))?;
    let stem = a
        .spec
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "tune".into());
    let vpath = out.join(format!("{stem}-validation.toml"));
    Spec::parse(&text, &vpath.display().to_string(), &name, &out)
        .context("the validation spec written from irace's elites does not validate")?;
    write(&vpath, &text)?;
    say!("irace's elites (best first; irace id: values):");
    for (i, e) in elites.iter().enumerate() {
        let v: Vec<String> = e.values.iter().map(|(n, v)| format!("{n}={v}")).collect();
        say!("  {}. {}: {}", i + 1, e.id, v.join(" "));
    }
    say!("wrote {}", out.join("elites.csv").display());
    say!(
        "wrote {} (validate: brdf-sls run {})",
        vpath.display(),
        vpath.display()
    );
    Ok(())
}
