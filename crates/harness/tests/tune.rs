//! The command line's side of tuning: `brdf-sls trial` (irace's target-runner) and `brdf-sls
//! tune` (irace's files, a dry run, elites from irace's output, a tiny tuning). Only the last
//! test needs irace; it says why it is skipped when irace is missing.

use std::path::Path;
use std::process::Command;

use brdf_experiment::spec::Spec;
use brdf_tune::irace;

/// A tiny tuning spec: 400-sample instances, AED, evaluation cutoffs (deterministic costs).
const TINY_TUNE: &str = include_str!("../../tune/tests/data/tiny-tune.toml");

/// What irace 3.5 prints at the end of a run (trimmed).
const IRACE_TAIL: &str = include_str!("../../tune/tests/data/irace-tail.out");

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
}

fn write_spec(dir: &Path) -> std::path::PathBuf {
    let p = dir.join("tiny-tune.toml");
    std::fs::write(&p, TINY_TUNE).unwrap();
    p
}

#[test]
fn trial_prints_one_cost_and_par10() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write_spec(dir.path());
    let run = |extra: &[&str]| {
        let o = bin()
            .arg("trial")
            .arg("--spec")
            .arg(&spec)
            .args(extra)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, out, err) = run(&["7", "1", "123", "s3", "--phi", "1.3", "--rho0", "20"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out.lines().count(), 1, "{out}");
    let cost: f64 = out.trim().parse().unwrap();
    assert!(cost > 0.0 && cost <= 400000.0, "{cost}");
    // Deterministic in the seed with an evaluation cutoff.
    assert_eq!(
        run(&["7", "1", "123", "s3", "--phi", "1.3", "--rho0", "20"]).1,
        out
    );
    // A cutoff no run can meet: censored, cost 10 x cutoff.
    let (code, out, _) = run(&["--cutoff", "50", "1", "1", "1", "s3"]);
    assert_eq!(code, Some(0));
    assert_eq!(out.trim().parse::<f64>().unwrap(), 500.0);
    let (_, out, _) = run(&["--cutoff", "50", "--penalty", "3", "1", "1", "1", "s3"]);
    assert_eq!(out.trim().parse::<f64>().unwrap(), 150.0);
    // The best RMSE at a budget.
    let (code, out, err) = run(&["--cost", "rmse", "--cutoff", "0.05", "1", "1", "1", "s3"]);
    assert_eq!(code, Some(0), "{err}");
    let rmse: f64 = out.trim().parse().unwrap();
    assert!(rmse > 0.05 && rmse < 1.0, "{rmse}");
    // Bad values: a clear message and status 2.
    for (args, expect) in [
        (&["1", "1", "1", "s3", "--phi", "0.5"][..], "`phi` must be"),
        (
            &["1", "1", "1", "s3", "--psi", "2"][..],
            "not a parameter of aed",
        ),
        (&["1", "1", "1", "nope"][..], "no instance named `nope`"),
        (&["1", "1", "1", "s3", "--phi"][..], "missing value"),
        (&["1", "1", "1", "s3", "100", "--phi", "2"][..], "capping"),
        (&["--cutoff=-1", "1", "1", "1", "s3"][..], "cutoff"),
    ] {
        let (code, out, err) = run(args);
        assert_eq!(code, Some(2), "{args:?}: {out} {err}");
        assert!(out.is_empty(), "{args:?}: {out}");
        assert!(err.contains(expect), "{args:?}: {err}");
    }
}

#[test]
fn tune_dry_run_and_from_output() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write_spec(dir.path());
    let out = dir.path().join("out");
    let o = bin()
        .arg("tune")
        .arg(&spec)
        .arg("--out")
        .arg(&out)
        .arg("--dry-run")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("--scenario"));
    for f in [
        "parameters.txt",
        "instances.txt",
        "scenario.txt",
        "target-runner",
    ] {
        assert!(out.join("irace").join(f).is_file(), "{f}");
    }
    // The target-runner works as irace calls it.
    let r = Command::new(out.join("irace/target-runner"))
        .args(["3", "1", "42", "s4", "--phi", "1.5", "--rho0", "30"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(
        String::from_utf8_lossy(&r.stdout)
            .trim()
            .parse::<f64>()
            .is_ok()
    );

    let sample = dir.path().join("irace.out");
    std::fs::write(&sample, IRACE_TAIL).unwrap();
    let o = bin()
        .arg("tune")
        .arg(&spec)
        .arg("--out")
        .arg(&out)
        .arg("--from-output")
        .arg(&sample)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let vspec = out.join("tiny-tune-validation.toml");
    let csv = std::fs::read_to_string(out.join("elites.csv")).unwrap();
    assert_eq!(csv.lines().next(), Some("rank,label,irace_id,phi,rho0"));
    assert!(csv.contains("2,AED irace-2,3,1.1,NA"), "{csv}");
    let c = bin().arg("check").arg(&vspec).output().unwrap();
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));

    // No [tune] table: status 2.
    let plain = dir.path().join("plain.toml");
    let cut = TINY_TUNE.find("[tune]").unwrap();
    let end = TINY_TUNE.find("[[instance]]").unwrap();
    std::fs::write(
        &plain,
        format!("{}{}", &TINY_TUNE[..cut], &TINY_TUNE[end..]),
    )
    .unwrap();
    let o = bin()
        .arg("tune")
        .arg(&plain)
        .arg("--dry-run")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no [tune] table"));
}

#[test]
fn tiny_tuning_with_irace() {
    let Some(cmd) = irace::find_irace() else {
        eprintln!(
            "skipped: irace not found ($IRACE, PATH, R's irace package); scripts/install-irace.sh \
             installs it"
        );
        return;
    };
    eprintln!("irace: {}", cmd.display());
    let dir = tempfile::tempdir().unwrap();
    let spec = write_spec(dir.path());
    let out = dir.path().join("out");
    let o = bin()
        .arg("tune")
        .arg(&spec)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.join("elites.csv").is_file());
    let vspec = out.join("tiny-tune-validation.toml");
    let v = Spec::from_file(&vspec).unwrap();
    assert_eq!(v.config_labels()[0], "AED default");
    assert!(v.config_labels().len() >= 2);
}
