//! Tuning with irace: the `[tune]` table, irace's files, elites parsing and the validation spec
//! (the command line's `trial` and `tune` are tested in crates/harness/tests/tune.rs).

use std::path::Path;

use brdf_experiment::spec::Spec;
use brdf_experiment::spec::tune::{CostKind, ParamType};
use brdf_tune::irace::{self, parse_elites};
use brdf_tune::validation::{TuningSource, validation_spec};

/// A tiny tuning spec: 400-sample instances, AED, evaluation cutoffs (deterministic costs).
const TINY_TUNE: &str = include_str!("data/tiny-tune.toml");

/// What irace 3.5 prints at the end of a run (trimmed).
const IRACE_TAIL: &str = include_str!("data/irace-tail.out");

fn spec() -> Spec {
    Spec::parse(TINY_TUNE, "tiny-tune.toml", "tiny-tune", Path::new(".")).unwrap()
}

fn parse_err(text: &str) -> String {
    Spec::parse(text, "t.toml", "t", Path::new("."))
        .unwrap_err()
        .to_string()
}

#[test]
fn tune_table_is_validated() {
    let s = spec();
    let t = s.tune.as_ref().expect("[tune] parsed");
    assert_eq!(t.algorithm, "AED");
    assert_eq!(t.train, ["s3", "s4"]);
    assert_eq!(t.cost.kind, CostKind::Evaluations);
    assert_eq!((t.cost.cutoff, t.cost.penalty), (400000.0, 10.0));
    assert_eq!(t.parameters[1].kind, ParamType::Int);
    assert!(t.parameters[1].log);
    // A spec without [tune] has none, and [tune] does not change the fingerprint.
    let cut = TINY_TUNE.find("[tune]").unwrap();
    let end = TINY_TUNE.find("[[instance]]").unwrap();
    let without = format!("{}{}", &TINY_TUNE[..cut], &TINY_TUNE[end..]);
    let w = Spec::parse(&without, "t.toml", "t", Path::new(".")).unwrap();
    assert!(w.tune.is_none());
    assert_eq!(w.fingerprint(), s.fingerprint());

    for (from, to, expect) in [
        ("name = \"phi\"", "name = \"psi\"", "not a parameter of aed"),
        (
            "test = [\"s5\"]",
            "test = [\"s4\"]",
            "also a training instance",
        ),
        (
            "test = [\"s5\"]",
            "test = [\"s9\"]",
            "no instance named `s9`",
        ),
        (
            "condition = \"phi > 1.2\"",
            "condition = \"psi > 1.2\"",
            "refers to `psi`",
        ),
        ("range = [10, 80]", "range = [10.5, 80]", "needs integers"),
        ("range = [1.1, 2.0]", "range = [0.5, 2.0]", "`phi` must be"),
        ("range = [1.1, 2.0]", "range = [2.0, 1.1]", "low < high"),
        ("budget = 120", "budget = 0", "tune.budget"),
        (
            "cutoff = 400000",
            "cutoff = -1",
            "cutoff must be a positive",
        ),
        (
            "type = \"real\"\nrange = [1.1, 2.0]",
            "type = \"int\"\nrange = [1, 2]",
            "not an integer field",
        ),
        ("seed = 2", "seeds = 2", "unknown field `seeds`"),
    ] {
        assert!(TINY_TUNE.contains(from), "{from}");
        let e = parse_err(&TINY_TUNE.replacen(from, to, 1));
        assert!(e.contains(expect), "{from} -> {to}: {e}");
    }
    // Without a cutoff, [budget] gives it for evaluations; for time it is missing.
    let no_cut = TINY_TUNE.replace("cutoff = 400000\n", "");
    let t = Spec::parse(&no_cut, "t.toml", "t", Path::new("."))
        .unwrap()
        .tune
        .unwrap();
    assert_eq!(t.cost.cutoff, 400000.0);
    let e = parse_err(&no_cut.replace("cost = \"evaluations\"", "cost = \"time\""));
    assert!(e.contains("`tune.cutoff` is needed"), "{e}");
}

#[test]
fn irace_files() {
    let s = spec();
    let t = s.tune.as_ref().unwrap();
    let params = irace::parameter_file(t);
    let lines: Vec<&str> = params.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), 2);
    assert!(lines[0].starts_with("phi ") && lines[0].contains("\"--phi \" r"));
    assert!(lines[0].ends_with("(1.1, 2)"), "{}", lines[0]);
    assert!(lines[1].contains("\"--rho0 \" i,log"), "{}", lines[1]);
    assert!(lines[1].ends_with("(10, 80) | phi > 1.2"), "{}", lines[1]);
    assert_eq!(irace::instance_file(t), "s3\ns4\n");
    let sc = irace::scenario_file(t, Path::new("/x/irace"), 2);
    for want in [
        "parameterFile = \"/x/irace/parameters.txt\"",
        "trainInstancesDir = \"\"",
        "trainInstancesFile = \"/x/irace/instances.txt\"",
        "targetRunner = \"/x/irace/target-runner\"",
        "maxExperiments = 120",
        "seed = 2",
        "parallel = 2",
    ] {
        assert!(sc.contains(want), "{want} in\n{sc}");
    }
    let runner = irace::target_runner(Path::new("/b/brdf-sls"), Path::new("/s/it's.toml"));
    assert!(runner.starts_with("#!/bin/sh\n"));
    assert!(runner.contains("exec '/b/brdf-sls' trial --spec '/s/it'\\''s.toml' \"$@\""));
}

#[test]
fn elites_and_validation_spec() {
    let s = spec();
    let t = s.tune.as_ref().unwrap();
    let elites = parse_elites(IRACE_TAIL, t).unwrap();
    assert_eq!(elites.len(), 2);
    assert_eq!(elites[0].id, 14);
    assert_eq!(
        elites[0].values,
        vec![
            ("phi".to_string(), toml::Value::Float(1.523)),
            ("rho0".to_string(), toml::Value::Integer(33))
        ]
    );
    // The conditional rho0 is off in the second elite.
    assert_eq!(elites[1].values.len(), 1);
    assert!(
        parse_elites("# Elitist race\n", t)
            .unwrap_err()
            .contains("did irace finish")
    );
    let bad = IRACE_TAIL.replace("--rho0 33", "--psi 33");
    assert!(
        parse_elites(&bad, t)
            .unwrap_err()
            .contains("not a tuned parameter")
    );

    let text = validation_spec(
        TINY_TUNE,
        &TuningSource::of(&s, &t.algorithm).unwrap(),
        t,
        &elites,
        "tiny-tune-validation",
    )
    .unwrap();
    let v = Spec::parse(&text, "v.toml", "v", Path::new(".")).unwrap();
    assert!(v.tune.is_none());
    assert_eq!(v.instance_names(), ["s5"]);
    assert_eq!(v.trials, 4);
    assert_eq!(
        v.config_labels(),
        ["AED default", "AED irace-1", "AED irace-2"]
    );
    let a = v.configurations[1]
        .algorithm
        .downcast_ref::<sls::AedConfig>();
    assert_eq!(a.map(|a| (a.phi, a.rho0)), Some((1.523, 33)));
    let a = v.configurations[2]
        .algorithm
        .downcast_ref::<sls::AedConfig>();
    assert_eq!(a.map(|a| (a.phi, a.rho0)), Some((1.1, 25)));
    assert!(text.contains("irace configuration 14"));
}
