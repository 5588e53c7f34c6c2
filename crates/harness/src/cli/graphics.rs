//! Flags of `render` and `polar`.

use std::path::PathBuf;

use brdf_graphics::ImageFormat;
use brdf_graphics::polar::RadiusScale;
use brdf_graphics::render::ToneMap;
use clap::Args;

use super::values::{Triple, enum_value};
use super::{DataArgs, ParamArgs};

/// Arguments of `brdf-sls render`. Defaults are those of `brdf_graphics::render::RenderOptions`
/// (a view chosen to show the anisotropic highlights of the `tuning` and `cross` BRDFs).
#[derive(Args)]
pub struct RenderArgs {
    /// The BRDF to render.
    #[command(flatten)]
    pub params: ParamArgs,
    /// Output PNG file (parent directories are created).
    #[arg(long, short, default_value = "render.png")]
    pub out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = brdf_graphics::render::RenderOptions::default().width)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = brdf_graphics::render::RenderOptions::default().height)]
    pub height: u32,
    /// Supersamples per pixel along each axis (S*S per pixel), 1 to 16.
    #[arg(long, value_name = "S", default_value_t = brdf_graphics::render::RenderOptions::default().supersampling)]
    pub supersampling: u32,
    /// Point light position X,Y,Z. The surface is the square |x|, |y| <= --half-size in the
    /// z = 0 plane (normal +z, the BRDF's x axis along world x); the light must have Z > 0.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true,
          default_value_t = Triple(brdf_graphics::render::RenderOptions::default().light))]
    pub light: Triple,
    /// Light intensity (>= 0; the image scales linearly with it).
    #[arg(long, allow_hyphen_values = true,
          default_value_t = brdf_graphics::render::RenderOptions::default().intensity)]
    pub intensity: f64,
    /// Camera (pinhole) position X,Y,Z, above the surface (Z > 0).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true,
          default_value_t = Triple(brdf_graphics::render::RenderOptions::default().camera))]
    pub camera: Triple,
    /// Point the camera looks at.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true,
          default_value_t = Triple(brdf_graphics::render::RenderOptions::default().look_at))]
    pub look_at: Triple,
    /// Vertical field of view in degrees, in (0, 180).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = brdf_graphics::render::RenderOptions::default().fov_deg)]
    pub fov: f64,
    /// Half the side of the square surface (> 0).
    #[arg(long, allow_hyphen_values = true,
          default_value_t = brdf_graphics::render::RenderOptions::default().plane_half_size)]
    pub half_size: f64,
    /// Multiplier of the linear radiance before tone mapping (> 0).
    #[arg(long, allow_hyphen_values = true,
          default_value_t = brdf_graphics::render::RenderOptions::default().exposure)]
    pub exposure: f64,
    /// Tone mapping: clamp (min(x, 1), brighter values clip) or reinhard (x / (1 + x)).
    #[arg(long, value_parser = enum_value::<ToneMap>, default_value = "clamp")]
    pub tone_map: ToneMap,
    /// Surface colour R,G,B (linear, multiplies the radiance; each >= 0).
    #[arg(long, value_name = "R,G,B", allow_hyphen_values = true,
          default_value_t = Triple(brdf_graphics::render::RenderOptions::default().tint))]
    pub tint: Triple,
}

impl RenderArgs {
    pub fn options(&self) -> brdf_graphics::render::RenderOptions {
        brdf_graphics::render::RenderOptions {
            width: self.width,
            height: self.height,
            supersampling: self.supersampling,
            camera: self.camera.0,
            look_at: self.look_at.0,
            fov_deg: self.fov,
            light: self.light.0,
            intensity: self.intensity,
            plane_half_size: self.half_size,
            exposure: self.exposure,
            tone_map: self.tone_map,
            tint: self.tint.0,
            ..brdf_graphics::render::RenderOptions::default()
        }
    }
}

