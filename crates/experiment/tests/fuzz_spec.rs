//! Fuzzing the spec parser: mutations of the shipped specs (numbers replaced by extreme values,
//! lines dropped or duplicated, keys renamed, bytes flipped) must give a spec or an error,
//! never a panic, and an accepted spec's plan stays within the stated limits. `cargo test`
//! runs a few hundred cases; `scripts/fuzz-long.sh` runs many more (PROPTEST_CASES).

use std::path::Path;

use brdf_experiment::spec::{Spec, limits};
use proptest::prelude::*;

const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "1e300",
    "-1e300",
    "nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "-9223372036854775808",
    "4000000000",
    "1.5",
    "\"x\"",
    "[]",
    "{}",
    "[1, 2, 3]",
    "true",
];

fn seeds() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments");
    let mut texts: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    texts.sort();
    texts
}

/// Applies mutation `kind` at position `at` (both reduced modulo what the text offers).
fn mutate(text: &str, kind: u8, at: usize, pick: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let i = at % lines.len().max(1);
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    match kind % 5 {
        0 => {
            // Replace the value of a `key = value` line with an extreme value.
            if let Some((k, _)) = lines[i].split_once('=') {
                out[i] = format!("{k}= {}", EXTREMES[pick % EXTREMES.len()]);
            }
        }
        1 => {
            out.remove(i);
        }
        2 => out.insert(i, lines[i].to_string()),
        3 => {
            if let Some((k, v)) = lines[i].split_once('=') {
                out[i] = format!("{}x ={v}", k.trim_end());
            }
        }
        _ => {
            let mut bytes = text.as_bytes().to_vec();
            if !bytes.is_empty() {
                let j = at % bytes.len();
                bytes[j] = (pick % 128) as u8;
            }
            return String::from_utf8_lossy(&bytes).into_owned();
        }
    }
    out.join("\n")
}

/// Cases per run: `PROPTEST_CASES` when set (scripts/fuzz-long.sh), else 512.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(512)
}

static EXECUTIONS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn mutated_specs_parse_or_fail_cleanly(
        which in 0usize..64,
        muts in prop::collection::vec((0u8..5, 0usize..10_000, 0usize..1000), 1..4),
    ) {
        let done = EXECUTIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if u64::from(cases()) == done {
            println!("FUZZ spec: {done} executions");
        }
        let texts = seeds();
        let mut text = texts[which % texts.len()].clone();
        for (kind, at, pick) in muts {
            text = mutate(&text, kind, at, pick);
        }
        if let Ok(spec) = Spec::parse(&text, "fuzz.toml", "fuzz", Path::new(".")) {
            let n = spec.trials as u64
                * spec.instances.len() as u64
                * spec.configurations.len() as u64;
            prop_assert!(n <= limits::MAX_PLANNED_TRIALS);
            prop_assert!(spec.configurations.len() <= limits::MAX_CONFIGURATIONS);
            prop_assert!(spec.stats.bootstrap <= limits::MAX_BOOTSTRAP);
            // describe() and the fingerprint must not panic either.
            let _ = spec.describe(2);
            let _ = spec.fingerprint();
        }
    }
}
