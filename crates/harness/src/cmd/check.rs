//! `brdf-sls check`: validate a spec and print its plan.

use anyhow::Result;
use harness::run::default_threads;

use super::shared::{default_out, load_spec, resolve_best_known};
use super::{input_error, say};
use crate::cli::CheckArgs;

/// `brdf-sls check`.
pub fn check(a: CheckArgs) -> Result<()> {
    let mut spec = load_spec(&a.spec)?;
    if let Some(n) = a.threads {
        harness::threads::check(n, "--threads").map_err(input_error)?;
    }
    let threads = a.threads.or(spec.threads).unwrap_or_else(default_threads);
    say!("{}", spec.describe(threads).trim_end());
    for i in &spec.instances {
        if let harness::spec::Source::File { resolved, .. } = &i.source
            && !resolved.exists()
        {
            return Err(input_error(format!(
                "instance `{}`: data file {} does not exist",
                i.name,
                resolved.display()
            )));
        }
    }
    resolve_best_known(&mut spec, None)?;
    say!("{}", harness::best_known::summary(&spec).trim_end());
    say!("fingerprint {}", spec.fingerprint());
    say!(
        "default results directory: {}",
        default_out(Some(&a.spec)).display()
    );
    Ok(())
}
