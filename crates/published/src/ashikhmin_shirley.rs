//! Ngan et al.'s Ashikhmin-Shirley fits as parameters of the `ashikhmin-shirley` family.
//!
//! Ngan et al. (2005) fit, per channel `c` (bbm's `bsdfmodel/ngan.h`, lines 152-158, on
//! `bsdfmodel/ashikhminshirley.h`, lines 63-81),
//!
//! ```text
//! f_c(u, v) = kd_c / pi + ks_c (n + 1)/(8 pi) (n.h)^n F(u.h) / ((u.h) max(uz, vz)),
//! F(c) = F0 + (1 - F0)(1 - c)^5
//! ```
//!
//! with `kd` the Lambertian albedo, `ks` the file's `albedo`, `F0` its `fresnelReflectance`
//! and `n` its `sharpness` (both shared). That is the family's isotropic lobe as it stands
//! (`sqrt((n + 1)(n + 1)) = n + 1`): `kd = kd_c / pi`, `ks = ks_c`, `nu = nv = n`,
//! `f0 = F0`, no pan. Every one of the 86 materials lies inside the family's bounds in every
//! channel.
//!
//! Löw et al.'s fits (`low_ashikhminshirley_E1.fit`, `_E2`) are not converted: their
//! `fresnelReflectance` is an index of refraction `eta` (1.08 to 10.1) for the exact
//! dielectric Fresnel factor, which the family's Schlick factor matches only roughly. With
//! `F0 = ((eta - 1)/(eta + 1))^2`, Schlick's factor is off the exact one by up to 280% at
//! `eta = 1.08`, 23% at 1.5, 18% at 1.83 (their median) and 82% at 10.09 (relative, the
//! largest over `u.h` in (0, 1]; absolute 0.24, 0.036, 0.036 and 0.40), far beyond the
//! agreement a conversion here is tested to. Besides, 6 albedo values of E1 (4 materials) and
//! 4 of E2 (2 materials) exceed the family's `ks <= 1`.

use super::convert::take;
use super::{ConvertError, PublishedFit, channel_index};
use brdf_io::Channel;
use brdf_model::Params;
use std::f64::consts::PI;

/// Ngan et al.'s Ashikhmin-Shirley fit of one material, per channel (red, green, blue).
#[derive(Clone, Debug, PartialEq)]
pub struct NganAshikhminShirley {
    /// Material.
    pub material: String,
    /// Lambertian albedo (the BRDF term is `kd / pi`); 0 when the line has no Lambertian term.
    pub kd: [f64; 3],
    /// The lobe's scale (`albedo` in the file).
    pub ks: [f64; 3],
    /// Schlick's `F0` (`fresnelReflectance`, shared in the published file).
    pub f0: [f64; 3],
    /// The exponent `n` (`sharpness`, shared in the published file).
    pub n: [f64; 3],
}

impl NganAshikhminShirley {
    /// Takes the values of a `NganAshikhminShirley` fit, checking that they can be converted:
    /// every value finite, `ks`, `F0` and `n` at least 0.
    pub fn from_fit(fit: &PublishedFit) -> Result<Self, ConvertError> {
        let v = take(
            fit,
            "NganAshikhminShirley",
            &[
                ("albedo", "the lobe's albedo (ks)", true),
                ("fresnelReflectance", "Schlick's F0", true),
                ("sharpness", "the exponent n", true),
            ],
        )?;
        Ok(NganAshikhminShirley {
            material: fit.material.clone(),
            kd: v[0],
            ks: v[1],
            f0: v[2],
            n: v[3],
        })
    }

    /// The family's parameters for one channel: `kd = kd_c / pi` and one lobe `ks = ks_c`,
    /// `nu = nv = n`, `f0 = F0`, pan 0 (an isotropic lobe's values). They may lie outside the
    /// family's bounds ([`super::bounds_violations`] says where).
    pub fn to_params(&self, channel: Channel) -> Params {
        let k = channel_index(channel);
        let fam = brdf_model::family(brdf_model::models::ashikhmin_shirley::NAME)
            .expect("a built-in family");
        let n = self.n[k];
        let lobe = vec![self.ks[k], n, n, self.f0[k], 0.0];
        Params::new(fam, vec![self.kd[k] / PI], vec![lobe])
            .expect("the Ashikhmin-Shirley family has five lobe fields")
    }

    /// [`NganAshikhminShirley::to_params`] for [`super::DEFAULT_CHANNEL`] (green).
    pub fn to_params_default(&self) -> Params {
        self.to_params(super::DEFAULT_CHANNEL)
    }
}
