//! Figures of an experiment: the statistics turned into [`Chart`]s, which `brdf_graphics`
//! draws. Every series of a configuration has that configuration's colour and line style
//! ([`Colors`]), in every figure of a page.
//! - [`rtd_chart`]: RTD (Kaplan-Meier = ECDF with a shared cutoff) per configuration, log time,
//!   with a pointwise 95% confidence band;
//! - [`sweep_chart`]: ERT with its bootstrap 10-90% band and the median against a swept value;
//! - [`trace_chart`]: best RMSE against CPU time for chosen trials;
//! - [`scatter_chart`]: run time against final RMSE;
//! - [`error_time_chart`]: median time-to-target and ERT as the target RMSE varies;
//! - [`ecdf_targets_chart`]: COCO-style ECDF over (run, target) pairs;
//! - [`fixed_budget_chart`]: the best RMSE reached by a given budget (median and quartiles);
//! - [`aggregate_ecdf_chart`]: the runtime ECDF over all (instance, target) pairs of a run.

use brdf_graphics::RGBColor;
use brdf_graphics::chart::{Chart, Series, Style, series_color, series_style, step_points, tick};

use crate::stats::{
    Group, Measure, Outcome, cdf_at, ert, group_outcomes, kaplan_meier, kaplan_meier_band, quantile,
};

/// One colour and line style per configuration label, by its place in a list (the spec's
/// configurations): the same in every figure of a page and in every page of one experiment.
#[derive(Clone, Debug, Default)]
pub struct Colors {
    labels: Vec<String>,
}

impl Colors {
    /// Colours for `labels` in this order.
    pub fn new(labels: &[String]) -> Colors {
        Colors {
            labels: labels.to_vec(),
        }
    }

    /// The index of `label` (labels not listed come after the listed ones, by position of
    /// first use: callers list every label they draw).
    fn index(&self, label: &str) -> usize {
        self.labels
            .iter()
            .position(|l| l == label)
            .unwrap_or(self.labels.len())
    }

    /// The colour of `label`.
    pub fn color(&self, label: &str) -> RGBColor {
        series_color(self.index(label))
    }

    /// The line style of `label`.
    pub fn style(&self, label: &str) -> Style {
        series_style(self.index(label))
    }
}

/// A series of configuration `config` in its colour and style.
fn config_series(colors: &Colors, config: &str, label: String, points: Vec<(f64, f64)>) -> Series {
    Series {
        label: Some(label),
        points,
        style: colors.style(config),
        color: colors.color(config),
        band: Vec::new(),
        key: Some(config.to_string()),
    }
}

/// The step band `(x, lo, hi)` of a Kaplan-Meier band from `x0` to `x1`.
fn step_band(band: &[(f64, f64, f64, f64)], x0: f64, x1: f64) -> Vec<(f64, f64, f64)> {
    let mut out = vec![(x0, 0.0, 0.0)];
    let (mut lo, mut hi) = (0.0, 0.0);
    for &(t, _, l, h) in band {
        out.push((t, lo, hi));
        out.push((t, l, h));
        (lo, hi) = (l, h);
    }
    out.push((x1.max(band.last().map_or(x0, |b| b.0)), lo, hi));
    out
}

