//! Physical parameters of the model and the published parameter sets.

use serde::{Deserialize, Serialize};

/// One generalised cosine lobe in physical coordinates.
///
/// The lobe contributes `max(0, cx u'x v'x + cy u'y v'y + cz uz vz)^n`, where `u'`, `v'` are the
/// directions rotated about the normal so that the lobe's x axis lies at angle `pan_deg` from the
/// surface x axis: `u'x = cos(p) ux + sin(p) uy`, `u'y = -sin(p) ux + cos(p) uy`.
/// An isotropic lobe has `cx == cy` (then `pan_deg` has no effect).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lobe {
    /// Weight of the x product (after rotation).
    pub cx: f64,
    /// Weight of the y product (after rotation).
    pub cy: f64,
    /// Weight of the normal (z) product.
    pub cz: f64,
    /// Specular exponent (Table 1: `[0, 10000]`).
    pub n: f64,
    /// Rotation of the lobe's x axis about the normal, in degrees (Table 1: `[-90, 90]`).
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
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
        let (k, field) = parse_lobe_name(name)?;
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
        let Some((k, field)) = parse_lobe_name(name) else {
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

/// Splits `"lobe3.cz"` into `(2, "cz")` (zero-based lobe index).
pub(crate) fn parse_lobe_name(name: &str) -> Option<(usize, &str)> {
    let rest = name.strip_prefix("lobe")?;
    let (num, field) = rest.split_once('.')?;
    let k: usize = num.parse().ok()?;
    if k == 0 {
        return None;
    }
    Some((k - 1, field))
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
