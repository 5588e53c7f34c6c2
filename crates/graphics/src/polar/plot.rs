//! What a polar figure shows ([`PolarPlot`] and its parts) and the numbers behind each panel.

use brdf_model::{DataSet, Params};
use plotters::style::RGBColor;

use super::slice::{InPlaneSample, SliceSelection, model_slice, select_in_plane};

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
    pub params: Params,
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