/// RTD chart of the groups of one instance, for `target` in `measure`, with each curve's
/// pointwise 95% confidence band. `cutoff` draws a reference line (the CPU or evaluation
/// budget).
pub fn rtd_chart(
    instance: &str,
    groups: &[&Group<'_>],
    (target, shown): (f64, &str),
    measure: Measure,
    cutoff: Option<f64>,
    colors: &Colors,
) -> Chart {
    let trials = groups.iter().map(|g| g.records.len()).max().unwrap_or(0);
    let value = shown.split(" (").next().unwrap_or(shown);
    let mut chart = Chart::new(
        format!(
            "RTD in {} - {instance}, target RMSE {shown} ({trials} trials per configuration)",
            measure.label()
        ),
        format!("{} to reach RMSE <= {value} (log scale)", measure.label()),
        "fraction of trials solved",
    );
    chart.x_log = true;
    // Many overlapping bands turn to mud: lighter ones beyond three configurations.
    chart.band_opacity = if groups.len() > 3 { 0.07 } else { 0.15 };
    let outcomes: Vec<Vec<Outcome>> = groups
        .iter()
        .map(|g| group_outcomes(g, target, measure))
        .collect();
    let (x0, x1) = time_range(outcomes.iter().flatten(), cutoff);
    chart.x_range = Some((x0, x1));
    chart.y_range = Some((0.0, 1.02));
    let max_t = x1 / 1.3;
    for (g, o) in groups.iter().zip(&outcomes) {
        let band = kaplan_meier_band(o);
        let km: Vec<(f64, f64)> = band.iter().map(|b| (b.0, b.1)).collect();
        let solved = o.iter().filter(|x| x.success.is_some()).count();
        let label = format!("{} ({solved}/{} solved)", g.config, o.len());
        let mut s = config_series(
            colors,
            &g.config,
            label,
            step_points(&km, x0, max_t.max(x0)),
        );
        s.band = step_band(&band, x0, max_t.max(x0));
        chart.series.push(s);
    }
    if let Some(c) = cutoff {
        chart.vlines.push((c, "cutoff".into()));
    }
    chart
}

/// The x range of a run-time chart: from below the first success to beyond the last time
/// spent (and the cutoff).
fn time_range<'o>(
    outcomes: impl Iterator<Item = &'o Outcome> + Clone,
    cutoff: Option<f64>,
) -> (f64, f64) {
    let min_t = outcomes
        .clone()
        .filter_map(|o| o.success)
        .filter(|t| *t > 0.0)
        .fold(f64::INFINITY, f64::min);
    let max_t = outcomes.map(|o| o.spent).chain(cutoff).fold(0.0, f64::max);
    if min_t.is_finite() {
        (min_t / 1.5, max_t.max(min_t * 2.0) * 1.3)
    } else {
        (max_t.max(1e-3) / 100.0, max_t.max(1e-3) * 1.3)
    }
}

/// Sweep chart: ERT (with bootstrap band) and median against the swept value. `rows` holds
/// per series label: (x, ERT, band lo, band hi, median).
#[allow(clippy::type_complexity)]
pub fn sweep_chart(
    title: &str,
    parameter: &str,
    measure: Measure,
    rows: &[(
        String,
        Vec<(f64, Option<f64>, Option<f64>, Option<f64>, Option<f64>)>,
    )],
    x_log: bool,
) -> Chart {
    let mut chart = Chart::new(title, parameter, format!("{} (log scale)", measure.label()));
    chart.y_log = true;
    chart.x_log = x_log;
    for (i, (label, pts)) in rows.iter().enumerate() {
        let ert: Vec<(f64, f64)> = pts.iter().filter_map(|p| p.1.map(|e| (p.0, e))).collect();
        let band: Vec<(f64, f64, f64)> = pts
            .iter()
            .filter_map(|p| match (p.2, p.3) {
                (Some(a), Some(b)) => Some((p.0, a, b)),
                _ => None,
            })
            .collect();
        let med: Vec<(f64, f64)> = pts.iter().filter_map(|p| p.4.map(|m| (p.0, m))).collect();
        let prefix = if label.is_empty() {
            String::new()
        } else {
            format!("{label} ")
        };
        chart.series.push(Series {
            label: Some(format!("{prefix}ERT (band: bootstrap 10-90%)")),
            points: ert.clone(),
            style: Style::Line,
            color: series_color(i),
            band,
            key: None,
        });
        chart.series.push(Series {
            label: None,
            points: ert,
            style: Style::Points,
            color: series_color(i),
            band: Vec::new(),
            key: None,
        });
        chart.series.push(Series {
            label: Some(format!("{prefix}median")),
            points: med,
            style: Style::Dashed,
            color: series_color(i),
            band: Vec::new(),
            key: None,
        });
    }
    chart
}