/// Arguments of `brdf-sls polar`.
#[derive(Args)]
pub struct PolarArgs {
    /// The measured data.
    #[command(flatten)]
    pub data: DataArgs,
    /// A model to overlay: LABEL=PARAMS, PARAMS a name (tuning, cross, paper-bluepaint,
    /// pbrt-bluepaint), JSON as printed on the `json:` line of `brdf-sls fit`, or @FILE holding
    /// such JSON; repeatable. Without `LABEL=` the name (or "fit N") labels it.
    #[arg(long = "fit", value_name = "LABEL=PARAMS")]
    pub fits: Vec<String>,
    /// Also overlay the best trial (lowest RMSE) of --config from the results of `brdf-sls run`
    /// (a results directory or its trials.jsonl).
    #[arg(long, value_name = "DIR", requires = "config")]
    pub from_results: Option<PathBuf>,
    /// Configuration label for --from-results, e.g. "AED phi=1.2".
    #[arg(long, value_name = "LABEL", requires = "from_results")]
    pub config: Option<String>,
    /// Instance for --from-results (default: the experiment's only instance).
    #[arg(long, value_name = "NAME", requires = "from_results")]
    pub instance: Option<String>,
    /// Incident angles in degrees, one panel each, e.g. 10,40,70 (default: three spread over
    /// the angles the data has in-plane samples at, avoiding grazing angles).
    #[arg(
        long,
        value_name = "DEG,...",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub incident: Vec<f64>,
    /// Output base: writes BASE.png and/or BASE.svg (an extension of BASE is replaced).
    #[arg(long, short, value_name = "BASE", default_value = "polar")]
    pub out: PathBuf,
    /// Formats to write, comma-separated.
    #[arg(long, value_delimiter = ',', default_values = ["png", "svg"])]
    pub formats: Vec<ImageFormat>,
    /// Radius of each panel (linear in the BRDF value): `auto` (everything drawn fits),
    /// `measured:K` (K times the panel's largest measured value; model curves beyond it are
    /// cut at the rim) or a number (a fixed radius).
    #[arg(long, default_value = "auto", value_parser = radius)]
    pub radius: RadiusScale,
    /// Use one radius for all panels (the largest) instead of one per panel.
    #[arg(long)]
    pub shared_radius: bool,
    /// Title (default: the data file, wavelength and filter).
    #[arg(long)]
    pub title: Option<String>,
    /// Legend text of the measured data (default: "measured (FILE NAME)").
    #[arg(long)]
    pub data_label: Option<String>,
    /// Also show the samples --max-value drops (hollow circles; values beyond the rim sit on it
    /// with their value printed), to see what the fits never saw.
    #[arg(long, requires = "max_value")]
    pub show_dropped: bool,
    /// Azimuth of the plane of incidence in degrees (0 for Cornell data).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = brdf_graphics::polar::SliceSelection::default().phi_i_deg)]
    pub phi_i: f64,
    /// Largest angle in degrees between a sample's incident direction and a panel's.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = brdf_graphics::polar::SliceSelection::default().incident_tol_deg)]
    pub incident_tol: f64,
    /// Largest angle in degrees between a sample's exitant direction and the plane.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = brdf_graphics::polar::SliceSelection::default().plane_tol_deg)]
    pub plane_tol: f64,
}

/// `--radius`: `auto`, `measured:K` or a positive number.
fn radius(s: &str) -> Result<RadiusScale, String> {
    let bad = || format!("`{s}`: expected `auto`, `measured:K` (K > 0) or a positive number");
    let positive = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
    };
    let s = s.trim();
    if s.eq_ignore_ascii_case("auto") {
        Ok(RadiusScale::Auto)
    } else if let Some(k) = s.strip_prefix("measured:") {
        positive(k).map(RadiusScale::Measured).ok_or_else(bad)
    } else {
        positive(s).map(RadiusScale::Fixed).ok_or_else(bad)
    }
}
