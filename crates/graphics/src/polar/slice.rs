//! The plane of incidence: the samples in it, the incident angles measured, the model along it.

use std::collections::BTreeMap;

use brdf_model::{DataSet, Params};

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
pub(super) fn incident_dir(theta_i_deg: f64, sel: &SliceSelection) -> [f64; 3] {
    let (a, _) = sel.axes();
    let (s, c) = theta_i_deg.to_radians().sin_cos();
    [s * a[0], s * a[1], c]
}

/// The exitant direction at signed angle `theta_o_deg` (positive = forward side).
pub(super) fn exitant_dir(theta_o_deg: f64, sel: &SliceSelection) -> [f64; 3] {
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
/// each has, in increasing order. Use it to choose the panels of a [`PolarPlot`](super::PolarPlot).
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
    params: &Params,
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use brdf_model::{BrdfParams, Lobe};

    pub(crate) fn dir(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
        let (st, ct) = theta_deg.to_radians().sin_cos();
        let (sp, cp) = phi_deg.to_radians().sin_cos();
        [st * cp, st * sp, ct]
    }

    /// Rows 0..: a known layout of in-plane and out-of-plane samples.
    pub(crate) fn synthetic_slice() -> DataSet {
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
        let phong: Params = BrdfParams {
            kd: 0.0,
            lobes: vec![Lobe::isotropic(-1.0, 1.0, 50.0)],
        }
        .into();
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
}
