//! What the command-line tests share: running the built `brdf-sls` as a user would (CI=true,
//! so no progress bars) and reading what it printed.

// Each test file compiles this module on its own and uses part of it.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs `brdf-sls args` in `cwd`.
pub fn brdf_sls(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(args)
        .current_dir(cwd)
        .env("CI", "true")
        .output()
        .unwrap()
}

/// Standard output, then standard error, as text.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A spec whose 3 trials take milliseconds (the probes of hostile input run it).
pub const PROBE_SPEC: &str = r#"
name = "probe"
seed = 5
trials = 3
kernel = "portable"

[budget]
evaluations = 20000

[[instance]]
name = "tuning"
targets = [0.0]
[instance.synthetic]
params = "tuning"
samples = 200
sigma = 0.1
seed = 1

[[algorithm]]
kind = "aed"
"#;
