//! `brdf-sls stress`: the numerical-stability report (brdf_stress) with its plots.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use brdf_graphics::ImageFormat;
use brdf_graphics::chart::{self, Chart, LegendAt, Series, Style};
use brdf_stress::{NamedData, StressOptions, StressReport};
use harness::spec::{DataFormat, FileSpec};

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
        .unwrap_or_else(|| PathBuf::from(harness::DEFAULT_RUNS_DIR).join("stress"));
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
        .write_to(&out, harness::store::write_atomic)
        .with_context(|| format!("writing the report to {}", out.display()))?;
    let plots = draw_plots(&report, &out.join("plots"))?;
    say!("{}", summary(&report));
    say!(
        "wrote {} and {} plots to {}",
        "stress.md, stress.json",
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

/// A stress progress line on stderr (a full run takes minutes).
fn progress_line(line: &str) {
    note!("{line}");
}

/// Reads a data file with the default data policy.
fn load_named(path: &Path) -> Result<NamedData> {
    if DataFormat::from_path(path).is_none() {
        bail_input!(
            "--data {}: cannot tell the format from the extension (.brdf, .csv, .binary)",
            path.display()
        );
    }
    let spec = FileSpec {
        path: path.to_path_buf(),
        format: None,
        wavelength: None,
        channel: None,
        max_value: None,
        drop_negative: false,
        drop_below_horizon: true,
    };
    let (data, rep) = harness::instance::load_file(&spec, path)
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

/// The error-in-ulps histogram of every kernel: share of values per ulps bin (log axes).
fn draw_plots(report: &StressReport, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut c = Chart::new(
        "Value error of each kernel against the double-double reference",
        "error in ulps (upper edge of the bin)",
        "share of values",
    );
    c.x_log = true;
    c.y_log = true;
    c.legend = LegendAt::UpperRight;
    for (i, k) in report.kernels.kernels.iter().enumerate() {
        let total: u64 = k.ulps_histogram.iter().map(|&(_, n)| n).sum();
        let points: Vec<(f64, f64)> = k
            .ulps_histogram
            .iter()
            .filter(|&&(edge, n)| edge.is_finite() && edge > 0.0 && n > 0)
            .map(|&(edge, n)| (edge, n as f64 / total.max(1) as f64))
            .collect();
        c.series.push(Series {
            label: Some(format!("{} (max {:.3e} ulps)", k.kernel, k.max_ulps)),
            points,
            // Kernels often agree bin for bin: distinct dash patterns keep each one visible.
            style: chart::distinct_style(i),
            color: chart::color(i),
            band: Vec::new(),
        });
    }
    let formats = [ImageFormat::Png, ImageFormat::Svg];
    let mut files = chart::draw(&c, &dir.join("kernel-ulps-histogram"), &formats)?;
    files.extend(chart::draw(
        &suite_map(report),
        &dir.join("solver-suite-map"),
        &formats,
    )?);
    Ok(files)
}

/// The solver suite as a pass/fail map: one row per group (NIST, MGH, BRDF), one point per
/// case, coloured by right, wrong with a failure code, or a suite failure.
fn suite_map(report: &StressReport) -> Chart {
    const GROUPS: [&str; 3] = ["nist", "mgh", "brdf"];
    let mut c = Chart::new(
        "Solver suite: every case, by group",
        "case (in suite order within its group)",
        "group",
    );
    c.legend = LegendAt::UpperRight;
    c.y_range = Some((0.5, 3.8));
    c.y_categories = vec!["NIST".into(), "MGH".into(), "BRDF hostile".into()];
    let kinds: [(&str, Style); 3] = [
        ("right", Style::Points),
        ("wrong, failure code", Style::HollowPoints),
        ("suite failure", Style::Points),
    ];
    let mut points: [Vec<(f64, f64)>; 3] = Default::default();
    for (g, group) in GROUPS.iter().enumerate() {
        let cases = report.suite.cases.iter().filter(|k| k.group == *group);
        for (i, case) in cases.enumerate() {
            let kind = match (case.right, case.failure.is_some()) {
                (true, _) => 0,
                (false, false) => 1,
                (false, true) => 2,
            };
            points[kind].push((i as f64, (g + 1) as f64));
        }
    }
    let colors = [chart::color(2), chart::color(1), chart::color(3)];
    for (((label, style), pts), color) in kinds.into_iter().zip(points).zip(colors) {
        let n = pts.len();
        c.series.push(Series {
            label: Some(format!("{label} ({n})")),
            points: pts,
            style,
            color,
            band: Vec::new(),
        });
    }
    c
}
