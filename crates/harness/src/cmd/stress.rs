//! `brdf-sls stress`: the numerical-stability report (brdf_stress) with its plots, written as
//! stress.md, stress.json and the page stress.html.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use brdf_experiment::spec::FileSpec;
use brdf_graphics::ImageFormat;
use brdf_graphics::chart::{self, Chart};
use brdf_stress::{NamedData, StressOptions, StressReport};

use super::{bail_input, note, say};
use crate::cli::StressArgs;

/// `brdf-sls stress`.
pub fn stress(a: StressArgs) -> Result<()> {
    if a.threads == Some(0) {
        bail_input!("--threads must be at least 1");
    }
    let data = a
        .data
        .iter()
        .map(|p| load_named(p))
        .collect::<Result<Vec<_>>>()?;
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(brdf_experiment::DEFAULT_RUNS_DIR).join("stress"));
    if a.rewrite_page {
        return rewrite_page(&out);
    }
    note!(
        "stress test ({}), seed {}, writing to {}",
        if a.quick { "quick" } else { "full" },
        a.seed,
        out.display()
    );
    let options = StressOptions {
        quick: a.quick,
        data,
        seed: a.seed,
        threads: a.threads,
        sizes: None,
        progress: Some(progress_line),
    };
    let report = brdf_stress::run(&options).context("running the stress test")?;
    report
        .write_to(&out, brdf_experiment::store::write_atomic)
        .with_context(|| format!("writing the report to {}", out.display()))?;
    let (plots, charts) = draw_plots(&report, &out.join("plots"))?;
    let machine = brdf_experiment::machine::MachineInfo::current(report.threads);
    let written = brdf_experiment::machine::unix_now();
    write_page(&report, &charts, Some(&machine), written, &out)?;
    say!("{}", summary(&report));
    say!(
        "wrote {} and {} plots to {}",
        "stress.md, stress.json, stress.html",
        plots.len(),
        out.display()
    );
    if !report.passed() {
        let failed: Vec<String> = report.failures().iter().map(|c| c.name.clone()).collect();
        bail!(
            "{} check(s) missed their tolerance: {} (see {})",
            failed.len(),
            failed.join("; "),
            out.join("stress.md").display()
        );
    }
    Ok(())
}

/// Writes stress.html of `report` with `charts` into `out`.
fn write_page(
    report: &StressReport,
    charts: &[Chart],
    machine: Option<&brdf_experiment::machine::MachineInfo>,
    written: u64,
    out: &Path,
) -> Result<()> {
    let page = brdf_analysis::html::stress_page(report, charts, machine, written)
        .context("building the stress page")?;
    let html = out.join("stress.html");
    brdf_experiment::store::write_atomic(&html, page.as_bytes())
        .with_context(|| format!("writing {}", html.display()))
}

/// `--rewrite-page`: stress.html and plots/ again from `out`/stress.json, no check run.
fn rewrite_page(out: &Path) -> Result<()> {
    let json = out.join("stress.json");
    let text = std::fs::read_to_string(&json).map_err(|e| {
        super::input_error(format!(
            "{}: {e} (--rewrite-page reads a stress run's stress.json)",
            json.display()
        ))
    })?;
    let report = StressReport::from_json(&text)
        .map_err(|e| super::input_error(format!("{}: {e}", json.display())))?;
    let (plots, charts) = draw_plots(&report, &out.join("plots"))?;
    write_page(
        &report,
        &charts,
        None,
        brdf_experiment::machine::unix_now(),
        out,
    )?;
    say!(
        "wrote stress.html and {} plots to {} from stress.json",
        plots.len(),
        out.display()
    );
    Ok(())
}

/// A stress progress line on stderr (a full run takes minutes).
fn progress_line(line: &str) {
    note!("{line}");
}

/// Reads a data file with the default data policy.
fn load_named(path: &Path) -> Result<NamedData> {
    let spec = FileSpec::plain(path.to_path_buf());
    if let Err(e) = spec.format_for(path) {
        bail_input!("--data {}: {e}", path.display());
    }
    let (data, rep) = brdf_experiment::instance::load_file(&spec, path)
        .with_context(|| format!("reading {}", path.display()))?;
    note!("{}: {} samples ({rep})", path.display(), data.len());
    Ok(NamedData {
        name: path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        data,
    })
}

/// One line per check that failed, and the counts.
fn summary(report: &StressReport) -> String {
    let failed = report.failures();
    let mut s = format!(
        "{} of {} checks passed in {:.1} s",
        report.checks.len() - failed.len(),
        report.checks.len(),
        report.seconds[3]
    );
    for c in failed {
        s.push_str(&format!(
            "\nFAILED {}: measured {}, tolerance {}",
            c.name, c.measured, c.tolerance
        ));
    }
    s
}

/// Draws every chart of the report to `dir` as PNG and SVG; returns the files and the charts
/// (the page inlines the same charts).
fn draw_plots(report: &StressReport, dir: &Path) -> Result<(Vec<PathBuf>, Vec<Chart>)> {
    let formats = [ImageFormat::Png, ImageFormat::Svg];
    let mut files = Vec::new();
    let mut charts = Vec::new();
    for (stem, c) in brdf_analysis::stress_charts::charts(report) {
        files.extend(chart::draw(&c, &dir.join(stem), &formats)?);
        charts.push(c);
    }
    Ok((files, charts))
}
