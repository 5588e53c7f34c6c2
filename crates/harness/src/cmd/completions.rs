//! `brdf-sls completions` and `brdf-sls man`: shell completions and man pages generated from
//! the command line's own definitions.

use std::path::Path;

use anyhow::{Context, Result};
use clap::CommandFactory;

use super::say;
use crate::cli::{Cli, CompletionsArgs, ManArgs};

/// `brdf-sls completions SHELL`: the script on standard output.
pub fn completions(a: CompletionsArgs) -> Result<()> {
    let mut cmd = Cli::command();
    let mut script = Vec::new();
    clap_complete::generate(a.shell, &mut cmd, "brdf-sls", &mut script);
    use std::io::Write as _;
    std::io::stdout()
        .lock()
        .write_all(&script)
        .map_err(|e| anyhow::Error::new(e).context("writing to standard output"))
}

/// `brdf-sls man`: the main page on standard output, or every page into `--out`.
pub fn man(a: ManArgs) -> Result<()> {
    let cmd = Cli::command();
    match a.out {
        None => {
            let mut page = Vec::new();
            clap_mangen::Man::new(cmd)
                .render(&mut page)
                .context("rendering the man page")?;
            use std::io::Write as _;
            std::io::stdout()
                .lock()
                .write_all(&page)
                .map_err(|e| anyhow::Error::new(e).context("writing to standard output"))
        }
        Some(dir) => {
            write_pages(cmd, &dir)?;
            say!(
                "wrote brdf-sls.1 and a page per command (brdf-sls-run.1, ...) to {}",
                dir.display()
            );
            Ok(())
        }
    }
}

/// Writes `brdf-sls.1` and `brdf-sls-<command>.1` for every command.
fn write_pages(cmd: clap::Command, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    clap_mangen::generate_to(cmd, dir)
        .with_context(|| format!("writing man pages to {}", dir.display()))
}
