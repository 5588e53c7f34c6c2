//! The workspace's architecture, read from the sources and manifests of every crate under
//! `crates/` (the Python package's included):
//!
//! - No file-level import circle in any crate: a file refers to another through a path
//!   `crate::a::b::Item`, `super::Item` or `self::a::Item` (in `use` or in code, braced use
//!   trees expanded), resolved to the file that defines the module it names; no file may be
//!   referred to back, directly or through others. `mod x;` declarations are not imports, and
//!   neither are a module's plain paths into its own children (`child::Item`): those are its
//!   structure. Circles still being removed are listed in [`ALLOWED_CIRCLES`].
//! - Crate dependencies flow one way, down the [`LAYERS`]: a crate's `[dependencies]` name
//!   only crates of lower layers.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::{Path, PathBuf};

/// File-level circles that stay for now, each as the set of files it joins (relative to the
/// workspace root). An entry that no longer matches a circle exactly fails the test: remove it.
const ALLOWED_CIRCLES: &[&[&str]] = &[];

/// Files that hold plain shared types and import nothing of their crate.
const LEAVES: &[&str] = &[
    "crates/experiment/src/best_known_record.rs",
    "crates/experiment/src/trial_key.rs",
    "crates/experiment/src/duration.rs",
    "crates/experiment/src/choice.rs",
    "crates/experiment/src/terminal.rs",
];

/// The workspace's crates (package names) in layers, lowest first: a crate depends only on
/// crates of lower layers.
const LAYERS: &[&[&str]] = &[
    &["brdf-simd"],
    &["brdf-model", "bounded-lm"],
    &["brdf-io"],
    &["sls", "brdf-graphics", "brdf-stress", "brdf-published"],
    &["brdf-experiment"],
    &["brdf-stats", "brdf-best-known"],
    &[
        "brdf-analysis",
        "brdf-tune",
        "brdf-fit",
        "brdf-workers",
        "brdf-merge",
    ],
    &["brdf-bench"],
    &["harness", "brdf-sls-py"],
];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every crate directory under `crates/` (a directory with a `Cargo.toml`), sorted.
fn crate_dirs() -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(workspace().join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("Cargo.toml").is_file())
        .collect();
    dirs.sort();
    assert!(dirs.len() >= 8, "too few crates found: {dirs:?}");
    dirs
}

