//! Polar plots of a BRDF in the plane of incidence (the paper's Figure 18).
//!
//! The plane of incidence contains the surface normal and the incident direction `u`, whose
//! azimuth is `phi_i` (0 for Cornell data). Exitant directions `v` in that plane are described
//! by one signed angle from the normal, `theta_o`: **positive on the forward (mirror) side**,
//! the side opposite to the incident direction, negative on the incident (back-scattering)
//! side. The mirror direction is therefore `theta_o = +theta_i`.
//!
//! A panel per incident angle shows the BRDF value as the radius against `theta_o` as the angle
//! from the vertical (the normal), drawn on a Cartesian chart at
//! `(x, y) = (r sin theta_o, r cos theta_o)`: measured samples lying in (or near) the plane
//! ([`select_in_plane`]) as dots, and any number of model curves ([`model_slice`]). The
//! incident direction is the dashed grey ray on the left.
//!
//! Cornell gonioreflectometer files (`experiments/data/*.brdf`) have `phi_i = 0`, incident
//! angles 10, 20, ..., 80 degrees and, at each, 12-16 exitant directions exactly in the
//! plane (`phi_s` = 0 or 180 degrees, `theta_s` = 0, 8.1, 16.3, ..., 79 degrees); the
//! paper's angles 0/35/65 are not measured there ([`incident_angles`] lists what is).
//!
//! API: [`SliceSelection`], [`select_in_plane`], [`incident_angles`],
//! [`default_incident_angles`], [`model_slice`],
//! [`PolarPlot`] (with [`PolarMeasured`], [`PolarCurve`], [`RadiusScale`]), [`polar_panels`]
//! (the numbers behind the plot) and [`draw_polar`] (PNG and/or SVG).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use brdf_model::{BrdfParams, DataSet};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::ImageFormat as PlotFormat;
use crate::chart::{PlotError, register_fonts};
use crate::files::{Figure, write_png, write_svg};

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

/// Which samples count as lying in the plane of incidence at a given incident angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliceSelection {
    /// Azimuth of the plane of incidence in degrees (0 for Cornell data).
    pub phi_i_deg: f64,
    /// Maximum angle in degrees between a sample's incident direction and the requested one.
    pub incident_tol_deg: f64,
    /// Maximum angle in degrees between a sample's exitant direction and the plane.
    pub plane_tol_deg: f64,
}

impl Default for SliceSelection {
    /// `phi_i = 0`, 2.5 degrees around the incident direction and 2 degrees off the plane:
    /// exact for gridded data such as Cornell's, a thin slice of scattered (synthetic) data.
    fn default() -> Self {
        SliceSelection {
            phi_i_deg: 0.0,
            incident_tol_deg: 2.5,
            plane_tol_deg: 2.0,
        }
    }
}

impl SliceSelection {
    /// Unit vectors along the plane's in-surface axis (toward the incident side) and normal.
    fn axes(&self) -> ([f64; 3], [f64; 3]) {
        let (s, c) = self.phi_i_deg.to_radians().sin_cos();
        ([c, s, 0.0], [-s, c, 0.0])
    }
}

/// One measured sample in the plane of incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InPlaneSample {
    /// Row of the sample in the data set.
    pub index: usize,
    /// Its incident angle from the normal, degrees.
    pub theta_i_deg: f64,
    /// Its signed exitant angle, degrees (positive on the forward side; see the module docs).
    pub theta_o_deg: f64,
    /// Its measured value.
    pub value: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Angle in degrees between unit vectors (clamped so rounding cannot give NaN).
fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    dot(a, b).clamp(-1.0, 1.0).acos().to_degrees()
}

/// The incident direction at `theta_i_deg` in the plane of `sel`.
fn incident_dir(theta_i_deg: f64, sel: &SliceSelection) -> [f64; 3] {
    let (a, _) = sel.axes();
    let (s, c) = theta_i_deg.to_radians().sin_cos();
    [s * a[0], s * a[1], c]
}

/// The exitant direction at signed angle `theta_o_deg` (positive = forward side).
fn exitant_dir(theta_o_deg: f64, sel: &SliceSelection) -> [f64; 3] {
    let (a, _) = sel.axes();
    let (s, c) = theta_o_deg.to_radians().sin_cos();
    [-s * a[0], -s * a[1], c]
}

