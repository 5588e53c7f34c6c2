//! Fuzzing results folders: results files are input too. Mutations of committed results
//! (header timestamps and labels, times and other numbers set to extremes such as 1e305,
//! subnormals, negatives and u64::MAX, hostile strings, lines dropped or duplicated, bytes
//! flipped, torn tails), written plain or packed (gzip), must be read, analysed and rendered
//! (statistics, the report page, a comparison with the original) or refused with an error:
//! never a panic or a hang. `cargo test` runs a few dozen cases; `scripts/fuzz-long.sh` runs
//! many more (PROPTEST_CASES).

use std::io::Write;
use std::path::Path;

use brdf_analysis::compare::{Options, compare, entries};
use brdf_analysis::folder::Folder;
use proptest::prelude::*;

/// Extreme numbers put where the results hold numbers.
const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1e305",
    "1e300",
    "-1e300",
    "5e-324",
    "1e12",
    "18446744073709551615",
    "4294967296",
    "0.5",
];

/// Hostile strings put where the results hold strings (labels, keys, hashes, spec text).
fn strings() -> Vec<String> {
    vec![
        String::new(),
        "L".repeat(70_000),
        "\u{1b}[2J<script>alert(1)</script>".into(),
        "a/b/c".into(),
        "\u{202e}evil".into(),
    ]
}

/// The committed results the mutations start from (small ones: the cases stay fast).
fn seeds() -> Vec<Vec<String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../results");
    ["fig13-sals-trace", "default"]
        .iter()
        .map(|name| {
            let file = std::fs::File::open(root.join(name).join("trials.jsonl.gz")).unwrap();
            let mut text = String::new();
            std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(file), &mut text)
                .unwrap();
            text.lines().map(String::from).collect()
        })
        .collect()
}

/// The leaves of `v` that are numbers (`numbers`) or strings, as JSON pointers.
fn leaves(v: &serde_json::Value, at: String, numbers: bool, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, c) in m {
                leaves(
                    c,
                    format!("{at}/{}", k.replace('~', "~0").replace('/', "~1")),
                    numbers,
                    out,
                );
            }
        }
        serde_json::Value::Array(a) => {
            for (i, c) in a.iter().enumerate() {
                leaves(c, format!("{at}/{i}"), numbers, out);
            }
        }
        serde_json::Value::Number(_) if numbers => out.push(at),
        serde_json::Value::String(_) if !numbers => out.push(at),
        _ => {}
    }
}

/// Applies mutation `kind` to line `at` (both reduced modulo what there is).
fn mutate(lines: &mut Vec<String>, kind: u8, at: usize, pick: usize) {
    if lines.is_empty() {
        return;
    }
    let i = at % lines.len();
    match kind % 6 {
        k @ (0 | 1) => {
            let Ok(mut v) = serde_json::from_str::<serde_json::Value>(&lines[i]) else {
                return;
            };
            let mut found = Vec::new();
            leaves(&v, String::new(), k == 0, &mut found);
            if found.is_empty() {
                return;
            }
            let ptr = &found[pick % found.len()];
            let new = if k == 0 {
                serde_json::from_str(NUMBERS[pick % NUMBERS.len()]).unwrap()
            } else {
                let s = strings();
                serde_json::Value::String(s[pick % s.len()].clone())
            };
            if let Some(slot) = v.pointer_mut(ptr) {
                *slot = new;
            }
            lines[i] = v.to_string();
        }
        2 => {
            lines.remove(i);
        }
        3 => {
            let copy = lines[i].clone();
            lines.insert(i, copy);
        }
        4 => {
            let mut bytes = lines[i].clone().into_bytes();
            if !bytes.is_empty() {
                let j = pick % bytes.len();
                bytes[j] = (at % 128) as u8;
            }
            lines[i] = String::from_utf8_lossy(&bytes).into_owned();
        }
        _ => {
            // A torn tail: the last line cut short.
            let last = lines.len() - 1;
            let cut = pick % (lines[last].len() + 1);
            let mut keep = cut.min(lines[last].len());
            while !lines[last].is_char_boundary(keep) {
                keep -= 1;
            }
            lines[last].truncate(keep);
        }
    }
}

/// Reads, analyses and renders `dir`; any error is fine, a panic is not.
fn exercise(dir: &Path, original: &Folder) {
    let Ok(folder) = Folder::read(dir) else {
        return;
    };
    let analysis = folder.analysis();
    let _ = brdf_analysis::html::report_page_of(&[(&folder, &analysis)], dir);
    let out = dir.join("stats");
    let _ = brdf_analysis::report::write_report(
        &folder.spec,
        &folder.contents.records,
        &folder.contents.sessions,
        &out,
        false,
    );
    let (ea, eb) = (
        entries(original, &original.statistics()),
        entries(&folder, &folder.statistics()),
    );
    let c = compare(&ea, &eb, Options::default());
    let _ = brdf_analysis::compare::table(&c);
    let _ = brdf_analysis::html::compare_page(original, &folder, (&ea, &eb), &c);
}

/// Cases per run: `PROPTEST_CASES` when set (scripts/fuzz-long.sh), else 24.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(24)
}

static EXECUTIONS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

proptest! {
    // A case that hangs (an axis whose ticks never end, say) fails after 60 s.
    #![proptest_config(ProptestConfig { cases: cases(), timeout: 60_000, ..ProptestConfig::default() })]

    #[test]
    fn mutated_results_are_read_and_rendered_or_refused_cleanly(
        which in 0usize..2,
        packed in any::<bool>(),
        muts in prop::collection::vec((0u8..6, 0usize..10_000, 0usize..100_000), 1..4),
    ) {
        let done = EXECUTIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if u64::from(cases()) == done {
            println!("FUZZ results: {done} executions");
        }
        let tmp = tempfile::tempdir().unwrap();
        let mut lines = seeds().swap_remove(which);
        let original_dir = tmp.path().join("original");
        std::fs::create_dir(&original_dir).unwrap();
        std::fs::write(original_dir.join("trials.jsonl"), lines.join("\n") + "\n").unwrap();
        let original = Folder::read(&original_dir).unwrap();
        for (kind, at, pick) in muts {
            mutate(&mut lines, kind, at, pick);
        }
        let text = lines.join("\n") + "\n";
        let dir = tmp.path().join("mutated");
        std::fs::create_dir(&dir).unwrap();
        if packed {
            let mut gz = flate2::write::GzEncoder::new(
                std::fs::File::create(dir.join("trials.jsonl.gz")).unwrap(),
                flate2::Compression::fast(),
            );
            gz.write_all(text.as_bytes()).unwrap();
            gz.finish().unwrap();
        } else {
            std::fs::write(dir.join("trials.jsonl"), text).unwrap();
        }
        exercise(&dir, &original);
    }
}
