//! Ngan et al.'s normalised one-lobe Lafortune fits as this crate's [`BrdfParams`].
//!
//! Ngan et al. (2005) fit, per channel `c`,
//!
//! ```text
//! f_c(u, v) = kd_c / pi
//!           + ks_c (n + 2) / (2 pi) max(0, Cxy (ux vx + uy vy) + Cz uz vz)^n / max(Cxy^2, Cz^2)^(n/2)
//! ```
//!
//! (bbm's `include/bsdfmodel/ngan.h`, lines 47-98, on top of `lafortune.h`, line 60), with
//! `kd` the Lambertian albedo, `ks` the file's `albedo`, `n` its `sharpness`, shared `Cxy`,
//! `Cz`. Both direction vectors point away from the surface, as in this crate. Because
//! `a max(0, d)^n = max(0, a^(1/n) d)^n` for `a >= 0`, the lobe is this crate's isotropic lobe
//! with
//!
//! ```text
//! s_c = (ks_c (n + 2) / (2 pi))^(1/n) / max(|Cxy|, |Cz|),   Cx = Cy = Cxy s_c,   Cz' = Cz s_c,
//! ```
//!
//! the same `n`, no pan, and the constant term `kd = kd_c / pi`.

use super::{PublishedFit, channel_index};
use brdf_io::Channel;
use brdf_model::lafortune::{BrdfParams, Lobe};
use brdf_model::lafortune::{C_BOUNDS, KD_BOUNDS, N_BOUNDS, PAN_BOUNDS};
use std::f64::consts::PI;

/// The channel used when none is given: green, as for MERL files elsewhere in the project.
pub const DEFAULT_CHANNEL: Channel = Channel::Green;

/// Why a published fit could not be converted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConvertError {
    /// The fit is of another model.
    #[error("{material} (line {line}): model `{found}`: expected `{expected}`")]
    WrongModel {
        /// Material.
        material: String,
        /// Line in the file.
        line: usize,
        /// The model needed.
        expected: String,
        /// The fit's model.
        found: String,
    },
    /// A parameter the conversion needs is missing.
    #[error("{material} (line {line}): no `{name}` parameter: expected {expected}")]
    Missing {
        /// Material.
        material: String,
        /// Line in the file.
        line: usize,
        /// Parameter name.
        name: String,
        /// What the conversion needs.
        expected: String,
    },
    /// A parameter value the conversion cannot represent.
    #[error("{material} (line {line}): {name} = {value}: expected {expected}")]
    Invalid {
        /// Material.
        material: String,
        /// Line in the file.
        line: usize,
        /// Parameter name, with the channel for per-channel values (`albedo[green]`).
        name: String,
        /// The value.
        value: f64,
        /// What the conversion needs.
        expected: String,
    },
}

/// Ngan et al.'s normalised Lafortune fit of one material, per channel (red, green, blue).
#[derive(Clone, Debug, PartialEq)]
pub struct NganLafortune {
    /// Material.
    pub material: String,
    /// Lambertian albedo (the BRDF term is `kd / pi`); 0 when the line has no Lambertian term.
    pub kd: [f64; 3],
    /// The lobe's albedo (`albedo` in the file).
    pub ks: [f64; 3],
    /// `Cxy` (shared by the channels in the published file).
    pub cxy: [f64; 3],
    /// `Cz` (shared in the published file).
    pub cz: [f64; 3],
    /// The exponent `n` (`sharpness`, shared in the published file).
    pub n: [f64; 3],
}

