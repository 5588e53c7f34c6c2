//! Ngan et al.'s Blinn-Phong fits as this crate's `blinn-phong` [`Params`].
//!
//! bbm evaluates `NganBlinnPhong` as a mirror-vector lobe, `albedo (n + 2)/(2 pi) max(0,
//! r(u).v)^n`, but the published numbers behave like the half-vector lobe
//! `albedo (n + 2)/(2 pi) max(0, n.h)^n` (docs/published-fits.md: against Ngan's Ward fits,
//! `n alpha^2` has a median of 2.6, as for a half-vector lobe, not 0.5). This conversion takes
//! that reading, per channel `c`:
//!
//! ```text
//! f_c(u, v) = kd_c / pi + albedo_c (n + 2) / (2 pi) max(0, n.h)^n
//! ```
//!
//! with `kd` the Lambertian albedo and a shared `n` (`sharpness`). This crate's lobe is
//! `ks (p + 8) / (8 pi) (n.h)^p`, so the conversion is exact in that reading: `kd = kd_c / pi`,
//! `p = n` and `ks = 4 albedo_c (n + 2) / (n + 8)`. It does not reproduce bbm's mirror lobe.

use super::cook_torrance::{invalid, take};
use super::{ConvertError, PublishedFit, channel_index};
use brdf_io::Channel;
use brdf_model::Params;
use brdf_model::family;
use brdf_model::models::blinn_phong;
use std::f64::consts::PI;

/// Ngan et al.'s Blinn-Phong fit of one material, per channel (red, green, blue).
#[derive(Clone, Debug, PartialEq)]
pub struct NganBlinnPhong {
    /// Material.
    pub material: String,
    /// Lambertian albedo (the BRDF term is `kd / pi`); 0 when the line has no Lambertian term.
    pub kd: [f64; 3],
    /// The lobe's scale (`albedo` in the file), with the `(n + 2) / (2 pi)` normalisation.
    pub albedo: [f64; 3],
    /// The exponent `n` (`sharpness`; shared by the channels).
    pub n: [f64; 3],
}

impl NganBlinnPhong {
    /// Takes the values of a `NganBlinnPhong` fit, checking that they can be converted: every
    /// value finite, `albedo >= 0`, `sharpness >= 0`.
    pub fn from_fit(fit: &PublishedFit) -> Result<Self, ConvertError> {
        let v = take(
            fit,
            "NganBlinnPhong",
            &[
                ("albedo", "the lobe's albedo"),
                ("sharpness", "the exponent n"),
            ],
        )?;
        let out = NganBlinnPhong {
            material: fit.material.clone(),
            kd: v[0],
            albedo: v[1],
            n: v[2],
        };
        for k in 0..3 {
            if out.albedo[k] < 0.0 {
                return Err(invalid(fit, "albedo", k, out.albedo[k], "a value >= 0"));
            }
            if out.n[k] < 0.0 {
                return Err(invalid(fit, "sharpness", k, out.n[k], "a value >= 0"));
            }
        }
        Ok(out)
    }

    /// The lobe's `ks` in `channel`: `4 albedo (n + 2) / (n + 8)`, so that `ks (n + 8) / (8 pi)
    /// = albedo (n + 2) / (2 pi)`.
    pub fn ks(&self, channel: Channel) -> f64 {
        let k = channel_index(channel);
        let n = self.n[k];
        4.0 * self.albedo[k] * (n + 2.0) / (n + 8.0)
    }

    /// This crate's `blinn-phong` parameters for one channel: `kd = kd_c / pi` and one lobe
    /// with [`NganBlinnPhong::ks`] and `p = n` (exact in the half-vector reading; see the module
    /// documentation). They may lie outside the family's bounds ([`super::bounds_violations`]).
    pub fn to_params(&self, channel: Channel) -> Params {
        let k = channel_index(channel);
        let fam = family(blinn_phong::NAME).expect("a built-in family");
        let lobe = vec![self.ks(channel), self.n[k]];
        Params::new(fam, vec![self.kd[k] / PI], vec![lobe]).expect("the family's field count")
    }

    /// [`NganBlinnPhong::to_params`] for [`super::DEFAULT_CHANNEL`] (green).
    pub fn to_params_default(&self) -> Params {
        self.to_params(super::DEFAULT_CHANNEL)
    }
}