/// Signed exitant angle of `v` in the plane of `sel` and its angle off the plane, degrees.
fn exitant_angles(v: [f64; 3], sel: &SliceSelection) -> (f64, f64) {
    let (a, b) = sel.axes();
    let off = dot(v, b).clamp(-1.0, 1.0).asin().abs().to_degrees();
    let signed = (-dot(v, a)).atan2(v[2]).to_degrees();
    (signed, off)
}

/// The samples of `data` whose incident direction lies within `sel.incident_tol_deg` of the
/// direction at `theta_i_deg` in the plane of incidence and whose exitant direction lies within
/// `sel.plane_tol_deg` of that plane, sorted by signed exitant angle. Samples with a non-finite
/// value or direction are skipped.
pub fn select_in_plane(
    data: &DataSet,
    theta_i_deg: f64,
    sel: &SliceSelection,
) -> Vec<InPlaneSample> {
    let target = incident_dir(theta_i_deg, sel);
    let mut out = Vec::new();
    for i in 0..data.len() {
        let (u, v, value) = (data.u(i), data.v(i), data.value(i));
        if !(value.is_finite() && u.iter().chain(v.iter()).all(|c| c.is_finite())) {
            continue;
        }
        if angle_deg(u, target) > sel.incident_tol_deg {
            continue;
        }
        let (theta_o_deg, off) = exitant_angles(v, sel);
        if off > sel.plane_tol_deg {
            continue;
        }
        out.push(InPlaneSample {
            index: i,
            theta_i_deg: u[2].clamp(-1.0, 1.0).acos().to_degrees(),
            theta_o_deg,
            value,
        });
    }
    out.sort_by(|p, q| p.theta_o_deg.total_cmp(&q.theta_o_deg));
    out
}

/// The incident angles (degrees, rounded to 0.1) at which `data` has samples with both
/// directions within `sel.plane_tol_deg` of the plane of incidence, with how many such samples
/// each has, in increasing order. Use it to choose the panels of a [`PolarPlot`].
pub fn incident_angles(data: &DataSet, sel: &SliceSelection) -> Vec<(f64, usize)> {
    let (a, b) = sel.axes();
    let mut counts: BTreeMap<i64, usize> = BTreeMap::new();
    for i in 0..data.len() {
        let (u, v) = (data.u(i), data.v(i));
        if !u.iter().chain(v.iter()).all(|c| c.is_finite()) {
            continue;
        }
        let u_off = dot(u, b).clamp(-1.0, 1.0).asin().abs().to_degrees();
        // Normal incidence lies in every plane; otherwise u must be on the plane's incident side.
        let theta_i = u[2].clamp(-1.0, 1.0).acos().to_degrees();
        let on_side = dot(u, a) >= 0.0 || theta_i < sel.plane_tol_deg;
        if u_off > sel.plane_tol_deg || !on_side {
            continue;
        }
        if exitant_angles(v, sel).1 > sel.plane_tol_deg {
            continue;
        }
        *counts.entry((theta_i * 10.0).round() as i64).or_default() += 1;
    }
    counts
        .into_iter()
        .map(|(k, n)| (k as f64 / 10.0, n))
        .collect()
}

/// Incident angles at or above this are grazing: measurements there are least reliable (the
/// paper's Figure 18 stops at 65 degrees), so [`default_incident_angles`] avoids them.
pub const GRAZING_DEG: f64 = 75.0;

/// Up to `count` incident angles spread evenly (first, last and evenly in between) over the
/// `available` ones (as returned by [`incident_angles`]), for a plot's default panels.
///
/// Angles with fewer than 3 in-plane samples are ignored when others have more (a panel of one
/// dot says little; scattered data has many such angles), and grazing angles (at or above
/// [`GRAZING_DEG`]) are used only, least grazing first, when fewer than `count` others exist.
/// Cornell data (10, 20, ..., 80 degrees) gives 10, 40 and 70 for `count = 3`. Empty when
/// `available` is.
pub fn default_incident_angles(available: &[(f64, usize)], count: usize) -> Vec<f64> {
    let mut cand: Vec<f64> = available.iter().filter(|a| a.1 >= 3).map(|a| a.0).collect();
    if cand.is_empty() {
        cand = available.iter().map(|a| a.0).collect();
    }
    let (mut below, grazing): (Vec<f64>, Vec<f64>) =
        cand.into_iter().partition(|t| *t < GRAZING_DEG);
    if below.len() < count {
        // Too few: complete with the least grazing angles (`available` is ascending).
        below.extend(grazing.into_iter().take(count - below.len()));
    }
    let cand = below;
    if cand.len() <= count || count < 2 {
        return cand.into_iter().take(count).collect();
    }
    let last = (cand.len() - 1) as f64;
    let mut out: Vec<f64> = (0..count)
        .map(|k| cand[(k as f64 * last / (count - 1) as f64).round() as usize])
        .collect();
    out.dedup();
    out
}

