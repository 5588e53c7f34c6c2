//! Records which code the binary is built from, so that results can say which code wrote them:
//! `BRDF_SLS_GIT` is the git commit (12 hex digits), with `-modified` when the workspace's
//! sources differ from it, or `unknown` outside a git checkout (a packaged crate, a tarball).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The tracked paths whose uncommitted changes make a build `-modified` (the code, not
/// results/ or the docs).
const CODE_PATHS: [&str; 3] = ["crates", "Cargo.toml", "Cargo.lock"];

fn git(root: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(root)
        .args(args)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// The workspace root when this crate sits in it as `crates/experiment` (a checkout), else `None`
/// (a packaged crate, e.g. under `target/package/` or a registry's cache, whose parent
/// directories belong to some other project's git history, not to this code's).
fn workspace_root(manifest: &Path) -> Option<PathBuf> {
    let root = manifest.join("../..");
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    (same(&root.join("crates/experiment"), manifest) && root.join("Cargo.toml").is_file())
        .then_some(root)
}

/// `<commit>`, `<commit>-modified`, or `unknown` without a checkout or without git.
fn describe(root: Option<&Path>) -> String {
    let Some(root) = root else {
        return "unknown".to_string();
    };
    let commit = git(root, &["rev-parse", "--short=12", "HEAD"]);
    let mut status_args = vec!["status", "--porcelain", "--untracked-files=no", "--"];
    status_args.extend(CODE_PATHS);
    let modified = git(root, &status_args).map(|s| !s.is_empty());
    match (commit, modified) {
        (Some(c), Some(true)) => format!("{c}-modified"),
        (Some(c), _) => c,
        _ => "unknown".to_string(),
    }
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let root = workspace_root(&manifest);
    println!("cargo:rustc-env=BRDF_SLS_GIT={}", describe(root.as_deref()));
    let Some(root) = root else {
        // Nothing to watch: the packaged sources change only with a new package.
        println!("cargo:rerun-if-changed=build.rs");
        return;
    };
    // Run again when HEAD moves (checkout, commit) or the code changes. Only existing paths:
    // cargo reruns a build script on every build while one of its paths is missing.
    let watch = |path: PathBuf| {
        if path.exists() {
            println!("cargo:rerun-if-changed={}", path.display());
        }
    };
    if let Some(git_dir) = git(&root, &["rev-parse", "--absolute-git-dir"]) {
        let git_dir = PathBuf::from(git_dir);
        watch(git_dir.join("HEAD"));
        watch(git_dir.join("packed-refs"));
        if let Some(head_ref) = git(&root, &["symbolic-ref", "-q", "HEAD"]) {
            watch(git_dir.join(head_ref));
        }
    }
    // The workspace's crates, whole (sources, manifests, tests: what `-modified` looks at);
    // not all of crates/, whose Python crate keeps its own target/ there.
    for p in [
        "model",
        "lm",
        "sls",
        "graphics",
        "stress",
        "experiment",
        "analysis",
        "tune",
        "bench",
        "harness",
    ] {
        watch(root.join("crates").join(p));
    }
    for p in ["Cargo.toml", "Cargo.lock"] {
        watch(root.join(p));
    }
}
