//! Figures of an experiment: the harness's statistics turned into [`Chart`]s, which
//! `brdf_graphics` draws.
//! - [`rtd_chart`]: RTD (Kaplan-Meier = ECDF with a shared cutoff) per configuration, log time;
//! - [`sweep_chart`]: ERT with its bootstrap 10-90% band and the median against a swept value;
//! - [`trace_chart`]: best RMSE against CPU time for chosen trials;
//! - [`scatter_chart`]: run time against final RMSE;
//! - [`error_time_chart`]: median time-to-target and ERT as the target RMSE varies;
//! - [`ecdf_targets_chart`]: COCO-style ECDF over (run, target) pairs.

use brdf_graphics::chart::{Chart, LegendAt, Series, Style, color, line_style, step_points, tick};

use crate::stats::{Group, Measure, Outcome, ert, group_outcomes, kaplan_meier, quantile};

/// RTD chart of the groups of one instance, for `target` in `measure`. `cutoff` draws a
/// reference line (the CPU or evaluation budget).
pub fn rtd_chart(
    instance: &str,
    groups: &[&Group<'_>],
    target: f64,
    measure: Measure,
    cutoff: Option<f64>,
) -> Chart {
    let trials = groups.iter().map(|g| g.records.len()).max().unwrap_or(0);
    let shown = crate::stats::fmt_target(target);
    let mut chart = Chart::new(
        format!("RTD - {instance}, target RMSE {shown} ({trials} trials per configuration)"),
        format!("{} to reach RMSE <= {shown} (log scale)", measure.label()),
        "fraction of trials solved",
    );
    chart.x_log = true;
    let outcomes: Vec<Vec<Outcome>> = groups
        .iter()
        .map(|g| group_outcomes(g, target, measure))
        .collect();
    let min_t = outcomes
        .iter()
        .flatten()
        .filter_map(|o| o.success)
        .filter(|t| *t > 0.0)
        .fold(f64::INFINITY, f64::min);
    let max_t = outcomes
        .iter()
        .flatten()
        .map(|o| o.spent)
        .chain(cutoff)
        .fold(0.0, f64::max);
    let (x0, x1) = if min_t.is_finite() {
        (min_t / 1.5, max_t.max(min_t * 2.0) * 1.3)
    } else {
        (max_t.max(1e-3) / 100.0, max_t.max(1e-3) * 1.3)
    };
    chart.x_range = Some((x0, x1));
    chart.y_range = Some((0.0, 1.02));
    for (i, (g, o)) in groups.iter().zip(&outcomes).enumerate() {
        let km = kaplan_meier(o);
        let solved = o.iter().filter(|x| x.success.is_some()).count();
        chart.series.push(Series {
            label: Some(format!("{} ({solved}/{})", g.config, o.len())),
            points: step_points(&km, x0, max_t.max(x0)),
            style: line_style(i),
            color: color(i),
            band: Vec::new(),
        });
    }
    // Curves rise to the right: the lower right corner is usually free.
    chart.legend = LegendAt::LowerRight;
    if let Some(c) = cutoff {
        chart.vlines.push((c, "cutoff".into()));
    }
    chart
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
            color: color(i),
            band,
        });
        chart.series.push(Series {
            label: None,
            points: ert,
            style: Style::Points,
            color: color(i),
            band: Vec::new(),
        });
        chart.series.push(Series {
            label: Some(format!("{prefix}median")),
            points: med,
            style: Style::Dashed,
            color: color(i),
            band: Vec::new(),
        });
    }
    chart.legend = LegendAt::UpperRight;
    chart
}

/// Trace chart: best RMSE against CPU time for the first `per_config` trials of each group.
pub fn trace_chart(
    instance: &str,
    groups: &[&Group<'_>],
    per_config: usize,
    targets: &[f64],
) -> Chart {
    let mut chart = Chart::new(
        format!("Anytime traces - {instance} (first {per_config} trials per configuration)"),
        "CPU seconds (log scale)",
        "best RMSE on the full data (log scale)",
    );
    chart.x_log = true;
    chart.y_log = true;
    chart.legend = LegendAt::UpperRight;
    let mut rmses = Vec::new();
    let mut xmin = f64::INFINITY;
    let mut xmax: f64 = 0.0;
    for (i, g) in groups.iter().enumerate() {
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
            chart.series.push(Series {
                label: (k == 0).then(|| g.config.clone()),
                points: pts,
                style: Style::Line,
                color: color(i),
                band: Vec::new(),
            });
        }
    }
    for &t in targets {
        chart.hlines.push((t, format!("target {t}")));
    }
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
pub fn scatter_chart(instance: &str, groups: &[&Group<'_>], target: f64) -> Chart {
    let mut chart = Chart::new(
        format!("Run time vs final RMSE - {instance} (filled: reached {target}, hollow: censored)"),
        "final best RMSE",
        "CPU seconds at the end of the trial (log scale)",
    );
    chart.y_log = true;
    chart.legend = LegendAt::UpperRight;
    for (i, g) in groups.iter().enumerate() {
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
        chart.series.push(Series {
            label: Some(g.config.clone()),
            points: ok,
            style: Style::Points,
            color: color(i),
            band: Vec::new(),
        });
        chart.series.push(Series {
            label: None,
            points: cens,
            style: Style::HollowPoints,
            color: color(i),
            band: Vec::new(),
        });
    }
    chart.vlines.push((target, format!("target {target}")));
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
) -> Chart {
    let mut chart = Chart::new(
        format!("Run time vs target error - {instance} (from anytime traces)"),
        "target RMSE (log scale)",
        format!("{} (log scale)", measure.label()),
    );
    chart.x_log = true;
    chart.y_log = true;
    chart.legend = LegendAt::UpperRight;
    for (i, g) in groups.iter().enumerate() {
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
        chart.series.push(Series {
            label: Some(format!("{} ERT", g.config)),
            points: e_pts,
            style: Style::Line,
            color: color(i),
            band: Vec::new(),
        });
        chart.series.push(Series {
            label: Some(format!("{} median", g.config)),
            points: m_pts,
            style: Style::Dashed,
            color: color(i),
            band: Vec::new(),
        });
    }
    chart
}

/// COCO-style ECDF: fraction of (run, target) pairs solved against run time.
pub fn ecdf_targets_chart(
    instance: &str,
    groups: &[&Group<'_>],
    grid: &[f64],
    measure: Measure,
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
    chart.legend = LegendAt::LowerRight;
    let mut all: Vec<Vec<Outcome>> = Vec::new();
    for g in groups {
        let mut o = Vec::new();
        for &t in grid {
            o.extend(group_outcomes(g, t, measure));
        }
        all.push(o);
    }
    let min_t = all
        .iter()
        .flatten()
        .filter_map(|o| o.success)
        .filter(|t| *t > 0.0)
        .fold(f64::INFINITY, f64::min);
    let max_t = all.iter().flatten().map(|o| o.spent).fold(0.0, f64::max);
    let (x0, x1) = if min_t.is_finite() {
        (min_t / 1.5, max_t.max(min_t * 2.0) * 1.3)
    } else {
        (max_t.max(1e-3) / 100.0, max_t.max(1e-3) * 1.3)
    };
    chart.x_range = Some((x0, x1));
    chart.y_range = Some((0.0, 1.02));
    for (i, (g, o)) in groups.iter().zip(&all).enumerate() {
        chart.series.push(Series {
            label: Some(g.config.clone()),
            points: step_points(&kaplan_meier(o), x0, max_t.max(x0)),
            style: line_style(i),
            color: color(i),
            band: Vec::new(),
        });
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
