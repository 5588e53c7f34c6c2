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

mod figure;
mod panel;
mod plot;
mod slice;

pub use figure::draw_polar;
pub use plot::{PolarCurve, PolarMeasured, PolarPanel, PolarPlot, RadiusScale, polar_panels};
pub use slice::{
    GRAZING_DEG, InPlaneSample, SliceSelection, default_incident_angles, incident_angles,
    model_slice, select_in_plane,
};
