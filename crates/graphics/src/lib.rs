//! Graphics of brdf-sls: plain-data charts, polar plots of BRDF slices and renderings of a lit
//! surface, drawn with plotters to PNG and SVG using the DejaVu Sans font embedded in the
//! binary (no system fonts needed). Nothing here knows about experiments or their statistics:
//! callers pass numbers, parameters and data sets.
//!
//! - [`chart`]: line and point charts with bands and reference lines (RTDs, sweeps, traces).
//! - [`polar`]: the BRDF in the plane of incidence, measured against fitted (Figure 18).
//! - [`render`]: a flat square lit by a point light, seen by a pinhole camera (Figures 8, 12).
//! - [`style`]: line and marker styles of series.
//! - [`legend`]: legends in rows under a chart, outside its plotting area.
//! - [`files`]: atomic writes of output files, figures as PNG and SVG, their font and errors.

pub mod chart;
pub mod files;
pub mod legend;
pub mod polar;
pub mod render;
pub mod style;
pub mod target;

pub use files::PlotError;
/// Colours of series and curves.
pub use plotters::style::RGBColor;

/// Image formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ImageFormat {
    /// PNG bitmap.
    Png,
    /// SVG vector.
    Svg,
}

impl std::str::FromStr for ImageFormat {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "png" => Ok(ImageFormat::Png),
            "svg" => Ok(ImageFormat::Svg),
            other => Err(format!(
                "unknown image format `{other}` (expected png or svg)"
            )),
        }
    }
}
