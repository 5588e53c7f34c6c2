//! Configuration labels of any length: new specs are held to `MAX_LABEL_CHARS`, and results
//! written before the limit (labels of 65,536 characters and more) stay readable by `stats`.

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

mod support;
use support::{brdf_sls, text};

use brdf_experiment::spec::limits::MAX_LABEL_CHARS;

/// Two trials of AED labelled `label` and of RPLS on the tiny instance.
fn spec_text(label: &str) -> String {
    common::TINY
        .replace("trials = 4", "trials = 2")
        .replace("label = \"AED\"", &format!("label = \"{label}\""))
        .replace("[algorithm.sweep]\nphi = [1.2, 1.4]\n", "")
}

#[test]
fn check_refuses_a_label_over_the_limit_naming_key_and_limit() {
    let dir = tempfile::tempdir().unwrap();
    let at_limit = "L".repeat(MAX_LABEL_CHARS);
    std::fs::write(dir.path().join("ok.toml"), spec_text(&at_limit)).unwrap();
    let o = brdf_sls(&["check", "ok.toml"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    std::fs::write(dir.path().join("long.toml"), spec_text(&"L".repeat(65_536))).unwrap();
    let o = brdf_sls(&["check", "long.toml"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("long.toml") && t.contains("`label`") && t.contains("65536 characters"),
        "{t}"
    );
    assert!(t.contains(&format!("at most {MAX_LABEL_CHARS}")), "{t}");
    assert!(
        t.len() < 1_000,
        "the error repeats the label: {} bytes",
        t.len()
    );
}

/// A folder run with a short label, then given a 70,000-character label throughout, with the
/// seeds the plan derives for it (as a run before the limit would have written it; an edited
/// label alone is refused, its trials' seeds being another plan's): `stats` reads it and
/// writes its table.
#[test]
fn stats_reads_results_with_a_label_longer_than_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("t.toml"), spec_text("SHORTLABEL")).unwrap();
    let o = brdf_sls(
        &["run", "t.toml", "--threads", "2", "--no-plots"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let results = dir.path().join("runs/t/trials.jsonl");
    let long = "L".repeat(70_000);
    let stored = std::fs::read_to_string(&results).unwrap();
    assert!(stored.contains("SHORTLABEL"));
    let mut relabelled = String::new();
    for line in stored.replace("SHORTLABEL", &long).lines() {
        let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
        if v["type"] == "trial" {
            let (instance, config) = (
                v["instance"].as_str().unwrap(),
                v["config"].as_str().unwrap(),
            );
            let trial = u32::try_from(v["trial"].as_u64().unwrap()).unwrap();
            // TINY's master seed.
            v["seed"] = brdf_experiment::seed::trial_seed(11, instance, config, trial).into();
        }
        relabelled.push_str(&format!("{v}\n"));
    }
    std::fs::write(&results, relabelled).unwrap();
    let o = brdf_sls(&["stats", "runs/t"], dir.path());
    assert!(
        o.status.success(),
        "{}",
        &text(&o)[..text(&o).len().min(2_000)]
    );
    let table = std::fs::read_to_string(dir.path().join("runs/t/table.txt")).unwrap();
    assert!(table.contains(&long) && table.contains("RPLS"));
    let tests = std::fs::read_to_string(dir.path().join("runs/t/tests.csv")).unwrap();
    assert!(tests.contains(&long));
    // `compare` pads its table's cells to the longest: it panicked from 65,536 characters.
    let o = brdf_sls(
        &["compare", "runs/t", "runs/t", "--out", "c.html"],
        dir.path(),
    );
    let t = text(&o);
    assert!(o.status.success(), "{}", &t[..t.len().min(2_000)]);
    assert!(t.contains(&long) && t.contains("RPLS"));
    // So is a data hash that long (results files are input): not comparable, and said so.
    let copy = dir.path().join("runs/u");
    std::fs::create_dir_all(&copy).unwrap();
    let stored = std::fs::read_to_string(&results).unwrap();
    let hash = "h".repeat(70_000);
    let header_end = stored.find('\n').unwrap();
    let mut header: serde_json::Value = serde_json::from_str(&stored[..header_end]).unwrap();
    header["data_hashes"]["tuning"] = hash.clone().into();
    let edited = format!("{}{}", header, &stored[header_end..]);
    std::fs::write(copy.join("trials.jsonl"), edited).unwrap();
    let o = brdf_sls(
        &["compare", "runs/t", "runs/u", "--out", "u.html"],
        dir.path(),
    );
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{}", &t[..t.len().min(2_000)]);
    assert!(t.contains("different instance data") && t.contains(&hash));
}
