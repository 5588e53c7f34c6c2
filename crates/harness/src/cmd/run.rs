//! `brdf-sls run`: run or resume an experiment, then write its statistics, table, plots and
//! report page ([`brdf_analysis::pipeline`]). Algorithms of `kind = "python"` run in worker
//! processes of the Python package ([`super::python`]); every other kind in this process.

use anyhow::Result;
use brdf_analysis::pipeline::{Request, run as run_pipeline};
use brdf_experiment::run::{RunOptions, default_threads};
use brdf_experiment::spec::Spec;

use super::shared::{default_out, load_spec};
use super::{input_error, say};
use crate::cli::RunArgs;

/// `brdf-sls run`: checks the flags, then runs the pipeline: prepare (lock, one read of the
/// results, each instance built once, best-known RMSEs), run, statistics, plots and page.
pub fn run(a: RunArgs) -> Result<()> {
    let spec = match &a.spec {
        Some(p) => load_spec(p)?,
        None => Spec::default_experiment(),
    };
    let out = a.out.clone().unwrap_or_else(|| {
        let base = default_out(a.spec.as_deref());
        match a.shard {
            Some(s) => base.join(s.dir_name()),
            None => base,
        }
    });
    brdf_experiment::input_file::check_out_dir(&out)
        .map_err(|e| input_error(format!("--out {}: {e}", out.display())))?;
    let threads = match a.threads {
        Some(n) => {
            brdf_experiment::threads::check(n, "--threads").map_err(input_error)?;
            n
        }
        None => spec.threads.unwrap_or_else(default_threads),
    };
    let request = Request {
        kernel: a.kernel.unwrap_or(spec.kernel),
        shard: a.shard,
        options: RunOptions {
            threads,
            fresh: a.fresh,
            progress: a.progress,
            limit: a.limit,
        },
        plots: !a.no_plots,
        notes: true,
        spec,
        out,
    };
    let origin = a.spec.clone();
    let finished = run_pipeline(request, |spec, built, kernel| {
        super::python::executor(spec, origin.as_deref(), built, kernel)
    })?;
    say!("{}", finished.report.table);
    say!("{}", finished.summary);
    Ok(())
}