impl NganLafortune {
    /// Takes the values of a `NganLafortune` fit, checking that they can be converted: every
    /// value finite, `ks >= 0`, `n > 0`, and `Cxy`, `Cz` not both 0.
    pub fn from_fit(fit: &PublishedFit) -> Result<Self, ConvertError> {
        const MODEL: &str = "NganLafortune";
        if fit.model != MODEL {
            return Err(ConvertError::WrongModel {
                material: fit.material.clone(),
                line: fit.line,
                expected: MODEL.into(),
                found: fit.model.clone(),
            });
        }
        let get = |name: &str, expected: &str| {
            fit.rgb(name).ok_or_else(|| ConvertError::Missing {
                material: fit.material.clone(),
                line: fit.line,
                name: name.into(),
                expected: expected.into(),
            })
        };
        let out = NganLafortune {
            material: fit.material.clone(),
            kd: fit.diffuse.unwrap_or([0.0; 3]),
            ks: get("albedo", "the lobe's albedo (ks)")?,
            cxy: get("Cxy", "the lobe's Cxy")?,
            cz: get("Cz", "the lobe's Cz")?,
            n: get("sharpness", "the exponent n")?,
        };
        let invalid = |name: &str, k: usize, value: f64, expected: &str| ConvertError::Invalid {
            material: fit.material.clone(),
            line: fit.line,
            name: format!("{name}[{}]", ["red", "green", "blue"][k]),
            value,
            expected: expected.into(),
        };
        for k in 0..3 {
            let checks = [
                ("kd", out.kd[k], "a finite value"),
                ("albedo", out.ks[k], "a finite value >= 0"),
                ("Cxy", out.cxy[k], "a finite value"),
                ("Cz", out.cz[k], "a finite value"),
                ("sharpness", out.n[k], "a finite value > 0"),
            ];
            for (name, v, expected) in checks {
                if !v.is_finite() {
                    return Err(invalid(name, k, v, expected));
                }
            }
            if out.ks[k] < 0.0 {
                return Err(invalid("albedo", k, out.ks[k], "a finite value >= 0"));
            }
            if out.n[k] <= 0.0 {
                return Err(invalid("sharpness", k, out.n[k], "a finite value > 0"));
            }
            if out.cxy[k] == 0.0 && out.cz[k] == 0.0 {
                return Err(invalid("Cz", k, 0.0, "Cxy or Cz not 0"));
            }
        }
        Ok(out)
    }

    /// The lobe's scale `s = (ks (n + 2) / (2 pi))^(1/n) / max(|Cxy|, |Cz|)` in `channel`.
    pub fn scale(&self, channel: Channel) -> f64 {
        let k = channel_index(channel);
        let n = self.n[k];
        (self.ks[k] * (n + 2.0) / (2.0 * PI)).powf(1.0 / n)
            / self.cxy[k].abs().max(self.cz[k].abs())
    }

    /// This crate's parameters for one channel: `kd = kd_c / pi` and one isotropic lobe
    /// `Cx = Cy = Cxy s`, `Cz' = Cz s`, `n`, no pan (see [`NganLafortune::scale`]). They may lie
    /// outside the Table 1 box ([`table1_violations`] says where).
    pub fn to_params(&self, channel: Channel) -> BrdfParams {
        let k = channel_index(channel);
        let s = self.scale(channel);
        BrdfParams {
            kd: self.kd[k] / PI,
            lobes: vec![Lobe::isotropic(self.cxy[k] * s, self.cz[k] * s, self.n[k])],
        }
    }

    /// [`NganLafortune::to_params`] for [`DEFAULT_CHANNEL`] (green).
    pub fn to_params_default(&self) -> BrdfParams {
        self.to_params(DEFAULT_CHANNEL)
    }
}

/// A parameter outside the paper's Table 1 box.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxViolation {
    /// Parameter name as in [`BrdfParams::get`] (`kd`, `lobe1.cz`, `lobe1.n`, ...).
    pub name: String,
    /// Its value.
    pub value: f64,
    /// The Table 1 bounds it misses.
    pub bounds: (f64, f64),
}

impl std::fmt::Display for BoxViolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (lo, hi) = self.bounds;
        write!(f, "{} = {} outside [{lo}, {hi}]", self.name, self.value)
    }
}

/// Every parameter of `p` outside the Table 1 box (kd in [0, 1], C in [-1.5, 1.5], n in
/// [0, 10000], pan in [-90, 90]) or not finite, in order (kd, then each lobe's cx, cy, cz,
/// n, pan). [`BrdfParams::validate`] stops at the first; this lists them all.
pub fn table1_violations(p: &BrdfParams) -> Vec<BoxViolation> {
    let mut out = Vec::new();
    let mut check = |name: String, value: f64, (lo, hi): (f64, f64)| {
        if !(value.is_finite() && value >= lo && value <= hi) {
            out.push(BoxViolation {
                name,
                value,
                bounds: (lo, hi),
            });
        }
    };
    check("kd".into(), p.kd, KD_BOUNDS);
    for (i, l) in p.lobes.iter().enumerate() {
        let k = i + 1;
        check(format!("lobe{k}.cx"), l.cx, C_BOUNDS);
        check(format!("lobe{k}.cy"), l.cy, C_BOUNDS);
        check(format!("lobe{k}.cz"), l.cz, C_BOUNDS);
        check(format!("lobe{k}.n"), l.n, N_BOUNDS);
        check(format!("lobe{k}.pan"), l.pan_deg, PAN_BOUNDS);
    }
    out
}