/// The model's values in the plane of incidence at `theta_i_deg`: `steps` points (at least 2)
/// `(theta_o_deg, f)` evenly spaced from -90 to +90 degrees (signed as in the module docs).
/// Non-finite values (overflowing lobes) are returned as they are; plots skip them.
pub fn model_slice(
    params: &BrdfParams,
    theta_i_deg: f64,
    sel: &SliceSelection,
    steps: usize,
) -> Vec<(f64, f64)> {
    let steps = steps.max(2);
    let u = incident_dir(theta_i_deg, sel);
    (0..steps)
        .map(|k| {
            let t = -90.0 + 180.0 * k as f64 / (steps - 1) as f64;
            (t, params.value(u, exitant_dir(t, sel)))
        })
        .collect()
}

/// Measured data to show as dots.
#[derive(Clone, Copy, Debug)]
pub struct PolarMeasured<'a> {
    /// Legend text.
    pub label: &'a str,
    /// The data set (already filtered as wanted).
    pub data: &'a DataSet,
    /// Dot colour.
    pub color: RGBColor,
}

/// A model curve.
#[derive(Clone, Debug)]
pub struct PolarCurve {
    /// Legend text.
    pub label: String,
    /// The BRDF.
    pub params: BrdfParams,
    /// Line colour.
    pub color: RGBColor,
    /// Dashed instead of solid.
    pub dashed: bool,
}

/// How the radius axis is scaled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RadiusScale {
    /// Everything drawn fits: the largest measured or model value (the default).
    Auto,
    /// This many times the largest measured value in the panel (model curves beyond it are cut
    /// at the rim; useful when a model overshoots at grazing angles). Falls back to `Auto`
    /// when the panel has no measured samples.
    Measured(f64),
    /// A fixed radius.
    Fixed(f64),
}

/// A figure of polar panels, one per incident angle.
#[derive(Clone, Debug)]
pub struct PolarPlot<'a> {
    /// Title above the panels.
    pub title: String,
    /// Incident angles in degrees, one panel each (in this order, three per row).
    pub incident_deg: Vec<f64>,
    /// Sample selection (plane azimuth and tolerances).
    pub selection: SliceSelection,
    /// Measured data, if any.
    pub measured: Option<PolarMeasured<'a>>,
    /// Measured samples a filter removed before fitting (e.g. values above a cap), if any:
    /// drawn as hollow circles so the reader sees what the fits never saw. They never set the
    /// radius; those beyond the rim sit on it, labelled with their value.
    pub dropped: Option<PolarMeasured<'a>>,
    /// Model curves (the first is drawn on top).
    pub curves: Vec<PolarCurve>,
    /// Radius scaling.
    pub radius: RadiusScale,
    /// Use one radius for all panels (the largest) instead of one per panel.
    pub shared_radius: bool,
    /// Size in pixels of one panel.
    pub panel_size: (u32, u32),
}

impl<'a> PolarPlot<'a> {
    /// A plot with default selection, automatic per-panel radius, 540x340 panels, no data and
    /// no curves.
    pub fn new(title: impl Into<String>, incident_deg: Vec<f64>) -> Self {
        PolarPlot {
            title: title.into(),
            incident_deg,
            selection: SliceSelection::default(),
            measured: None,
            dropped: None,
            curves: Vec::new(),
            radius: RadiusScale::Auto,
            shared_radius: false,
            panel_size: (540, 340),
        }
    }
}

/// The numbers behind one panel.
#[derive(Clone, Debug, PartialEq)]
pub struct PolarPanel {
    /// Incident angle, degrees.
    pub theta_i_deg: f64,
    /// Measured samples in the plane (empty without measured data).
    pub measured: Vec<InPlaneSample>,
    /// Dropped samples in the plane (empty without [`PolarPlot::dropped`]).
    pub dropped: Vec<InPlaneSample>,
    /// One [`model_slice`] per curve, in the order of [`PolarPlot::curves`].
    pub curves: Vec<Vec<(f64, f64)>>,
    /// Radius of the outer ring.
    pub r_max: f64,
}

