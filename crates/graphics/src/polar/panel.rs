//! One panel of the figure: rings, spokes, the incident ray, model curves and samples.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::plot::{PolarPanel, PolarPlot};

/// A "nice" ring spacing giving 3 to 6 rings up to `r`.
fn ring_step(r: f64) -> f64 {
    let raw = r / 4.0;
    let mag = 10f64.powf(raw.log10().floor());
    let m = raw / mag;
    let nice = if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

/// A panel's title: the incident angle as used (not rounded: a panel at 9.5 degrees must not
/// read "10") and the sample counts.
fn panel_title(panel: &PolarPanel) -> String {
    let angle = panel.theta_i_deg;
    if panel.dropped.is_empty() {
        format!("incident {angle}° ({} measured)", panel.measured.len())
    } else {
        format!(
            "incident {angle}° ({} measured, {} dropped)",
            panel.measured.len(),
            panel.dropped.len()
        )
    }
}

pub(super) const GRID: RGBColor = RGBColor(215, 215, 215);
pub(super) const GRID_TEXT: RGBColor = RGBColor(90, 90, 90);

pub(super) fn text_pos(h: HPos, v: VPos) -> Pos {
    Pos::new(h, v)
}

pub(super) fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &PolarPlot,
    panel: &PolarPanel,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let area = area
        .titled(&panel_title(panel), ("sans-serif", 17))
        .map_err(e)?
        .margin(4, 6, 10, 10);
    let r = panel.r_max;
    let (pw, ph) = area.dim_in_pixel();
    let (pw, ph) = (f64::from(pw.max(1)), f64::from(ph.max(1)));
    // Same data units per pixel on both axes so rings are circles; room for the angle labels
    // around the rim and the ring labels under the horizon.
    let per_px = (2.3 * r / pw).max(1.28 * r / ph);
    let half_w = per_px * pw / 2.0;
    let y0 = -0.12 * r;
    let mut chart = ChartBuilder::on(&area)
        .build_cartesian_2d(-half_w..half_w, y0..y0 + per_px * ph)
        .map_err(e)?;
    let polar = |t_deg: f64, rad: f64| {
        let (s, c) = t_deg.to_radians().sin_cos();
        (rad * s, rad * c)
    };
    let arc =
        |rad: f64| -> Vec<(f64, f64)> { (0..=180).map(|k| polar(-90.0 + k as f64, rad)).collect() };
    // Rings with their values under the horizon, on the forward side.
    let step = ring_step(r);
    let mut k = 1;
    while (k as f64) * step <= r * 1.0001 {
        let rad = k as f64 * step;
        chart
            .draw_series(LineSeries::new(arc(rad), GRID.stroke_width(1)))
            .map_err(e)?;
        chart
            .draw_series(std::iter::once(Text::new(
                crate::chart::tick(rad),
                (rad, -0.02 * r),
                ("sans-serif", 12)
                    .into_font()
                    .color(&GRID_TEXT)
                    .pos(text_pos(HPos::Center, VPos::Top)),
            )))
            .map_err(e)?;
        k += 1;
    }
    chart
        .draw_series(LineSeries::new(
            arc(r),
            RGBColor(160, 160, 160).stroke_width(1),
        ))
        .map_err(e)?;
    // Spokes every 30 degrees, labelled with the signed exitant angle.
    for t in (-90..=90).step_by(30) {
        let t = f64::from(t);
        chart
            .draw_series(LineSeries::new(
                vec![(0.0, 0.0), polar(t, r)],
                GRID.stroke_width(1),
            ))
            .map_err(e)?;
        let (x, y) = polar(t, r * 1.04);
        let hpos = if t < -1.0 {
            HPos::Right
        } else if t > 1.0 {
            HPos::Left
        } else {
            HPos::Center
        };
        let vpos = if t.abs() > 89.0 {
            VPos::Center
        } else {
            VPos::Bottom
        };
        chart
            .draw_series(std::iter::once(Text::new(
                format!("{t:.0}°"),
                (x, y),
                ("sans-serif", 12)
                    .into_font()
                    .color(&GRID_TEXT)
                    .pos(text_pos(hpos, vpos)),
            )))
            .map_err(e)?;
    }
    // The incident direction, on the negative (back-scattering) side.
    chart
        .draw_series(DashedLineSeries::new(
            vec![(0.0, 0.0), polar(-panel.theta_i_deg, r)],
            6,
            4,
            RGBColor(100, 100, 100).stroke_width(2),
        ))
        .map_err(e)?;
    // Model curves, cut where they leave the disc so a clipped overshoot is visible as a gap.
    // In reverse so the first curve (the legend's first) ends up on top where curves overlap.
    for (curve, pts) in plot.curves.iter().zip(&panel.curves).rev() {
        let style = curve.color.stroke_width(2);
        let mut segment: Vec<(f64, f64)> = Vec::new();
        let mut segments = Vec::new();
        for &(t, f) in pts {
            if f.is_finite() && f <= r * 1.000_001 {
                segment.push(polar(t, f.max(0.0)));
            } else if !segment.is_empty() {
                segments.push(std::mem::take(&mut segment));
            }
        }
        if !segment.is_empty() {
            segments.push(segment);
        }
        for s in segments {
            if curve.dashed {
                chart
                    .draw_series(DashedLineSeries::new(s, 8, 5, style))
                    .map_err(e)?;
            } else {
                chart.draw_series(LineSeries::new(s, style)).map_err(e)?;
            }
        }
    }
    // Measured samples: a thin line through them (in exitant-angle order) and dots; values
    // beyond the rim are drawn hollow on the rim.
    if let Some(m) = plot.measured {
        let pts: Vec<(f64, f64)> = panel
            .measured
            .iter()
            .map(|s| polar(s.theta_o_deg, s.value.clamp(0.0, r)))
            .collect();
        chart
            .draw_series(LineSeries::new(pts, m.color.mix(0.5).stroke_width(1)))
            .map_err(e)?;
        chart
            .draw_series(panel.measured.iter().map(|s| {
                let style = if s.value > r {
                    m.color.stroke_width(1)
                } else {
                    m.color.filled()
                };
                Circle::new(polar(s.theta_o_deg, s.value.clamp(0.0, r)), 3, style)
            }))
            .map_err(e)?;
    }
    // Dropped samples: hollow, larger than the measured dots so both show where they meet;
    // beyond the rim they sit on it with their value just outside (they can be far larger
    // than everything fitted, so scaling the panel to them would flatten the rest).
    if let Some(m) = plot.dropped {
        chart
            .draw_series(panel.dropped.iter().map(|s| {
                Circle::new(
                    polar(s.theta_o_deg, s.value.clamp(0.0, r)),
                    5,
                    m.color.stroke_width(2),
                )
            }))
            .map_err(e)?;
        for s in panel.dropped.iter().filter(|s| s.value > r) {
            let (x, y) = polar(s.theta_o_deg, r * 1.04);
            let hpos = if s.theta_o_deg < -1.0 {
                HPos::Right
            } else if s.theta_o_deg > 1.0 {
                HPos::Left
            } else {
                HPos::Center
            };
            chart
                .draw_series(std::iter::once(Text::new(
                    crate::chart::tick(s.value),
                    (x, y),
                    ("sans-serif", 12)
                        .into_font()
                        .color(&m.color)
                        .pos(text_pos(hpos, VPos::Center)),
                )))
                .map_err(e)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_panel_title_shows_the_incident_angle_as_used() {
        let panel = |t: f64| super::PolarPanel {
            theta_i_deg: t,
            measured: Vec::new(),
            dropped: Vec::new(),
            curves: Vec::new(),
            r_max: 1.0,
        };
        assert_eq!(
            super::panel_title(&panel(9.5)),
            "incident 9.5° (0 measured)"
        );
        assert_eq!(
            super::panel_title(&panel(35.0)),
            "incident 35° (0 measured)"
        );
    }
}