/// Trace chart: best RMSE against CPU time for the first `per_config` trials of each group.
pub fn trace_chart(
    instance: &str,
    groups: &[&Group<'_>],
    per_config: usize,
    targets: &[f64],
    colors: &Colors,
) -> Chart {
    let mut chart = Chart::new(
        format!("Anytime traces - {instance} (first {per_config} trials per configuration)"),
        "CPU seconds (log scale)",
        "best RMSE on the full data (log scale)",
    );
    chart.x_log = true;
    chart.y_log = true;
    let mut rmses = Vec::new();
    let mut xmin = f64::INFINITY;
    let mut xmax: f64 = 0.0;
    for g in groups {
        for (k, r) in g.records.iter().take(per_config).enumerate() {
            let tr = &r.result.trace;
            let mut pts = Vec::new();
            for (j, p) in tr.iter().enumerate() {
                let t = p.at.cpu_seconds.max(1e-4);
                if j > 0 {
                    pts.push((t, tr[j - 1].rmse));
                }
                pts.push((t, p.rmse));
                // The first half of a trace's improvements is the descent from its random
                // start; the range is set by where the traces settle.
                if 2 * j >= tr.len() {
                    rmses.push(p.rmse);
                }
                xmin = xmin.min(t);
            }
            let end = r.result.ended_at.cpu_seconds.max(1e-4);
            xmax = xmax.max(end);
            if let Some(last) = tr.last() {
                pts.push((end, last.rmse));
            }
            let mut s = config_series(colors, &g.config, g.config.clone(), pts);
            s.label = (k == 0).then(|| g.config.clone());
            chart.series.push(s);
        }
    }
    target_lines(&mut chart, targets);
    chart.y_range = trace_y_range(&rmses, targets);
    if xmin.is_finite() && xmax > 0.0 {
        chart.x_range = Some((xmin / 1.5, xmax.max(xmin * 2.0) * 1.3));
    }
    chart
}

/// The y range of a trace chart: from 0.9 times the lowest target to the 90% quantile of
/// `rmses` (the RMSEs where the traces settle; at least 1.1 times the highest target). The band that decides between
/// configurations lies just above the targets; random picks' large RMSEs above the quantile and
/// exact fits far below the targets would squash it, so both are clipped (a trace that drops
/// below the range has reached every target). Without targets: the data's range.
fn trace_y_range(rmses: &[f64], targets: &[f64]) -> Option<(f64, f64)> {
    let mut v: Vec<f64> = rmses
        .iter()
        .copied()
        .filter(|r| r.is_finite() && *r > 0.0)
        .collect();
    v.sort_by(f64::total_cmp);
    let targets: Vec<f64> = targets
        .iter()
        .copied()
        .filter(|t| t.is_finite() && *t > 0.0)
        .collect();
    let lowest = targets.iter().copied().reduce(f64::min);
    let highest = targets.iter().copied().reduce(f64::max);
    let q90 = (!v.is_empty()).then(|| v[((v.len() - 1) as f64 * 0.9).round() as usize]);
    let lo = match (lowest, v.first()) {
        (Some(t), _) => t * 0.9,
        (None, Some(&m)) => m / 1.05,
        (None, None) => return None,
    };
    let hi = match (q90, highest) {
        (Some(q), Some(t)) => q.max(t * 1.1),
        (Some(q), None) => q,
        (None, Some(t)) => t * 1.1,
        (None, None) => return None,
    } * 1.05;
    (hi > lo).then_some((lo, hi))
}

/// Scatter of run time against final RMSE, one colour per configuration; successes filled,
/// censored runs hollow.
pub fn scatter_chart(
    instance: &str,
    groups: &[&Group<'_>],
    (target, shown): (f64, &str),
    colors: &Colors,
) -> Chart {
    let mut chart = Chart::new(
        format!("Run time vs final RMSE - {instance} (filled: reached {shown}, hollow: censored)"),
        "final best RMSE",
        "CPU seconds at the end of the trial (log scale)",
    );
    chart.y_log = true;
    for g in groups {
        let mut ok = Vec::new();
        let mut cens = Vec::new();
        for r in &g.records {
            let p = (r.result.best_rmse, r.result.ended_at.cpu_seconds.max(1e-4));
            if r.result.reached() {
                ok.push(p);
            } else {
                cens.push(p);
            }
        }
        let mut filled = config_series(colors, &g.config, g.config.clone(), ok);
        filled.style = Style::Points;
        let mut hollow = config_series(colors, &g.config, g.config.clone(), cens);
        hollow.style = Style::HollowPoints;
        hollow.label = None;
        chart.series.push(filled);
        chart.series.push(hollow);
    }
    chart.vlines.push((target, format!("target {shown}")));
    chart
}

/// A log-spaced grid of `steps` targets from `lo` to `hi`.
pub fn target_grid(lo: f64, hi: f64, steps: usize) -> Vec<f64> {
    let steps = steps.max(2);
    (0..steps)
        .map(|i| (lo.ln() + (hi.ln() - lo.ln()) * i as f64 / (steps - 1) as f64).exp())
        .collect()
}

/// Median time-to-target and ERT against the target RMSE, from the stored traces.
pub fn error_time_chart(
    instance: &str,
    groups: &[&Group<'_>],
    grid: &[f64],
    measure: Measure,
    colors: &Colors,
) -> Chart {
    let mut chart = Chart::new(
        format!("Run time vs target error - {instance} (from anytime traces)"),
        "target RMSE (log scale)",
        format!("{} (log scale)", measure.label()),
    );
    chart.x_log = true;
    chart.y_log = true;
    for g in groups {
        let mut e_pts = Vec::new();
        let mut m_pts = Vec::new();
        for &t in grid {
            let o = group_outcomes(g, t, measure);
            let e = ert(&o);
            if e.is_finite() && e > 0.0 {
                e_pts.push((t, e));
            }
            if let Some(m) = quantile(&kaplan_meier(&o), 0.5).filter(|m| *m > 0.0) {
                m_pts.push((t, m));
            }
        }
        // Colour: the configuration; line: solid ERT, dashed median.
        let mut e = config_series(colors, &g.config, format!("{} ERT", g.config), e_pts);
        e.style = Style::Line;
        let mut m = config_series(colors, &g.config, format!("{} median", g.config), m_pts);
        m.style = Style::Dashed;
        chart.series.push(e);
        chart.series.push(m);
    }
    chart
}

/// COCO-style ECDF: fraction of (run, target) pairs solved against run time.
pub fn ecdf_targets_chart(
    instance: &str,
    groups: &[&Group<'_>],
    grid: &[f64],
    measure: Measure,
    colors: &Colors,
) -> Chart {
    let (lo, hi) = (
        grid.first().copied().unwrap_or(0.0),
        grid.last().copied().unwrap_or(0.0),
    );
    let mut chart = Chart::new(
        format!(
            "ECDF over {} targets in [{}, {}] - {instance}",
            grid.len(),
            tick(lo),
            tick(hi)
        ),
        format!("{} (log scale)", measure.label()),
        "fraction of (trial, target) pairs solved",
    );
    chart.x_log = true;
    let mut all: Vec<Vec<Outcome>> = Vec::new();
    for g in groups {
        let mut o = Vec::new();
        for &t in grid {
            o.extend(group_outcomes(g, t, measure));
        }
        all.push(o);
    }
    let (x0, x1) = time_range(all.iter().flatten(), None);
    chart.x_range = Some((x0, x1));
    chart.y_range = Some((0.0, 1.02));
    for (g, o) in groups.iter().zip(&all) {
        let pts = step_points(&kaplan_meier(o), x0, (x1 / 1.3).max(x0));
        chart
            .series
            .push(config_series(colors, &g.config, g.config.clone(), pts));
    }
    chart
}

/// The targets as labelled horizontal reference lines (as many digits as keep them apart).
fn target_lines(chart: &mut Chart, targets: &[f64]) {
    let digits = crate::stats::target_digits(targets);
    for &t in targets {
        let label = format!("target {}", crate::stats::significant(t, digits));
        chart.hlines.push((t, label));
    }
}

/// Quantile `p` of sorted values (the smallest value with at least `p` of them at or below).
fn sorted_quantile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::INFINITY;
    }
    let k = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}

/// The best full-data RMSE of `record` after `budget` in `measure` (`+inf` before its first
/// evaluation): the last trace point at or before the budget. A trial that ended earlier
/// keeps its last RMSE.
fn best_at(record: &brdf_experiment::store::TrialRecord, budget: f64, measure: Measure) -> f64 {
    record
        .result
        .trace
        .iter()
        .take_while(|p| measure.of(&p.at) <= budget)
        .last()
        .map_or(f64::INFINITY, |p| p.rmse)
}

/// The fixed-budget view of one instance: for each configuration, the best RMSE its trials
/// had reached by a given budget in `measure` (median line, interquartile band), read from the
/// stored traces, with the targets as reference lines.
pub fn fixed_budget_chart(
    instance: &str,
    groups: &[&Group<'_>],
    targets: &[f64],
    measure: Measure,
    colors: &Colors,
) -> Chart {
    let mut chart = Chart::new(
        format!("Best RMSE by budget - {instance} (median and quartiles over trials)"),
        format!("budget in {} (log scale)", measure.label()),
        "best full-data RMSE reached (log scale)",
    );
    chart.x_log = true;
    chart.y_log = true;
    chart.band_opacity = if groups.len() > 3 { 0.07 } else { 0.15 };
    let starts = groups.iter().flat_map(|g| &g.records).filter_map(|r| {
        r.result
            .trace
            .first()
            .map(|p| measure.of(&p.at))
            .filter(|t| *t > 0.0)
    });
    let lo = starts.fold(f64::INFINITY, f64::min);
    let hi = groups
        .iter()
        .flat_map(|g| &g.records)
        .map(|r| measure.of(&r.result.ended_at))
        .fold(0.0, f64::max);
    if !(lo.is_finite() && hi > 0.0) {
        return chart;
    }
    let hi = hi.max(lo * 2.0);
    let grid = target_grid(lo, hi, 60);
    let mut rmses = Vec::new();
    for g in groups {
        let (mut med, mut band) = (Vec::new(), Vec::new());
        for &b in &grid {
            let mut v: Vec<f64> = g.records.iter().map(|r| best_at(r, b, measure)).collect();
            v.sort_by(f64::total_cmp);
            let (q1, q2, q3) = (
                sorted_quantile(&v, 0.25),
                sorted_quantile(&v, 0.5),
                sorted_quantile(&v, 0.75),
            );
            if q2.is_finite() {
                med.push((b, q2));
                rmses.push(q2);
            }
            if q1.is_finite() && q3.is_finite() {
                band.push((b, q1, q3));
                rmses.push(q3);
            }
        }
        let mut s = config_series(colors, &g.config, g.config.clone(), med);
        s.band = band;
        chart.series.push(s);
    }
    target_lines(&mut chart, targets);
    chart.y_range = trace_y_range(&rmses, targets);
    chart.x_range = Some((lo / 1.2, hi * 1.2));
    chart
}

/// The runtime ECDF over many (instance, target) pairs, COCO-style: for each configuration,
/// the mean over the pairs of its Kaplan-Meier curve (each pair weighted equally), i.e. the
/// fraction of (trial, instance, target) triples solved by a given time. `pairs` holds, per
/// configuration label, its outcomes for each pair it ran.
pub fn aggregate_ecdf_chart(
    title: &str,
    pairs: &[(String, Vec<Vec<Outcome>>)],
    measure: Measure,
    colors: &Colors,
) -> Chart {
    let n = pairs.iter().map(|p| p.1.len()).max().unwrap_or(0);
    let mut chart = Chart::new(
        format!("{title} ({n} instance-target pairs, {})", measure.label()),
        format!("{} (log scale)", measure.label()),
        "fraction of (trial, instance, target) solved",
    );
    chart.x_log = true;
    let all = pairs.iter().flat_map(|p| p.1.iter().flatten());
    let (x0, x1) = time_range(all, None);
    chart.x_range = Some((x0, x1));
    chart.y_range = Some((0.0, 1.02));
    for (config, outcomes) in pairs {
        let curves: Vec<Vec<(f64, f64)>> = outcomes.iter().map(|o| kaplan_meier(o)).collect();
        let mut times: Vec<f64> = curves.iter().flatten().map(|p| p.0).collect();
        times.sort_by(f64::total_cmp);
        times.dedup();
        let k = curves.len().max(1) as f64;
        let mean: Vec<(f64, f64)> = times
            .iter()
            .map(|&t| (t, curves.iter().map(|c| cdf_at(c, t)).sum::<f64>() / k))
            .collect();
        let pts = step_points(&mean, x0, (x1 / 1.3).max(x0));
        chart
            .series
            .push(config_series(colors, config, config.clone(), pts));
    }
    chart
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trace_range_zooms_on_the_targets() {
        // Random picks far above, an exact fit far below: the range keeps the band between
        // 0.9 times the lowest target and the 90% quantile.
        let mut rmses = vec![50.0, 0.115, 0.112, 0.111, 0.110, 0.108, 0.105, 0.104, 0.103];
        rmses.push(1e-14);
        let (lo, hi) = trace_y_range(&rmses, &[0.1, 0.102]).unwrap();
        assert!((lo - 0.09).abs() < 1e-12, "{lo}");
        assert!(hi > 0.115 && hi < 0.13, "{hi}");
        // The highest target stays visible when every trace lies below it.
        let (_, hi) = trace_y_range(&[0.01, 0.02], &[0.5]).unwrap();
        assert!(hi >= 0.55, "{hi}");
        assert_eq!(trace_y_range(&[], &[]), None);
    }

    #[test]
    fn target_grid_is_geometric() {
        let g = target_grid(0.1, 1.0, 3);
        assert!((g[1] - 0.1f64.sqrt()).abs() < 1e-12);
        assert_eq!(g.len(), 3);
    }
}
