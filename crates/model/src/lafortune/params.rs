//! The Lafortune family's typed parameters and the published parameter sets.

use crate::params::{ParamError, Reflectance, check};
use serde::{Deserialize, Serialize};

/// Table 1 bounds of `kd` (the same as a Lafortune [`crate::Layout`]'s defaults).
pub const KD_BOUNDS: (f64, f64) = (0.0, 1.0);
/// Table 1 bounds of `cx`, `cy` and `cz`.
pub const C_BOUNDS: (f64, f64) = (-1.5, 1.5);
/// Table 1 bounds of the exponent `n`.
pub const N_BOUNDS: (f64, f64) = (0.0, 10000.0);
/// Table 1 bounds of the pan angle, degrees.
pub const PAN_BOUNDS: (f64, f64) = (-90.0, 90.0);

/// One generalised cosine lobe in physical coordinates.
///
/// The lobe contributes `max(0, cx u'x v'x + cy u'y v'y + cz uz vz)^n`, where `u'`, `v'` are the
/// directions rotated about the normal so that the lobe's x axis lies at angle `pan_deg` from the
/// surface x axis: `u'x = cos(p) ux + sin(p) uy`, `u'y = -sin(p) ux + cos(p) uy`.
/// An isotropic lobe has `cx == cy` (then `pan_deg` has no effect).
///
/// Deserialising refuses unknown fields, so that a typo (`pan = 45`) is an error rather than
/// a silently ignored key.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lobe {
    /// Weight of the x product (after rotation).
    pub cx: f64,
    /// Weight of the y product (after rotation).
    pub cy: f64,
    /// Weight of the normal (z) product.
    pub cz: f64,
    /// Specular exponent (Table 1: `[0, 10000]`).
    pub n: f64,
    /// Rotation of the lobe's x axis about the normal, in degrees (Table 1: `[-90, 90]`). A
    /// positive pan turns the lobe's axes counter-clockwise seen from above (from +x towards
    /// +y): the lobe turned by `+phi` at directions turned by `+phi` is the unturned lobe at
    /// the unturned directions. `(cx, cy, pan)` and `(cy, cx, pan + 90)` are the same lobe
    /// (docs/model.md, "Equivalent parameter sets"; tests/equivalences.rs).
    #[serde(default)]
    pub pan_deg: f64,
}

impl Lobe {
    /// An isotropic lobe (`cx = cy = cxy`, no pan).
    pub fn isotropic(cxy: f64, cz: f64, n: f64) -> Self {
        Lobe {
            cx: cxy,
            cy: cxy,
            cz,
            n,
            pan_deg: 0.0,
        }
    }

    /// The lobe's value `max(0, d)^n` at directions `u`, `v` (scalar reference using `powf`).
    ///
    /// `d <= 0` gives 0 for every `n`, including `n = 0` (the clamp is applied first).
    pub fn value(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        let (s, c) = self.pan_deg.to_radians().sin_cos();
        let ux = c * u[0] + s * u[1];
        let uy = -s * u[0] + c * u[1];
        let vx = c * v[0] + s * v[1];
        let vy = -s * v[0] + c * v[1];
        let d = self.cx * (ux * vx) + self.cy * (uy * vy) + self.cz * (u[2] * v[2]);
        if d > 0.0 { d.powf(self.n) } else { 0.0 }
    }
}

/// A complete parameter set: the constant diffuse term plus any number of lobes.
///
/// Deserialising refuses unknown fields; it does not check values: call
/// [`BrdfParams::validate`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BrdfParams {
    /// The constant BRDF term (the paper's "Diffuse"); the diffuse albedo is `rho_d = pi * kd`.
    pub kd: f64,
    /// The specular lobes.
    pub lobes: Vec<Lobe>,
}

impl BrdfParams {
    /// `f(u, v) = kd + sum_k max(0, d_k)^n_k` (scalar reference using `powf`; both vectors point
    /// away from the surface, z is the normal).
    pub fn value(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        self.kd + self.lobes.iter().map(|l| l.value(u, v)).sum::<f64>()
    }