/// `path` relative to the workspace root, with `/` separators (for messages and the lists).
fn relative(path: &Path) -> String {
    let root = workspace().canonicalize().unwrap();
    let path = path.canonicalize().unwrap();
    let rel = path.strip_prefix(&root).unwrap();
    rel.components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

// ---------------------------------------------------------------------------------------------
// Reading Rust sources.

/// `src` with comments, string and character literals blanked (newlines kept): only code.
fn code_of(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let n = c.len();
    let mut out = String::with_capacity(src.len());
    let blank = |out: &mut String, range: std::ops::Range<usize>| {
        for &ch in &c[range.start.min(n)..range.end.min(n)] {
            out.push(if ch == '\n' { '\n' } else { ' ' });
        }
    };
    let mut i = 0;
    while i < n {
        let ch = c[i];
        let next = c.get(i + 1).copied();
        let after_ident = i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_');
        if ch == '/' && next == Some('/') {
            let end = (i..n).find(|&j| c[j] == '\n').unwrap_or(n);
            blank(&mut out, i..end);
            i = end;
        } else if ch == '/' && next == Some('*') {
            // Block comments nest.
            let (mut j, mut depth) = (i, 0);
            while j < n {
                if c[j] == '/' && c.get(j + 1) == Some(&'*') {
                    depth += 1;
                    j += 2;
                } else if c[j] == '*' && c.get(j + 1) == Some(&'/') {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            blank(&mut out, i..j);
            i = j;
        } else if !after_ident && (ch == 'r' || (ch == 'b' && next == Some('r'))) && {
            let mut j = i + if ch == 'b' { 2 } else { 1 };
            while c.get(j) == Some(&'#') {
                j += 1;
            }
            c.get(j) == Some(&'"')
        } {
            // A raw string: r"..", r#".."#, br"..".
            let mut j = i + if ch == 'b' { 2 } else { 1 };
            let mut hashes = 0;
            while c[j] == '#' {
                hashes += 1;
                j += 1;
            }
            j += 1;
            while j < n && !(c[j] == '"' && (1..=hashes).all(|k| c.get(j + k) == Some(&'#'))) {
                j += 1;
            }
            let end = j + 1 + hashes;
            blank(&mut out, i..end);
            i = end;
        } else if ch == '"' {
            let mut j = i + 1;
            while j < n && c[j] != '"' {
                j += if c[j] == '\\' { 2 } else { 1 };
            }
            blank(&mut out, i..j + 1);
            i = j + 1;
        } else if ch == '\'' && next == Some('\\') {
            // An escaped character literal: '\n', '\'', '\u{..}'.
            let mut j = i + 3;
            while j < n && c[j] != '\'' {
                j += 1;
            }
            blank(&mut out, i..j + 1);
            i = j + 1;
        } else if ch == '\'' && c.get(i + 2) == Some(&'\'') {
            blank(&mut out, i..i + 3);
            i += 3;
        } else {
            // Code, including lifetimes ('a).
            out.push(ch);
            i += 1;
        }
    }
    out
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    /// `::`
    Sep,
    Punct(char),
}

fn tokens(code: &str) -> Vec<Tok> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        if ch.is_whitespace() {
            i += 1;
        } else if ch.is_alphanumeric() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(Tok::Ident(c[start..i].iter().collect()));
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            out.push(Tok::Sep);
            i += 2;
        } else {
            out.push(Tok::Punct(ch));
            i += 1;
        }
    }
    out
}

fn is_ident(t: Option<&Tok>, name: &str) -> bool {
    matches!(t, Some(Tok::Ident(s)) if s == name)
}

/// Reads the path or use tree starting at `k` (its first segment an identifier) onto `prefix`,
/// pushes every whole path it names to `out` and returns the index after it.
fn path_tree(t: &[Tok], mut k: usize, mut path: Vec<String>, out: &mut Vec<Vec<String>>) -> usize {
    let in_braces = !path.is_empty();
    loop {
        match t.get(k) {
            // `self` inside braces names the prefix itself.
            Some(Tok::Ident(s)) if s == "self" && in_braces => k += 1,
            Some(Tok::Ident(s)) => {
                path.push(s.clone());
                k += 1;
            }
            Some(Tok::Punct('*')) => {
                k += 1;
                break;
            }
            _ => break,
        }
        if t.get(k) != Some(&Tok::Sep) {
            break;
        }
        k += 1;
        if t.get(k) == Some(&Tok::Punct('{')) {
            k += 1;
            loop {
                match t.get(k) {
                    None => return k,
                    Some(Tok::Punct('}')) => return k + 1,
                    Some(Tok::Punct(',')) => k += 1,
                    Some(Tok::Ident(_)) | Some(Tok::Punct('*')) => {
                        k = path_tree(t, k, path.clone(), out);
                    }
                    // Not a use tree after all: skip to the closing brace.
                    Some(_) => {
                        let mut depth = 1;
                        while depth > 0 && k < t.len() {
                            match t[k] {
                                Tok::Punct('{') => depth += 1,
                                Tok::Punct('}') => depth -= 1,
                                _ => {}
                            }
                            k += 1;
                        }
                        return k;
                    }
                }
            }
        }
    }
    if is_ident(t.get(k), "as") {
        k += 2;
    }
    out.push(path);
    k
}

