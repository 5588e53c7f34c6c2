//! Results folders and specs that name kinds this program cannot run: a custom Rust kind
//! (written by another program) is read as opaque settings by the commands that only read
//! results; `kind = "python"` is refused up front by the commands that run a trial in this
//! process (issue 45.20).

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

mod support;
use support::{brdf_sls, text};

use std::path::Path;

/// A results folder as a custom binary with a kind `my-search` would have written it: run
/// with RPLS under the label MINE, then the kind renamed in the stored spec.
fn custom_kind_folder(dir: &Path) {
    let spec = common::TINY.replace("trials = 4", "trials = 2").replace(
        "[[algorithm]]\nkind = \"rpls\"",
        "[[algorithm]]\nlabel = \"MINE\"\nkind = \"rpls\"",
    );
    std::fs::write(dir.join("mine.toml"), spec).unwrap();
    let o = brdf_sls(&["run", "mine.toml", "--out", "out", "--no-plots"], dir);
    assert!(o.status.success(), "{}", text(&o));
    let path = dir.join("out/trials.jsonl");
    let stored = std::fs::read_to_string(&path).unwrap();
    let renamed = stored
        .replace(r#"kind = \"rpls\""#, r#"kind = \"my-search\"\nstep = 0.5"#)
        .replace(r#""kind":"rpls""#, r#""kind":"my-search","step":0.5"#);
    assert_ne!(renamed, stored);
    // The header's fingerprint as that program computed it, from its canonical spec.
    let mut lines: Vec<String> = renamed.lines().map(str::to_string).collect();
    let mut header: serde_json::Value = serde_json::from_str(&lines[0]).unwrap();
    header["fingerprint"] = brdf_experiment::seed::fingerprint(&header["spec"].to_string()).into();
    lines[0] = header.to_string();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
}

/// The fingerprint in the results header.
fn stored_fingerprint(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("out/trials.jsonl")).unwrap();
    let header: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    header["fingerprint"].as_str().unwrap().to_string()
}

#[test]
fn results_of_a_custom_kind_are_read_without_its_program() {
    let dir = tempfile::tempdir().unwrap();
    custom_kind_folder(dir.path());
    let o = brdf_sls(&["stats", "out", "--print-only"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("MINE"), "{}", text(&o));
    // The kind's settings are read back whole: the statistics name the results' fingerprint.
    let o = brdf_sls(&["stats", "out"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(
        summary["fingerprint"],
        stored_fingerprint(dir.path()).as_str()
    );
    for args in [
        &["plot", "out"][..],
        &["report", "out"],
        &["export", "--format", "ioh", "out", "--out", "ioh"],
        &["compare", "out", "out"],
    ] {
        let o = brdf_sls(args, dir.path());
        assert!(o.status.success(), "{args:?}: {}", text(&o));
    }
    assert!(
        std::fs::read_to_string(dir.path().join("out/report.html"))
            .unwrap()
            .contains("MINE")
    );
    // A spec that names the kind is still refused where it would run: it needs its program.
    let spec = std::fs::read_to_string(dir.path().join("mine.toml"))
        .unwrap()
        .replace("kind = \"rpls\"", "kind = \"my-search\"");
    std::fs::write(dir.path().join("theirs.toml"), spec).unwrap();
    let o = brdf_sls(&["check", "theirs.toml"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("unknown `kind` `my-search`"),
        "{}",
        text(&o)
    );
}

#[test]
fn trial_refuses_a_python_configuration_up_front() {
    let dir = tempfile::tempdir().unwrap();
    let spec = common::TINY.replace(
        "[[algorithm]]\nkind = \"rpls\"",
        "[[algorithm]]\nlabel = \"PY\"\nkind = \"python\"\nentry = \"m:f\"",
    );
    std::fs::write(dir.path().join("py.toml"), spec).unwrap();
    let o = brdf_sls(
        &[
            "trial", "--spec", "py.toml", "--config", "PY", "1", "1", "7", "tuning",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("configuration `PY` is of kind `python`, which `brdf-sls trial` cannot run"),
        "{t}"
    );
}
