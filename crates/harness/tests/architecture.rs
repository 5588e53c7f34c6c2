//! The library's module graph: leaf modules import nothing of the crate, and no two modules
//! import each other, directly or through others (read from the sources' `crate::` paths).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Modules that hold plain shared types and must stay leaves.
const LEAVES: [&str; 4] = ["best_known_record", "trial_key", "duration", "choice"];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The Rust files of top-level module `name` (`name.rs` or everything under `name/`).
fn files_of(name: &str) -> Vec<PathBuf> {
    let file = src().join(format!("{name}.rs"));
    if file.is_file() {
        return vec![file];
    }
    let mut out = Vec::new();
    let mut stack = vec![src().join(name)];
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        for e in entries {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out
}

/// The library's top-level modules, from `pub mod` / `mod` lines of lib.rs.
fn modules() -> Vec<String> {
    std::fs::read_to_string(src().join("lib.rs"))
        .unwrap()
        .lines()
        .filter_map(|l| {
            let l = l.trim();
            let rest = l
                .strip_prefix("pub mod ")
                .or_else(|| l.strip_prefix("mod "))?;
            Some(rest.strip_suffix(';')?.trim().to_string())
        })
        .collect()
}

/// The other top-level modules `name`'s code (not its comments) refers to as `crate::X`.
fn imports(name: &str, all: &BTreeSet<String>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for f in files_of(name) {
        for line in std::fs::read_to_string(&f).unwrap().lines() {
            let code = line.split("//").next().unwrap_or("");
            for (i, _) in code.match_indices("crate::") {
                if i > 0 && code[..i].ends_with('$') {
                    continue;
                }
                let rest = &code[i + "crate::".len()..];
                assert!(
                    !rest.starts_with('{'),
                    "{}: write `use crate::module::...` one module a line (this test reads them)",
                    f.display()
                );
                let m: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if m != name && all.contains(&m) {
                    out.insert(m);
                }
            }
        }
    }
    out
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let all: BTreeSet<String> = modules().into_iter().collect();
    all.iter().map(|m| (m.clone(), imports(m, &all))).collect()
}

#[test]
fn leaf_modules_import_nothing_of_the_crate() {
    let g = graph();
    for leaf in LEAVES {
        let deps = g.get(leaf).unwrap_or_else(|| panic!("no module `{leaf}`"));
        assert!(deps.is_empty(), "`{leaf}` imports {deps:?}");
    }
}

#[test]
fn the_module_graph_has_no_cycles() {
    let g = graph();
    // Depth-first search; a module met again while still on the path closes a cycle.
    fn visit<'a>(
        m: &'a str,
        g: &'a BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<&'a str>,
        done: &mut BTreeSet<&'a str>,
    ) {
        if let Some(at) = path.iter().position(|p| *p == m) {
            panic!("import cycle: {} -> {m}", path[at..].join(" -> "));
        }
        if !done.insert(m) {
            return;
        }
        path.push(m);
        for d in &g[m] {
            visit(d, g, path, done);
        }
        path.pop();
    }
    let mut done = BTreeSet::new();
    for m in g.keys() {
        visit(m, &g, &mut Vec::new(), &mut done);
    }
}