/// The module path of a source file from its place under `src/` (`a/mod.rs` and `a.rs` are
/// `a`; the crate root `lib.rs` or `main.rs` is the empty path).
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.strip_suffix(".rs").unwrap();
    if !(parts.is_empty() && (stem == "lib" || stem == "main")) && stem != "mod" {
        parts.push(stem.to_string());
    }
    parts
}

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())) {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// A crate's file-level import graph: for each file (relative to the workspace), the files it
/// refers to, each with the first path that does.
type Graph = BTreeMap<String, BTreeMap<String, String>>;

fn import_graph(crate_dir: &Path) -> Graph {
    let src = crate_dir.join("src");
    let mut files = rust_files(&src);
    // A binary next to a library is a crate of its own; it must then be one file.
    if src.join("lib.rs").is_file() {
        let main = src.join("main.rs");
        if main.is_file() {
            let code = code_of(&std::fs::read_to_string(&main).unwrap());
            let t = tokens(&code);
            let declares = t.windows(3).any(|w| {
                is_ident(Some(&w[0]), "mod")
                    && matches!(w[1], Tok::Ident(_))
                    && w[2] == Tok::Punct(';')
            });
            assert!(
                !declares,
                "{}: a binary beside lib.rs declares modules",
                main.display()
            );
            files.retain(|f| *f != main);
        }
    }
    // Modules (file modules and the inline `mod x { .. }` ones) -> the file that holds them,
    // and each file's paths as (module the path is written in, path).
    let mut modules: BTreeMap<Vec<String>, String> = BTreeMap::new();
    let mut uses: Vec<(String, Vec<String>, Vec<String>)> = Vec::new();
    for f in &files {
        let name = relative(f);
        let file_module = module_of(&src, f);
        modules.insert(file_module.clone(), name.clone());
        let code = code_of(&std::fs::read_to_string(f).unwrap());
        let t = tokens(&code);
        let mut depth = 0usize;
        let mut inline: Vec<(String, usize)> = Vec::new();
        let mut pending: Option<String> = None;
        let mut k = 0;
        while k < t.len() {
            let current = |inline: &[(String, usize)]| {
                let mut m = file_module.clone();
                m.extend(inline.iter().map(|(n, _)| n.clone()));
                m
            };
            match &t[k] {
                Tok::Punct('{') => {
                    depth += 1;
                    if let Some(name_) = pending.take() {
                        inline.push((name_, depth));
                        modules.insert(current(&inline), name.clone());
                    }
                    k += 1;
                }
                Tok::Punct('}') => {
                    if inline.last().is_some_and(|(_, d)| *d == depth) {
                        inline.pop();
                    }
                    depth = depth.saturating_sub(1);
                    k += 1;
                }
                Tok::Ident(s) if s == "mod" => {
                    if let (Some(Tok::Ident(m)), Some(Tok::Punct('{'))) =
                        (t.get(k + 1), t.get(k + 2))
                    {
                        pending = Some(m.clone());
                    }
                    k += 1;
                }
                Tok::Ident(s)
                    if (s == "crate" || s == "super" || s == "self")
                        && t.get(k + 1) == Some(&Tok::Sep)
                        && !(k > 0 && matches!(t[k - 1], Tok::Sep | Tok::Punct('$'))) =>
                {
                    let mut paths = Vec::new();
                    k = path_tree(&t, k, Vec::new(), &mut paths);
                    let here = current(&inline);
                    for p in paths {
                        uses.push((name.clone(), here.clone(), p));
                    }
                }
                _ => k += 1,
            }
        }
    }
    let mut graph: Graph = files
        .iter()
        .map(|f| (relative(f), BTreeMap::new()))
        .collect();
    for (from, here, path) in uses {
        let (mut abs, rest) = match path[0].as_str() {
            "crate" => (Vec::new(), &path[1..]),
            "self" => (here.clone(), &path[1..]),
            _ => {
                let supers = path.iter().take_while(|s| *s == "super").count();
                let mut base = here.clone();
                for _ in 0..supers {
                    base.pop();
                }
                (base, &path[supers..])
            }
        };
        abs.extend(rest.iter().cloned());
        let to = (0..=abs.len())
            .rev()
            .find_map(|len| modules.get(&abs[..len]))
            .unwrap_or_else(|| panic!("{from}: cannot resolve `{}`", path.join("::")));
        if *to != from {
            graph
                .get_mut(&from)
                .unwrap()
                .entry(to.clone())
                .or_insert_with(|| path.join("::"));
        }
    }
    graph
}

/// The strongly connected sets of more than one file: the circles.
fn circles(graph: &Graph) -> Vec<BTreeSet<String>> {
    let reach = |from: &str| -> BTreeSet<String> {
        let mut seen = BTreeSet::new();
        let mut queue = VecDeque::from([from.to_string()]);
        while let Some(f) = queue.pop_front() {
            for to in graph[&f].keys() {
                if seen.insert(to.clone()) {
                    queue.push_back(to.clone());
                }
            }
        }
        seen
    };
    let reaches: BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|f| (f, reach(f))).collect();
    let mut out: Vec<BTreeSet<String>> = Vec::new();
    for (f, r) in &reaches {
        if !r.contains(*f) || out.iter().any(|c| c.contains(*f)) {
            continue;
        }
        let set: BTreeSet<String> = r
            .iter()
            .filter(|g| reaches[*g].contains(*f))
            .cloned()
            .collect();
        out.push(set);
    }
    out
}

