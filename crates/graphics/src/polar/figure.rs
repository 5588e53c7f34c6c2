//! The whole figure: checks, layout, title, legend and the PNG/SVG files ([`draw_polar`]).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use super::panel::{GRID_TEXT, draw_panel, text_pos};
use super::plot::{PolarPanel, PolarPlot, polar_panels};
use crate::ImageFormat as PlotFormat;
use crate::files::{Figure, PlotError, register_fonts, write_png, write_svg};

/// A polar plot laid out in panels, drawable on any backend.
struct PolarFigure<'a, 'p> {
    plot: &'a PolarPlot<'p>,
    panels: &'a [PolarPanel],
    cols: usize,
}

impl Figure for PolarFigure<'_, '_> {
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        draw_figure(root, self.plot, self.panels, self.cols)
    }
}

/// Draws `plot` to `<base>.png` and/or `<base>.svg` (both written atomically via a temporary
/// file), returning the files written. Panels of at least 200x150 pixels, at most 30
/// incident angles, each in `[0, 90)` degrees; otherwise a [`PlotError::Draw`] naming the
/// problem.
pub fn draw_polar(
    plot: &PolarPlot,
    base: &Path,
    formats: &[PlotFormat],
) -> Result<Vec<PathBuf>, PlotError> {
    register_fonts();
    let invalid = |message: String| PlotError::Draw {
        path: base.to_path_buf(),
        message,
    };
    if plot.panel_size.0 < 200 || plot.panel_size.1 < 150 {
        return Err(invalid(format!(
            "panel_size must be at least 200x150 pixels, got {}x{}",
            plot.panel_size.0, plot.panel_size.1
        )));
    }
    if plot.incident_deg.len() > 30 {
        return Err(invalid(format!(
            "at most 30 incident angles (panels), got {}",
            plot.incident_deg.len()
        )));
    }
    if let Some(t) = plot
        .incident_deg
        .iter()
        .find(|t| !(**t >= 0.0 && **t < 90.0))
    {
        return Err(invalid(format!(
            "incident angles must be in [0, 90) degrees, got {t}"
        )));
    }
    let panels = polar_panels(plot);
    let n = panels.len().max(1);
    let cols = n.min(3) as u32;
    let rows = n.div_ceil(3) as u32;
    // Widen the figure (panels share the extra width) when the title or legend would not fit
    // above or below the panels, e.g. one panel with several labelled curves.
    let size = (
        (cols * plot.panel_size.0).max(min_figure_width(plot)),
        TITLE_H + rows * plot.panel_size.1 + LEGEND_H,
    );
    if let Some(dir) = base.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| PlotError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    let figure = PolarFigure {
        plot,
        panels: &panels,
        cols: cols as usize,
    };
    let mut written = Vec::new();
    for f in formats {
        let path = match f {
            PlotFormat::Png => base.with_extension("png"),
            PlotFormat::Svg => base.with_extension("svg"),
        };
        match f {
            PlotFormat::Png => write_png(&figure, size, &path)?,
            PlotFormat::Svg => write_svg(&figure, size, &path)?,
        }
        written.push(path);
    }
    Ok(written)
}

/// Width in pixels of `text` in the sans-serif font at `size` points (a rough estimate when
/// the font cannot measure it).
fn text_width(text: &str, size: f64) -> u32 {
    ("sans-serif", size)
        .into_font()
        .box_size(text)
        .map(|(w, _)| w)
        .unwrap_or_else(|_| (text.chars().count() as f64 * size * 0.6) as u32)
}

/// The narrowest figure that holds the title, the legend row and the note under it (the
/// layout of [`draw_figure`] and [`draw_legend`]).
fn min_figure_width(plot: &PolarPlot) -> u32 {
    let title = text_width(&plot.title, 22.0) + 40;
    let entries = plot
        .measured
        .iter()
        .chain(plot.dropped.iter())
        .map(|m| m.label)
        .chain(plot.curves.iter().map(|c| c.label.as_str()));
    let legend = 20 + entries.map(|l| 26 + text_width(l, 15.0) + 36).sum::<u32>();
    let note = text_width(LEGEND_NOTE, 11.0) + 40;
    title.max(legend).max(note)
}

/// The explanation under the legend.
const LEGEND_NOTE: &str = "radius: BRDF value; angle: exitant direction from the normal (+ = forward side); dashed grey: incident direction";

/// Height in pixels of the title strip.
const TITLE_H: u32 = 44;
/// Height in pixels of the legend strip.
const LEGEND_H: u32 = 46;

fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &PolarPlot,
    panels: &[PolarPanel],
    cols: usize,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (w, h) = root.dim_in_pixel();
    let (title, rest) = root.split_vertically(TITLE_H);
    let (body, legend) = rest.split_vertically(h - TITLE_H - LEGEND_H);
    title
        .draw(&Text::new(
            plot.title.as_str(),
            (w as i32 / 2, 12),
            ("sans-serif", 22)
                .into_font()
                .color(&BLACK)
                .pos(text_pos(HPos::Center, VPos::Top)),
        ))
        .map_err(e)?;
    let rows = panels.len().div_ceil(cols.max(1)).max(1);
    let areas = body.split_evenly((rows, cols.max(1)));
    for (panel, area) in panels.iter().zip(&areas) {
        draw_panel(area, plot, panel)?;
    }
    draw_legend(&legend, plot)
}

fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &PolarPlot,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let font = ("sans-serif", 15)
        .into_font()
        .color(&BLACK)
        .pos(text_pos(HPos::Left, VPos::Center));
    let y = 22;
    let mut x = 20;
    // Advance per entry: the label's measured width plus the marker and a gap (a rough
    // estimate when the backend cannot measure).
    let advance = |label: &str| {
        let w = area
            .estimate_text_size(label, &font)
            .map(|(w, _)| w as i32)
            .unwrap_or(label.chars().count() as i32 * 8);
        26 + w + 36
    };
    if let Some(m) = plot.measured {
        area.draw(&Circle::new((x + 10, y), 4, m.color.filled()))
            .map_err(e)?;
        area.draw(&Text::new(m.label, (x + 26, y), font.clone()))
            .map_err(e)?;
        x += advance(m.label);
    }
    if let Some(m) = plot.dropped {
        area.draw(&Circle::new((x + 10, y), 5, m.color.stroke_width(2)))
            .map_err(e)?;
        area.draw(&Text::new(m.label, (x + 26, y), font.clone()))
            .map_err(e)?;
        x += advance(m.label);
    }
    for c in &plot.curves {
        let style = c.color.stroke_width(2);
        if c.dashed {
            area.draw(&PathElement::new(vec![(x, y), (x + 8, y)], style))
                .map_err(e)?;
            area.draw(&PathElement::new(vec![(x + 13, y), (x + 21, y)], style))
                .map_err(e)?;
        } else {
            area.draw(&PathElement::new(vec![(x, y), (x + 21, y)], style))
                .map_err(e)?;
        }
        area.draw(&Text::new(c.label.as_str(), (x + 26, y), font.clone()))
            .map_err(e)?;
        x += advance(&c.label);
    }
    area.draw(&Text::new(
        LEGEND_NOTE,
        (20, y + 16),
        ("sans-serif", 11)
            .into_font()
            .color(&GRID_TEXT)
            .pos(text_pos(HPos::Left, VPos::Center)),
    ))
    .map_err(e)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polar::slice::tests::{dir, synthetic_slice};
    use crate::polar::{PolarCurve, PolarMeasured, RadiusScale};
    use brdf_model::{BrdfParams, DataSet, Lobe, named_params};

    #[test]
    fn files_are_written() {
        let d = synthetic_slice();
        let mut plot = PolarPlot::new("test", vec![20.0, 40.0, 70.0, 0.0]);
        plot.measured = Some(PolarMeasured {
            label: "measured",
            data: &d,
            color: RGBColor(31, 119, 180),
        });
        plot.curves.push(PolarCurve {
            label: "Table 6".into(),
            params: named_params("paper-bluepaint").unwrap().into(),
            color: RGBColor(214, 39, 40),
            dashed: false,
        });
        plot.curves.push(PolarCurve {
            label: "overflow".into(),
            params: BrdfParams {
                kd: 0.1,
                lobes: vec![Lobe::isotropic(-1.5, 1.5, 10000.0)],
            }
            .into(),
            color: BLACK,
            dashed: true,
        });
        let mut over = DataSet::new();
        over.push(dir(40.0, 0.0), dir(40.0, 180.0), 5.0);
        plot.dropped = Some(PolarMeasured {
            label: "dropped",
            data: &over,
            color: RGBColor(31, 119, 180),
        });
        plot.radius = RadiusScale::Measured(1.2);
        let dir = tempfile::tempdir().unwrap();
        let files = draw_polar(
            &plot,
            &dir.path().join("p/fig18"),
            &[PlotFormat::Png, PlotFormat::Svg],
        )
        .unwrap();
        assert_eq!(files.len(), 2);
        for f in &files {
            assert!(std::fs::metadata(f).unwrap().len() > 1000, "{f:?}");
        }
        let panels = polar_panels(&plot);
        assert_eq!(panels.len(), 4);
        let mut bad = plot.clone();
        bad.incident_deg = vec![95.0];
        assert!(draw_polar(&bad, &dir.path().join("bad"), &[PlotFormat::Png]).is_err());
        bad.incident_deg = vec![10.0];
        bad.panel_size = (0, 0);
        assert!(draw_polar(&bad, &dir.path().join("bad"), &[PlotFormat::Png]).is_err());
        // Dropped samples are selected per panel but never set the radius.
        assert_eq!(panels[1].dropped.len(), 1);
        assert!(panels[0].dropped.is_empty());
        assert!((panels[1].r_max - 1.2 * 0.5).abs() < 1e-12);
        // No measured samples at 70 degrees: the radius comes from the (finite) curves.
        assert!(panels[2].measured.is_empty() && panels[2].r_max.is_finite());
    }
}