    /// Checks that every value is finite and inside the paper's Table 1 box ([`KD_BOUNDS`],
    /// [`C_BOUNDS`] for cx, cy, cz, [`N_BOUNDS`], [`PAN_BOUNDS`]) and that there are at most
    /// [`MAX_LOBES`](crate::MAX_LOBES) lobes. The error names the first offending parameter, e.g.
    /// `lobe1.cz = 5: expected a finite value in [-1.5, 1.5]`.
    pub fn validate(&self) -> Result<(), ParamError> {
        check(|| "kd".into(), self.kd, KD_BOUNDS)?;
        if self.lobes.len() > crate::MAX_LOBES {
            return Err(ParamError::TooManyLobes {
                count: self.lobes.len(),
            });
        }
        for (k, l) in self.lobes.iter().enumerate() {
            let k = k + 1;
            check(|| format!("lobe{k}.cx"), l.cx, C_BOUNDS)?;
            check(|| format!("lobe{k}.cy"), l.cy, C_BOUNDS)?;
            check(|| format!("lobe{k}.cz"), l.cz, C_BOUNDS)?;
            check(|| format!("lobe{k}.n"), l.n, N_BOUNDS)?;
            check(|| format!("lobe{k}.pan"), l.pan_deg, PAN_BOUNDS)?;
        }
        Ok(())
    }

    /// The diffuse albedo `rho_d = pi * kd`.
    pub fn rho_d(&self) -> f64 {
        std::f64::consts::PI * self.kd
    }

    /// A parameter by name: `"kd"`, `"lobeK.cx"`, `"lobeK.cy"`, `"lobeK.cxy"` (= cx),
    /// `"lobeK.cz"`, `"lobeK.n"`, `"lobeK.pan"` (degrees), lobes numbered from 1.
    pub fn get(&self, name: &str) -> Option<f64> {
        if name == "kd" {
            return Some(self.kd);
        }
        let (k, field) = crate::params::parse_lobe_name(name)?;
        let l = self.lobes.get(k)?;
        Some(match field {
            "cx" | "cxy" => l.cx,
            "cy" => l.cy,
            "cz" => l.cz,
            "n" => l.n,
            "pan" => l.pan_deg,
            _ => return None,
        })
    }

    /// Sets a parameter by name (see [`BrdfParams::get`]); `"lobeK.cxy"` sets both cx and cy.
    /// Returns false when the name does not exist.
    pub fn set(&mut self, name: &str, value: f64) -> bool {
        if name == "kd" {
            self.kd = value;
            return true;
        }
        let Some((k, field)) = crate::params::parse_lobe_name(name) else {
            return false;
        };
        let Some(l) = self.lobes.get_mut(k) else {
            return false;
        };
        match field {
            "cx" => l.cx = value,
            "cy" => l.cy = value,
            "cxy" => {
                l.cx = value;
                l.cy = value;
            }
            "cz" => l.cz = value,
            "n" => l.n = value,
            "pan" => l.pan_deg = value,
            _ => return false,
        }
        true
    }
}

impl Reflectance for BrdfParams {
    fn value(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        BrdfParams::value(self, u, v)
    }
    fn check(&self) -> Result<(), ParamError> {
        self.validate()
    }
}

/// Names accepted by [`named_params`].
pub const NAMED_PARAMS: [&str; 4] = ["tuning", "cross", "paper-bluepaint", "pbrt-bluepaint"];

