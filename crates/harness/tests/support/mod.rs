//! What the command-line tests share: running the built `brdf-sls` as a user would (CI=true,
//! so no progress bars) and reading what it printed.

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
