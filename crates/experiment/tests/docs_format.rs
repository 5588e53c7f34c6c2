//! Keeps docs/experiment-format.md true: every `toml` block on the page must be a spec that the
//! harness's own reader accepts, and each key table (marked `<!-- keys: ID -->`) must list
//! exactly the keys the reader accepts in that table. The accepted keys are read from the
//! reader's unknown-key error, which lists them ("unknown field `x`, expected one of ..."), so
//! a key added to or removed from the code without the page, or the other way round, fails
//! here. The `[[algorithm]]` keys the harness reads itself (`label`, `descent`, `sweep`) are
//! not listed by any error; for them the test checks that each documented key is accepted and
//! is not also a parameter of some algorithm.
//!
//! Only the public API is used (`brdf_experiment::spec::Spec::parse`), so the test does not
//! depend on how the spec module is organised inside.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use brdf_experiment::spec::Spec;

const DOC: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../docs/experiment-format.md"
);
const DOC_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs");
const PROBE: &str = "zz_not_a_key";
const KINDS: [&str; 8] = ["aed", "aers", "rpls", "ds", "sa", "sals", "avg", "asa"];

fn doc() -> String {
    std::fs::read_to_string(DOC).unwrap_or_else(|e| panic!("reading {DOC}: {e}"))
}

fn parse(text: &str) -> Result<Spec, String> {
    Spec::parse(text, "experiment-format.md", "doc", Path::new(DOC_DIR)).map_err(|e| e.to_string())
}

/// The text of every ```toml block, with the line it starts on.
fn toml_blocks(doc: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (i, line) in doc.lines().enumerate() {
        let fence = line.trim_start().starts_with("```");
        match current.take() {
            None if line.trim_start().starts_with("```toml") => {
                current = Some((i + 1, String::new()))
            }
            None => {}
            Some(block) if fence => out.push(block),
            Some((start, mut text)) => {
                text.push_str(line);
                text.push('\n');
                current = Some((start, text));
            }
        }
    }
    assert!(current.is_none(), "an unclosed ```toml block");
    out
}

/// The first column of the table after each `<!-- keys: ID -->` marker, by ID.
fn key_tables(doc: &str) -> BTreeMap<String, BTreeSet<String>> {
    let mut out = BTreeMap::new();
    let mut lines = doc.lines().peekable();
    while let Some(line) = lines.next() {
        let Some(id) = line
            .trim()
            .strip_prefix("<!-- keys:")
            .and_then(|r| r.strip_suffix("-->"))
        else {
            continue;
        };
        let id = id.trim().to_string();
        let mut keys = BTreeSet::new();
        // The table starts at the next line that begins with '|' and ends at the first that
        // does not; rows whose first cell is `key` are keys.
        while lines.peek().is_some_and(|l| !l.starts_with('|')) {
            lines.next();
        }
        while let Some(row) = lines.next_if(|l| l.starts_with('|')) {
            let first = row
                .trim_start_matches('|')
                .split('|')
                .next()
                .unwrap_or("")
                .trim();
            if let Some(key) = first.strip_prefix('`').and_then(|k| k.strip_suffix('`')) {
                assert!(
                    keys.insert(key.to_string()),
                    "table `{id}` lists `{key}` twice"
                );
            }
        }
        assert!(
            !keys.is_empty(),
            "the table after `<!-- keys: {id} -->` lists no keys"
        );
        assert!(
            out.insert(id.clone(), keys).is_none(),
            "two tables marked `{id}`"
        );
    }
    out
}

/// A minimal valid spec with `extra` lines added to the named sections (`top`, `budget`,
/// `instance`, `synthetic` or `file`, `model`, `algorithm`, `plots`, `stats`).
fn spec_with(kind: &str, file: bool, extra: &[(&str, &str)]) -> String {
    let at = |section: &str| -> String {
        extra
            .iter()
            .filter(|(s, _)| *s == section)
            .map(|(_, l)| format!("{l}\n"))
            .collect()
    };
    let source = if file {
        format!("[instance.file]\npath = \"x.csv\"\n{}", at("file"))
    } else {
        format!(
            "[instance.synthetic]\nparams = \"tuning\"\n{}",
            at("synthetic")
        )
    };
    format!(
        "seed = 1\ntrials = 1\n{}\
         [budget]\ncpu_seconds = 1.0\n{}\
         [[instance]]\nname = \"i\"\ntargets = [0.1]\n{}\
         {source}\
         [instance.model]\n{}\
         [[algorithm]]\nkind = \"{kind}\"\n{}\
         [plots]\n{}\
         [stats]\n{}",
        at("top"),
        at("budget"),
        at("instance"),
        at("model"),
        at("algorithm"),
        at("plots"),
        at("stats"),
    )
}