/// One circle through the first file of `set`, with the path behind each step.
fn describe(graph: &Graph, set: &BTreeSet<String>) -> String {
    let start = set.iter().next().unwrap();
    // Breadth-first from `start` inside the set, back to `start`.
    let mut prev: BTreeMap<String, String> = BTreeMap::new();
    let mut queue = VecDeque::from([start.clone()]);
    'search: while let Some(f) = queue.pop_front() {
        for to in graph[&f].keys().filter(|t| set.contains(*t)) {
            if to == start {
                prev.insert(format!("{start}#end"), f.clone());
                break 'search;
            }
            if !prev.contains_key(to) {
                prev.insert(to.clone(), f.clone());
                queue.push_back(to.clone());
            }
        }
    }
    let mut chain = vec![start.clone()];
    let mut at = prev[&format!("{start}#end")].clone();
    while at != *start {
        chain.push(at.clone());
        at = prev[&at].clone();
    }
    chain.push(start.clone());
    chain.reverse();
    let steps: Vec<String> = chain
        .windows(2)
        .map(|w| format!("  {} -> {} (`{}`)", w[0], w[1], graph[&w[0]][&w[1]]))
        .collect();
    format!(
        "{}\n{}",
        set.iter().cloned().collect::<Vec<_>>().join(", "),
        steps.join("\n")
    )
}

#[test]
fn the_checker_reads_use_trees_and_paths() {
    let code = code_of(
        "use crate::{a::{b, c::D}, e as f};\n// crate::g\nlet s = \"crate::h\";\nuse super::super::{self, i::*};\nx = self::j::k(); y = $crate::l; z = 'q'; fn f<'a>() {}",
    );
    let t = tokens(&code);
    let mut paths = Vec::new();
    let mut k = 0;
    while k < t.len() {
        if matches!(&t[k], Tok::Ident(s) if s == "crate" || s == "super" || s == "self")
            && t.get(k + 1) == Some(&Tok::Sep)
            && !(k > 0 && matches!(t[k - 1], Tok::Sep | Tok::Punct('$')))
        {
            k = path_tree(&t, k, Vec::new(), &mut paths);
        } else {
            k += 1;
        }
    }
    let paths: Vec<String> = paths.iter().map(|p| p.join("::")).collect();
    assert_eq!(
        paths,
        [
            "crate::a::b",
            "crate::a::c::D",
            "crate::e",
            "super::super",
            "super::super::i",
            "self::j::k"
        ]
    );
}

