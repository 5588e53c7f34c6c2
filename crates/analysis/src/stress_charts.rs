//! The charts of a stress report (`brdf-sls stress`): drawn to `plots/` and inlined in
//! `stress.html`, so both show the same figures.

use brdf_graphics::chart::{self, Chart, Series, Style};
use brdf_stress::StressReport;

/// Every chart of `report` with the file stem it is drawn under in `plots/`.
pub fn charts(report: &StressReport) -> Vec<(&'static str, Chart)> {
    vec![
        ("kernel-ulps-histogram", ulps_histogram(report)),
        ("solver-suite-map", suite_map(report)),
    ]
}

/// The error-in-ulps histogram of every kernel: share of values per ulps bin (log axes).
pub fn ulps_histogram(report: &StressReport) -> Chart {
    let mut c = Chart::new(
        "Value error of each kernel against the double-double reference",
        "error in ulps (upper edge of the bin)",
        "share of values",
    );
    c.x_log = true;
    c.y_log = true;
    for (i, k) in report.kernels.kernels.iter().enumerate() {
        let total: u64 = k.ulps_histogram.iter().map(|&(_, n)| n).sum();
        // Log axes: empty bins and the open last bin (an infinite edge) have no place.
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
            key: None,
        });
    }
    c
}

/// The solver suite as a pass/fail map: one row per group (NIST, MGH, BRDF), one point per
/// case, coloured by right, wrong with a failure code, or a suite failure.
pub fn suite_map(report: &StressReport) -> Chart {
    const GROUPS: [&str; 3] = ["nist", "mgh", "brdf"];
    let mut c = Chart::new(
        "Solver suite: every case, by group",
        "case (in suite order within its group)",
        "group",
    );
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
            key: None,
        });
    }
    c
}
