//! `brdf-sls bench`: checks the flags, then [`brdf_bench`] measures the kernels and searches and
//! writes bench.md, bench.json and the page bench.html.

use std::path::PathBuf;

use anyhow::Result;
use brdf_bench::Settings;

use super::{bail_input, note, say};
use crate::cli::BenchArgs;

/// `brdf-sls bench`.
pub fn bench(a: BenchArgs) -> Result<()> {
    if a.seeds == 0 || a.seeds > 10_000 {
        bail_input!("--seeds {}: expected 1 to 10000", a.seeds);
    }
    if !(a.cutoff > 0.0 && a.cutoff.is_finite()) {
        bail_input!(
            "--cutoff {}: expected a positive number of CPU seconds",
            a.cutoff
        );
    }
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(brdf_experiment::DEFAULT_RUNS_DIR).join("bench"));
    if a.rewrite_page {
        brdf_bench::rewrite_page(&out)?;
        say!("wrote bench.html to {} from bench.json", out.display());
        return Ok(());
    }
    let settings = Settings {
        seeds: a.seeds,
        cutoff: a.cutoff,
        progress: a.progress,
    };
    let report = brdf_bench::measure(&settings, &mut |line| note!("{line}"))?;
    let md = brdf_bench::write_files(&report, &out)?;
    say!("{md}");
    say!(
        "wrote bench.md, bench.json and bench.html to {}",
        out.display()
    );
    Ok(())
}