#[test]
fn leaf_files_import_nothing_of_their_crate() {
    for leaf in LEAVES {
        let path = workspace().join(leaf);
        assert!(path.is_file(), "LEAVES names {leaf}, which is no file");
        let crate_dir = path
            .ancestors()
            .find(|d| d.join("Cargo.toml").is_file())
            .unwrap();
        let imports = &import_graph(crate_dir)[*leaf];
        assert!(imports.is_empty(), "{leaf} imports {imports:?}");
    }
}

#[test]
fn no_crate_has_a_file_level_import_circle() {
    let allowed: Vec<BTreeSet<String>> = ALLOWED_CIRCLES
        .iter()
        .map(|c| c.iter().map(|s| s.to_string()).collect())
        .collect();
    let mut found = Vec::new();
    let mut problems = Vec::new();
    for dir in crate_dirs() {
        let graph = import_graph(&dir);
        for set in circles(&graph) {
            if !allowed.contains(&set) {
                problems.push(format!("import circle: {}", describe(&graph, &set)));
            }
            found.push(set);
        }
    }
    for a in &allowed {
        if !found.contains(a) {
            problems.push(format!(
                "{a:?} is no longer a circle: remove it from ALLOWED_CIRCLES"
            ));
        }
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

// ---------------------------------------------------------------------------------------------
// Crate dependencies.

/// A manifest's package name and the names of its normal and build dependencies (target-
/// specific ones included; dev-dependencies not), read line by line.
fn manifest(dir: &Path) -> (String, BTreeSet<String>) {
    let text = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
    let mut section = String::new();
    let mut name = None;
    let mut deps = BTreeSet::new();
    for line in text.lines() {
        let line = line.split('#').next().unwrap().trim();
        if let Some(s) = line.strip_prefix('[') {
            section = s.trim_end_matches(']').trim().to_string();
            // `[dependencies.NAME]`
            for kind in ["dependencies.", "build-dependencies."] {
                if let Some(dep) = section
                    .split(kind)
                    .nth(1)
                    .filter(|_| !section.starts_with("dev-"))
                {
                    deps.insert(dep.trim_matches('"').to_string());
                }
            }
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        let key = key.trim();
        if section == "package" && key == "name" {
            name = Some(value.trim().trim_matches('"').to_string());
        }
        let is_deps = section == "dependencies"
            || section == "build-dependencies"
            || (section.starts_with("target.") && section.ends_with(".dependencies"));
        if is_deps {
            let dep = key.split('.').next().unwrap().trim_matches('"');
            // A renamed dependency: `alias = { package = "name", .. }`.
            let package = value
                .split("package")
                .nth(1)
                .and_then(|r| r.split('"').nth(1))
                .unwrap_or(dep);
            deps.insert(package.to_string());
        }
    }
    (name.expect("a [package] name"), deps)
}

#[test]
fn crate_dependencies_flow_down_the_layers() {
    let layer_of: BTreeMap<&str, usize> = LAYERS
        .iter()
        .enumerate()
        .flat_map(|(i, l)| l.iter().map(move |c| (*c, i)))
        .collect();
    let manifests: BTreeMap<String, BTreeSet<String>> =
        crate_dirs().iter().map(|d| manifest(d)).collect();
    let mut problems = Vec::new();
    for (name, deps) in &manifests {
        let Some(&layer) = layer_of.get(name.as_str()) else {
            problems.push(format!("crate `{name}` is in no layer: add it to LAYERS"));
            continue;
        };
        for dep in deps.iter().filter(|d| manifests.contains_key(*d)) {
            let dep_layer = layer_of.get(dep.as_str()).copied().unwrap_or(usize::MAX);
            if dep_layer >= layer {
                problems.push(format!(
                    "`{name}` (layer {layer}) depends on `{dep}` (layer {dep_layer}): \
                     dependencies go to lower layers only"
                ));
            }
        }
    }
    for name in layer_of.keys() {
        if !manifests.contains_key(*name) {
            problems.push(format!(
                "LAYERS names `{name}`, which no crate under crates/ is"
            ));
        }
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}