/// Points per model curve (1 degree apart).
const CURVE_STEPS: usize = 181;

/// Computes every panel of `plot`: selected samples, model curves and the radius.
pub fn polar_panels(plot: &PolarPlot) -> Vec<PolarPanel> {
    let mut panels: Vec<PolarPanel> = plot
        .incident_deg
        .iter()
        .map(|&ti| {
            let measured = plot
                .measured
                .map(|m| select_in_plane(m.data, ti, &plot.selection))
                .unwrap_or_default();
            let dropped = plot
                .dropped
                .map(|m| select_in_plane(m.data, ti, &plot.selection))
                .unwrap_or_default();
            let curves: Vec<Vec<(f64, f64)>> = plot
                .curves
                .iter()
                .map(|c| model_slice(&c.params, ti, &plot.selection, CURVE_STEPS))
                .collect();
            let max_of = |it: &mut dyn Iterator<Item = f64>| {
                it.filter(|v| v.is_finite()).fold(0.0f64, f64::max)
            };
            let m_max = max_of(&mut measured.iter().map(|s| s.value));
            let c_max = max_of(&mut curves.iter().flatten().map(|p| p.1));
            let r = match plot.radius {
                RadiusScale::Fixed(r) => r,
                RadiusScale::Measured(k) if m_max > 0.0 => k * m_max,
                _ => 1.05 * m_max.max(c_max),
            };
            PolarPanel {
                theta_i_deg: ti,
                measured,
                dropped,
                curves,
                r_max: if r > 0.0 && r.is_finite() { r } else { 1.0 },
            }
        })
        .collect();
    if plot.shared_radius {
        let r = panels.iter().map(|p| p.r_max).fold(0.0, f64::max);
        for p in &mut panels {
            p.r_max = r;
        }
    }
    panels
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

const GRID: RGBColor = RGBColor(215, 215, 215);
const GRID_TEXT: RGBColor = RGBColor(90, 90, 90);

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

fn text_pos(h: HPos, v: VPos) -> Pos {
    Pos::new(h, v)
}

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

fn draw_panel<DB: DrawingBackend>(
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

    use super::*;
    use brdf_model::{Lobe, named_params};

    fn dir(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
        let (st, ct) = theta_deg.to_radians().sin_cos();
        let (sp, cp) = phi_deg.to_radians().sin_cos();
        [st * cp, st * sp, ct]
    }

    /// Rows 0..: a known layout of in-plane and out-of-plane samples.
    fn synthetic_slice() -> DataSet {
        let mut d = DataSet::new();
        // 0: in plane, forward side (phi_s = 180), theta_i 40.
        d.push(dir(40.0, 0.0), dir(30.0, 180.0), 0.5);
        // 1: in plane, back side.
        d.push(dir(40.0, 0.0), dir(20.0, 0.0), 0.2);
        // 2: 1 degree off the plane: still selected with the default 2 degree tolerance.
        d.push(
            dir(40.0, 0.0),
            dir(60.0, 180.0 - 1.0 / 60f64.to_radians().sin()),
            0.3,
        );
        // 3: exitant far out of the plane.
        d.push(dir(40.0, 0.0), dir(30.0, 90.0), 0.9);
        // 4: another incident angle.
        d.push(dir(20.0, 0.0), dir(20.0, 180.0), 0.7);
        // 5: incident azimuth 90 degrees (a different plane of incidence).
        d.push(dir(40.0, 90.0), dir(30.0, 270.0), 0.6);
        // 6: exitant at the normal.
        d.push(dir(40.0, 0.0), [0.0, 0.0, 1.0], 0.25);
        // 7: non-finite value.
        d.push(dir(40.0, 0.0), dir(10.0, 0.0), f64::NAN);
        d
    }

    #[test]
    fn in_plane_selection_picks_the_right_samples() {
        let d = synthetic_slice();
        let sel = SliceSelection::default();
        let s = select_in_plane(&d, 40.0, &sel);
        let idx: Vec<usize> = s.iter().map(|p| p.index).collect();
        assert_eq!(idx, vec![1, 6, 0, 2], "{s:?}");
        let ang: Vec<f64> = s.iter().map(|p| p.theta_o_deg).collect();
        assert!((ang[0] + 20.0).abs() < 1e-9, "{ang:?}");
        assert!(ang[1].abs() < 1e-9);
        assert!((ang[2] - 30.0).abs() < 1e-9);
        assert!((ang[3] - 60.0).abs() < 0.05);
        assert!((s[0].theta_i_deg - 40.0).abs() < 1e-9);
        // A tighter plane tolerance drops the sample 1 degree off the plane.
        let tight = SliceSelection {
            plane_tol_deg: 0.5,
            ..sel
        };
        assert_eq!(select_in_plane(&d, 40.0, &tight).len(), 3);
        // The plane at azimuth 90 degrees selects only row 5.
        let rotated = SliceSelection {
            phi_i_deg: 90.0,
            ..sel
        };
        let r: Vec<usize> = select_in_plane(&d, 40.0, &rotated)
            .iter()
            .map(|p| p.index)
            .collect();
        assert_eq!(r, vec![5]);
        assert_eq!(select_in_plane(&d, 20.0, &sel)[0].index, 4);
        assert!(select_in_plane(&d, 70.0, &sel).is_empty());
        let angles = incident_angles(&d, &sel);
        assert_eq!(angles, vec![(20.0, 1), (40.0, 5)]);
    }

    #[test]
    fn default_angles_spread_over_the_data() {
        let cornell: Vec<(f64, usize)> = (1..=8).map(|k| (10.0 * k as f64, 15)).collect();
        assert_eq!(default_incident_angles(&cornell, 3), vec![10.0, 40.0, 70.0]);
        assert_eq!(default_incident_angles(&cornell, 1), vec![10.0]);
        // Too few non-grazing angles: grazing ones are used rather than fewer panels.
        let few = [(30.0, 5), (70.0, 5), (80.0, 5)];
        assert_eq!(default_incident_angles(&few, 3), vec![30.0, 70.0, 80.0]);
        assert_eq!(default_incident_angles(&few, 2), vec![30.0, 70.0]);
        // Angles with one or two samples only count when nothing better exists.
        let sparse = [(5.0, 1), (20.0, 9), (21.0, 1), (50.0, 4)];
        assert_eq!(default_incident_angles(&sparse, 3), vec![20.0, 50.0]);
        let scattered = [(12.3, 1), (47.9, 1)];
        assert_eq!(default_incident_angles(&scattered, 3), vec![12.3, 47.9]);
        let sparse_grazing = [(20.4, 1), (43.1, 1), (76.9, 1), (89.7, 1)];
        assert_eq!(
            default_incident_angles(&sparse_grazing, 3),
            vec![20.4, 43.1, 76.9]
        );
        assert!(default_incident_angles(&[], 3).is_empty());
    }

    #[test]
    fn model_slice_peaks_at_the_mirror_direction() {
        let phong = BrdfParams {
            kd: 0.0,
            lobes: vec![Lobe::isotropic(-1.0, 1.0, 50.0)],
        };
        let sel = SliceSelection::default();
        let s = model_slice(&phong, 35.0, &sel, 181);
        assert_eq!(s.len(), 181);
        assert_eq!(s[0].0, -90.0);
        assert_eq!(s[180].0, 90.0);
        let peak = s
            .iter()
            .copied()
            .fold((0.0, f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
        assert!((peak.0 - 35.0).abs() < 1e-9, "{peak:?}");
        assert!((peak.1 - 1.0).abs() < 1e-9);
        // Consistent with select_in_plane: a sample taken from the curve has the same angle.
        let mut d = DataSet::new();
        d.push(incident_dir(35.0, &sel), exitant_dir(-50.0, &sel), 1.0);
        assert!((select_in_plane(&d, 35.0, &sel)[0].theta_o_deg + 50.0).abs() < 1e-9);
    }

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
            params: named_params("paper-bluepaint").unwrap(),
            color: RGBColor(214, 39, 40),
            dashed: false,
        });
        plot.curves.push(PolarCurve {
            label: "overflow".into(),
            params: BrdfParams {
                kd: 0.1,
                lobes: vec![Lobe::isotropic(-1.5, 1.5, 10000.0)],
            },
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
