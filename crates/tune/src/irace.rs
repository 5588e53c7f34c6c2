//! irace's side of tuning: the parameter file, the instance list, the scenario, the
//! target-runner script, finding the `irace` command, and reading irace's output (its
//! progress lines, the elite configurations and their parameter switches).
//!
//! Every path written into the scenario is absolute, so irace may be started from any
//! directory. The target-runner is a two-line shell script that calls `brdf-sls trial` with
//! the spec; irace appends `<config-id> <instance-id> <seed> <instance> <switches...>`.

use std::path::{Path, PathBuf};

use brdf_experiment::spec::tune::{ParamType, TuneParameter, TuneSpec, toml_value};

/// File names inside the irace directory.
pub const PARAMETER_FILE: &str = "parameters.txt";
/// The training instance list.
pub const INSTANCE_FILE: &str = "instances.txt";
/// irace's scenario.
pub const SCENARIO_FILE: &str = "scenario.txt";
/// The target-runner script.
pub const TARGET_RUNNER: &str = "target-runner";
/// irace's log (an R data file; `irace::read_logfile` reads it).
pub const LOG_FILE: &str = "irace.Rdata";
/// irace's standard output, kept for [`parse_elites`] and for the record.
pub const OUTPUT_FILE: &str = "irace.out";

/// The heading irace prints before the final elites as command lines.
pub const ELITES_HEADING: &str = "# Best configurations as commandlines";

/// Formats a number for irace (integers without a decimal point).
fn num(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

/// irace's letter for a parameter type.
pub fn type_letter(kind: ParamType) -> &'static str {
    match kind {
        ParamType::Int => "i",
        ParamType::Real => "r",
        ParamType::Categorical => "c",
        ParamType::Ordinal => "o",
    }
}

/// The switch irace puts before a parameter's value (`--phi `).
pub fn switch(p: &TuneParameter) -> String {
    format!("--{} ", p.name)
}

