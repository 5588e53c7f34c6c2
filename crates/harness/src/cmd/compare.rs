//! `brdf-sls compare`: before and after, as a verdict table, an HTML page and an exit status
//! (3 when B is significantly slower anywhere, so CI can use it as a regression check and
//! tell it from a failure, 1, or bad input, 2).

use anyhow::{Context, Result};
use brdf_analysis::compare::{Options, compare as judge, entries, table};
use brdf_analysis::stats::Measure;

use super::report::{folder_of, lock_page_folder, read_folder, write_page};
use super::{bail_input, say};
use crate::cli::{CompareArgs, VerdictMeasure};

/// B significantly slower somewhere: exit status [`super::SLOWER_STATUS`] with this message.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Slower(pub String);

/// `brdf-sls compare`.
pub fn compare(a: CompareArgs) -> Result<()> {
    if !(a.alpha > 0.0 && a.alpha < 1.0) {
        bail_input!(
            "--alpha must be between 0 and 1 (exclusive), not {}",
            a.alpha
        );
    }
    if !(a.min_effect >= 0.0 && a.min_effect.is_finite()) {
        bail_input!(
            "--min-effect must be a finite fraction of at least 0 (0.05 = 5%), not {}",
            a.min_effect
        );
    }
    let (fa, fb) = (read_folder(&a.a)?, read_folder(&a.b)?);
    let (ea, eb) = (
        entries(&fa, &fa.statistics()),
        entries(&fb, &fb.statistics()),
    );
    let options = Options {
        alpha: a.alpha,
        min_effect: a.min_effect,
        measure: match a.measure {
            VerdictMeasure::Evals => Measure::Evaluations,
            VerdictMeasure::Cpu => Measure::CpuSeconds,
        },
        bootstrap: fa.spec.stats.bootstrap,
        seed: fa.spec.seed,
    };
    let c = judge(&ea, &eb, options);
    say!("{}", table(&c).trim_end());
    let out = a
        .out
        .unwrap_or_else(|| folder_of(&a.b).join("compare.html"));
    let page = brdf_analysis::html::compare_page(&fa, &fb, (&ea, &eb), &c)
        .context("building the comparison page")?;
    let _lock = lock_page_folder(&out)?;
    write_page(&out, &page)?;
    say!("wrote {}", out.display());
    if c.comparable() == 0 {
        bail_input!(
            "nothing in {} and {} is comparable (see the reasons above)",
            a.a.display(),
            a.b.display()
        );
    }
    if c.slower() > 0 {
        return Err(Slower(format!(
            "{} of {} compared pairs are significantly slower in {}",
            c.slower(),
            c.comparable(),
            a.b.display()
        ))
        .into());
    }
    Ok(())
}