/// Published parameter sets by name:
/// - `"tuning"`: the paper's Table 2 (one anisotropic lobe, pan 45 degrees, n 20, kd 0.15);
/// - `"cross"`: Table 3 (the Table 2 lobe plus the same lobe at pan -45 degrees);
/// - `"paper-bluepaint"`: Table 6 (the paper's fit of the blue house paint at 550 nm);
/// - `"pbrt-bluepaint"`: pbrt-v1 `bluepaint.cpp`, green channel (three isotropic lobes,
///   `kd = 0.39667 / pi`).
pub fn named_params(name: &str) -> Option<BrdfParams> {
    let tuning = Lobe {
        cx: -1.0,
        cy: 0.8,
        cz: 0.96,
        n: 20.0,
        pan_deg: 45.0,
    };
    match name {
        "tuning" => Some(BrdfParams {
            kd: 0.15,
            lobes: vec![tuning],
        }),
        "cross" => Some(BrdfParams {
            kd: 0.15,
            lobes: vec![
                tuning,
                Lobe {
                    pan_deg: -45.0,
                    ..tuning
                },
            ],
        }),
        "paper-bluepaint" => Some(BrdfParams {
            kd: 0.126,
            lobes: vec![Lobe::isotropic(0.914, 0.52, 10.21)],
        }),
        "pbrt-bluepaint" => Some(BrdfParams {
            kd: 0.39667 / std::f64::consts::PI,
            lobes: vec![
                Lobe::isotropic(0.857255, 0.774290, 18.597755),
                Lobe::isotropic(-0.406681, 0.017625, 2.581499),
                Lobe::isotropic(-1.029426, 0.696530, 63.767912),
            ],
        }),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbrt_bluepaint_at_normal() {
        let p = named_params("pbrt-bluepaint").unwrap();
        let f = p.value([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]);
        assert!((f - 0.1349).abs() < 5e-5, "{f}");
        assert!((p.rho_d() - 0.39667).abs() < 1e-12);
    }

    #[test]
    fn named_access_round_trips() {
        let mut p = named_params("cross").unwrap();
        assert_eq!(p.get("lobe2.pan"), Some(-45.0));
        assert!(p.set("lobe1.cxy", 0.3));
        assert_eq!(p.get("lobe1.cy"), Some(0.3));
        assert_eq!(p.get("lobe3.cx"), None);
        assert_eq!(p.get("lobe0.cx"), None);
        assert!(!p.set("bogus", 1.0));
        for name in NAMED_PARAMS {
            assert!(named_params(name).is_some());
        }
        assert!(named_params("nope").is_none());
    }

    #[test]
    fn bounds_agree_with_layout_and_validate_names_the_parameter() {
        use crate::{Layout, LobeKind};
        let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
        assert_eq!(layout.physical_bounds("kd"), Some(KD_BOUNDS));
        for c in ["cx", "cy", "cz"] {
            assert_eq!(
                layout.physical_bounds(&format!("lobe1.{c}")),
                Some(C_BOUNDS)
            );
        }
        assert_eq!(layout.physical_bounds("lobe1.n"), Some(N_BOUNDS));
        assert_eq!(layout.physical_bounds("lobe1.pan"), Some(PAN_BOUNDS));
        for name in NAMED_PARAMS {
            named_params(name).unwrap().validate().unwrap();
        }
        let mut p = named_params("cross").unwrap();
        p.lobes[0].cz = 5.0;
        let e = p.validate().unwrap_err();
        assert_eq!(
            e.to_string(),
            "lobe1.cz = 5: expected a finite value in [-1.5, 1.5]"
        );
        p.lobes[0].cz = 0.5;
        p.lobes[1].pan_deg = f64::NAN;
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .starts_with("lobe2.pan = NaN")
        );
        p.lobes[1].pan_deg = 0.0;
        p.kd = -0.1;
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .starts_with("kd = -0.1")
        );
        p.kd = 0.1;
        p.lobes[1].n = 1e5;
        assert!(p.validate().unwrap_err().to_string().contains("[0, 10000]"));
        p.lobes = vec![Lobe::isotropic(0.0, 1.0, 1.0); crate::MAX_LOBES + 1];
        assert!(matches!(p.validate(), Err(ParamError::TooManyLobes { .. })));
    }

    #[test]
    fn reciprocity_and_clamp() {
        let p = named_params("cross").unwrap();
        let u = [0.3, -0.4, (1.0f64 - 0.25).sqrt()];
        let v = [-0.6, 0.1, (1.0f64 - 0.37).sqrt()];
        assert_eq!(p.value(u, v), p.value(v, u));
        // d <= 0 gives 0 even with n = 0.
        let l = Lobe::isotropic(0.0, -1.0, 0.0);
        assert_eq!(l.value([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]), 0.0);
    }
}