/// One line of irace's parameter file: `name "--name " type (range) | condition`.
pub fn parameter_line(p: &TuneParameter) -> String {
    let kind = if p.log && p.kind.is_numeric() {
        format!("{},log", type_letter(p.kind))
    } else {
        type_letter(p.kind).to_string()
    };
    let domain = match (p.kind, p.range) {
        (ParamType::Int | ParamType::Real, Some([lo, hi])) => format!("({}, {})", num(lo), num(hi)),
        _ => format!(
            "({})",
            p.values
                .iter()
                .map(|v| format!("\"{v}\""))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut line = format!("{:<20} \"{}\" {:<6} {}", p.name, switch(p), kind, domain);
    if let Some(c) = &p.condition {
        line.push_str(&format!(" | {c}"));
    }
    line
}

/// irace's parameter file.
pub fn parameter_file(t: &TuneSpec) -> String {
    let mut s = String::from(
        "# Written by brdf-sls tune. name, switch, type (i/r/c/o, ,log), range or values, | condition\n",
    );
    for p in &t.parameters {
        s.push_str(&parameter_line(p));
        s.push('\n');
    }
    s
}

/// The training instance list: one instance name per line (irace hands the name to the
/// target-runner, which looks it up in the spec).
pub fn instance_file(t: &TuneSpec) -> String {
    let mut s = String::new();
    for name in &t.train {
        s.push_str(name);
        s.push('\n');
    }
    s
}

/// Quotes a string for R (double quotes, backslashes and quotes escaped).
fn r_string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// irace's scenario file for the files in `dir` (absolute), running `parallel` trials at once.
pub fn scenario_file(t: &TuneSpec, dir: &Path, parallel: usize) -> String {
    let p = |f: &str| r_string(&dir.join(f).display().to_string());
    format!(
        "## Written by brdf-sls tune.\n\
         parameterFile = {}\n\
         trainInstancesDir = \"\"\n\
         trainInstancesFile = {}\n\
         targetRunner = {}\n\
         execDir = {}\n\
         logFile = {}\n\
         maxExperiments = {}\n\
         seed = {}\n\
         parallel = {}\n\
         deterministic = 0\n\
         digits = 4\n",
        p(PARAMETER_FILE),
        p(INSTANCE_FILE),
        p(TARGET_RUNNER),
        r_string(&dir.display().to_string()),
        p(LOG_FILE),
        t.budget,
        t.seed,
        parallel,
    )
}

/// Quotes a string for a POSIX shell.
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// The target-runner: calls `binary trial --spec SPEC` with irace's arguments appended.
pub fn target_runner(binary: &Path, spec: &Path) -> String {
    format!(
        "#!/bin/sh\n\
         # Written by brdf-sls tune. irace calls: <config-id> <instance-id> <seed> <instance> \
         <switches...>\n\
         # and reads one number, the cost, from standard output.\n\
         exec {} trial --spec {} \"$@\"\n",
        shell_quote(&binary.display().to_string()),
        shell_quote(&spec.display().to_string()),
    )
}

/// How to start irace.
#[derive(Clone, Debug, PartialEq)]
pub struct IraceCommand {
    /// The program.
    pub program: PathBuf,
    /// Arguments before irace's own (for `Rscript -e irace::irace.cmdline()`).
    pub prefix: Vec<String>,
}

impl IraceCommand {
    /// A printable form.
    pub fn display(&self) -> String {
        let mut parts = vec![shell_quote(&self.program.display().to_string())];
        parts.extend(self.prefix.iter().map(|a| shell_quote(a)));
        parts.join(" ")
    }
}

fn executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt as _;
    p.metadata()
        .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

fn on_path(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|path| {
        std::env::split_paths(&path)
            .map(|d| d.join(name))
            .find(|p| executable(p))
    })
}

/// Finds irace: `$IRACE` (a path), then `irace` on the `PATH`, then the package's `bin/irace`
/// as R reports it (`system.file("bin", "irace", package = "irace")`), then the usual site
/// libraries, then `Rscript -e 'irace::irace.cmdline()'` when R has the package. `None` when
/// irace is not installed (see `scripts/install-irace.sh`).
pub fn find_irace() -> Option<IraceCommand> {
    let plain = |program: PathBuf| IraceCommand {
        program,
        prefix: vec![],
    };
    if let Some(p) = std::env::var_os("IRACE").map(PathBuf::from)
        && executable(&p)
    {
        return Some(plain(p));
    }
    if let Some(p) = on_path("irace") {
        return Some(plain(p));
    }
    let rscript = on_path("Rscript")?;
    let reported = std::process::Command::new(&rscript)
        .args(["-e", "cat(system.file('bin', 'irace', package = 'irace'))"])
        .stderr(std::process::Stdio::null())
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
        .filter(|p| !p.as_os_str().is_empty());
    let candidates = reported.into_iter().chain(
        [
            "/usr/lib/R/site-library/irace/bin/irace",
            "/usr/local/lib/R/site-library/irace/bin/irace",
            "/usr/lib/R/library/irace/bin/irace",
        ]
        .map(PathBuf::from),
    );
    for c in candidates {
        if executable(&c) {
            return Some(plain(c));
        }
    }
    let has_package = std::process::Command::new(&rscript)
        .args([
            "-e",
            "quit(status = if (requireNamespace('irace', quietly = TRUE)) 0 else 1)",
        ])
        .stderr(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    has_package.then(|| IraceCommand {
        program: rscript,
        prefix: vec![
            "-e".into(),
            "irace::irace.cmdline()".into(),
            "--args".into(),
        ],
    })
}

/// irace's lines worth showing without `--verbose`: iteration starts and budget left.
pub fn is_progress(line: &str) -> bool {
    (line.starts_with("# ") && line.contains("Iteration ") && line.contains(" of "))
        || line.starts_with("# remainingBudget:")
}

/// Parses irace's switches (`--phi 1.3 --rho0 25`) into `(name, value)` pairs.
pub fn parse_switches(args: &[String]) -> Result<Vec<(String, toml::Value)>, String> {
    let mut out: Vec<(String, toml::Value)> = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let Some(name) = a.strip_prefix("--").filter(|n| !n.is_empty()) else {
            return Err(format!(
                "`{a}`: expected a parameter switch `--NAME VALUE` (irace's bound argument is \
                 not supported: leave capping off)"
            ));
        };
        let (name, value) = match name.split_once('=') {
            Some((n, v)) => (n.to_string(), v.to_string()),
            None => match it.next() {
                Some(v) => (name.to_string(), v.clone()),
                None => return Err(format!("`{a}`: missing value")),
            },
        };
        if out.iter().any(|(n, _)| *n == name) {
            return Err(format!("`--{name}` given twice"));
        }
        out.push((name, toml_value(&value)));
    }
    Ok(out)
}

/// One elite configuration from irace's output.
#[derive(Clone, Debug, PartialEq)]
pub struct Elite {
    /// irace's configuration id.
    pub id: u64,
    /// The parameter values irace set (conditional parameters that are off are absent).
    pub values: Vec<(String, toml::Value)>,
}

/// Reads the final elites (best first) from irace's standard output: the block after
/// [`ELITES_HEADING`], one `ID --name value ...` line each. Errors say what is missing (e.g.
/// irace stopped before finishing).
pub fn parse_elites(output: &str, t: &TuneSpec) -> Result<Vec<Elite>, String> {
    let Some(start) = output.rfind(ELITES_HEADING) else {
        return Err(format!(
            "irace's output has no `{ELITES_HEADING}` block (did irace finish?)"
        ));
    };
    let mut elites = Vec::new();
    for line in output[start..].lines().skip(1) {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            break;
        }
        let mut words = line.split_whitespace();
        let id_word = words.next().unwrap_or_default();
        let id: u64 = id_word
            .parse()
            .map_err(|_| format!("elite line `{line}`: `{id_word}` is not a configuration id"))?;
        let rest: Vec<String> = words.map(str::to_string).collect();
        let values = parse_switches(&rest).map_err(|e| format!("elite line `{line}`: {e}"))?;
        for (name, _) in &values {
            if !t.parameters.iter().any(|p| &p.name == name) {
                return Err(format!(
                    "elite line `{line}`: `{name}` is not a tuned parameter"
                ));
            }
        }
        elites.push(Elite { id, values });
    }
    if elites.is_empty() {
        return Err(format!("irace's `{ELITES_HEADING}` block is empty"));
    }
    Ok(elites)
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_experiment::spec::tune::with_values;
    use sls::AlgorithmConfig;

    #[test]
    fn switches_and_values() {
        let args: Vec<String> = ["--phi", "1.3", "--rho0", "25", "--on_failure=restart"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let v = parse_switches(&args).unwrap();
        assert_eq!(v[0], ("phi".into(), toml::Value::Float(1.3)));
        assert_eq!(v[1], ("rho0".into(), toml::Value::Integer(25)));
        assert_eq!(v[2].1, toml::Value::String("restart".into()));
        assert!(parse_switches(&["--phi".to_string()]).is_err());
        assert!(parse_switches(&["12.5".to_string()]).is_err());
        let twice: Vec<String> = ["--phi", "1", "--phi", "2"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert!(parse_switches(&twice).is_err());
        let base = AlgorithmConfig::default_for("aed").unwrap();
        let c = with_values(&base, &v[..2]).unwrap();
        let a = c.downcast_ref::<sls::AedConfig>().expect("kind changed");
        assert_eq!((a.phi, a.rho0), (1.3, 25));
        // An integer for a real field is accepted; a fraction for an integer field is not.
        assert!(with_values(&base, &[("phi".into(), toml::Value::Integer(2))]).is_ok());
        assert!(with_values(&base, &[("rho0".into(), toml::Value::Float(2.5))]).is_err());
        assert!(with_values(&base, &[("phi".into(), toml::Value::Float(0.5))]).is_err());
        let e = with_values(&base, &[("psi".into(), toml::Value::Float(1.5))]).unwrap_err();
        assert!(e.contains("rho0"), "{e}");
    }
}