/// The keys the reader accepts where `spec` puts the unknown key [`PROBE`], read from its
/// error message.
fn accepted(what: &str, spec: &str) -> BTreeSet<String> {
    let message = match parse(spec) {
        Ok(_) => panic!("{what}: a spec with the unknown key `{PROBE}` was accepted:\n{spec}"),
        Err(m) => m,
    };
    let needle = format!("unknown field `{PROBE}`");
    let rest = message
        .split_once(&needle)
        .unwrap_or_else(|| panic!("{what}: no unknown-field error for `{PROBE}`: {message}"))
        .1;
    let rest = rest.lines().next().unwrap_or("");
    let listed = rest
        .split_once("expected")
        .unwrap_or_else(|| panic!("{what}: the error lists no accepted keys: {message}"))
        .1;
    listed
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// Each documented table's ID and the keys the reader accepts there.
fn code_tables() -> BTreeMap<String, BTreeSet<String>> {
    let probe = format!("{PROBE} = 1");
    let p = probe.as_str();
    let mut out = BTreeMap::new();
    for (id, section, file) in [
        ("top", "top", false),
        ("budget", "budget", false),
        ("instance", "instance", false),
        ("instance.synthetic", "synthetic", false),
        ("instance.file", "file", true),
        ("instance.model", "model", false),
        ("plots", "plots", false),
        ("stats", "stats", false),
    ] {
        let spec = spec_with("aed", file, &[(section, p)]);
        out.insert(id.to_string(), accepted(id, &spec));
    }
    // The suite tables: an `[instance.suite]` and a top-level `[[suite]]` with the probe.
    let head = "seed = 1\ntrials = 1\n[budget]\ncpu_seconds = 1.0\n";
    let tail = "[[algorithm]]\nkind = \"aed\"\n";
    let instance_suite = format!(
        "{head}[[instance]]\nname = \"i\"\ntargets = [0.1]\n[instance.suite]\n\
         suite = \"ngan-ward\"\nmaterial = \"steel\"\n{probe}\n{tail}"
    );
    out.insert(
        "instance.suite".to_string(),
        accepted("instance.suite", &instance_suite),
    );
    let suite = format!("{head}[[suite]]\nsuite = \"ngan-ward\"\ntargets = [0.1]\n{probe}\n{tail}");
    out.insert("suite".to_string(), accepted("suite", &suite));
    for kind in KINDS {
        let id = format!("algorithm.{kind}");
        let spec = spec_with(kind, false, &[("algorithm", p)]);
        out.insert(id.clone(), accepted(&id, &spec));
    }
    let range = format!("[algorithm.sweep]\nphi = {{ from = 1, to = 2, steps = 2, {probe} }}");
    out.insert(
        "algorithm.sweep-range".into(),
        accepted(
            "sweep range",
            &spec_with("aed", false, &[("algorithm", &range)]),
        ),
    );
    out
}

#[test]
fn every_toml_block_is_a_valid_spec() {
    let blocks = toml_blocks(&doc());
    assert!(
        blocks.len() >= 3,
        "expected the page's examples, found {} toml blocks",
        blocks.len()
    );
    for (line, text) in blocks {
        if let Err(e) = parse(&text) {
            panic!(
                "docs/experiment-format.md, the toml block at line {line} does not validate: {e}"
            );
        }
    }
}

#[test]
fn key_tables_list_exactly_the_accepted_keys() {
    let documented = key_tables(&doc());
    let code = code_tables();
    let mut problems = Vec::new();
    for (id, keys) in &code {
        match documented.get(id) {
            None => problems.push(format!(
                "no table marked `<!-- keys: {id} -->` (keys {keys:?})"
            )),
            Some(doc_keys) => {
                let missing: Vec<_> = keys.difference(doc_keys).collect();
                let extra: Vec<_> = doc_keys.difference(keys).collect();
                if !missing.is_empty() {
                    problems.push(format!("`{id}`: accepted but not documented: {missing:?}"));
                }
                if !extra.is_empty() {
                    problems.push(format!("`{id}`: documented but not accepted: {extra:?}"));
                }
            }
        }
    }
    for id in documented.keys() {
        if !code.contains_key(id) && id != "algorithm" {
            problems.push(format!(
                "a table marked `{id}`, which the test does not know"
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "docs/experiment-format.md:\n{}",
        problems.join("\n")
    );
}

#[test]
fn nested_annealing_tables_take_the_sa_keys() {
    let documented = key_tables(&doc());
    let sa = &documented["algorithm.sa"];
    let probe = format!("{{ {PROBE} = 1 }}");
    for (kind, key) in [("sals", "first"), ("sals", "later"), ("avg", "sa")] {
        let line = format!("{key} = {probe}");
        let spec = spec_with(kind, false, &[("algorithm", &line)]);
        assert_eq!(
            &accepted(&format!("{kind}.{key}"), &spec),
            sa,
            "{kind}.{key}"
        );
    }
}

#[test]
fn the_harness_own_algorithm_keys_are_accepted() {
    let documented = key_tables(&doc());
    let common = documented
        .get("algorithm")
        .expect("a table marked `<!-- keys: algorithm -->`");
    assert!(
        common.contains("kind"),
        "`kind` is missing from the [[algorithm]] table"
    );
    let code = code_tables();
    for key in common {
        for kind in KINDS {
            assert!(
                !code[&format!("algorithm.{kind}")].contains(key),
                "`{key}` is documented as the harness's own key but is a parameter of `{kind}`"
            );
        }
        if key == "kind" {
            continue;
        }
        // A value of the wrong type may be refused, but never as an unknown key.
        let line = format!("{key} = \"zz\"");
        let spec = spec_with("aed", false, &[("algorithm", &line)]);
        if let Err(m) = parse(&spec) {
            assert!(
                !m.contains(&format!("unknown field `{key}`")),
                "`{key}` is documented but refused as unknown: {m}"
            );
        }
    }
}
