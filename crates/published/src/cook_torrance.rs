//! Ngan et al.'s Cook-Torrance fits as this crate's `cook-torrance` [`Params`], and the
//! approximate GGX lobe of the same width.
//!
//! Ngan et al. (2005) fit, per channel `c` (bbm's `include/bsdfmodel/ngan.h`, lines 134-147;
//! docs/published-fits.md),
//!
//! ```text
//! f_c(u, v) = kd_c / pi + albedo_c D(h) G(u, v) F(c) / (pi uz vz)
//! D = exp(-tan^2(theta_h) / m^2) / (pi m^2 cos^4(theta_h)),   m = roughness
//! G = min(1, 2 hz uz / (u.h), 2 hz vz / (v.h))
//! F = F0 + (1 - F0)(1 - c)^5,   c = (u.h + v.h) / 2,   F0 = eta
//! ```
//!
//! with `kd` the Lambertian albedo, shared `eta` (read as `F0`, bbm's `ior::reflectance`) and
//! `roughness`. This crate's lobe is `ks D G F / (4 uz vz)` with the same `D`, `G` and `F`, so
//! the conversion is exact: `kd = kd_c / pi`, one isotropic lobe with `ks = 4 albedo_c / pi`,
//! `m = roughness`, `f0 = eta`.
//!
//! Löw et al.'s Cook-Torrance fits (`LowCookTorrance`) are not converted: they use Cook's exact
//! Fresnel term with an index of refraction, which Schlick's approximation does not reproduce.

use super::{ConvertError, PublishedFit, channel_index};
use brdf_io::Channel;
use brdf_model::Params;
use brdf_model::family;
use brdf_model::models::{cook_torrance, ggx};
use std::f64::consts::PI;

/// bbm's name of the model.
const MODEL: &str = "NganCookTorrance";

/// Ngan et al.'s Cook-Torrance fit of one material, per channel (red, green, blue).
#[derive(Clone, Debug, PartialEq)]
pub struct NganCookTorrance {
    /// Material.
    pub material: String,
    /// Lambertian albedo (the BRDF term is `kd / pi`); 0 when the line has no Lambertian term.
    pub kd: [f64; 3],
    /// The specular term's scale (`albedo` in the file).
    pub albedo: [f64; 3],
    /// Schlick's `F0` (`eta` in the file; shared by the channels).
    pub f0: [f64; 3],
    /// Beckmann's roughness `m` (`roughness`; shared by the channels).
    pub m: [f64; 3],
}

/// Reads the named parameters of a fit of `model`, each checked finite.
pub(crate) fn take(
    fit: &PublishedFit,
    model: &str,
    names: &[(&str, &str)],
) -> Result<Vec<[f64; 3]>, ConvertError> {
    if fit.model != model {
        return Err(ConvertError::WrongModel {
            material: fit.material.clone(),
            line: fit.line,
            expected: model.into(),
            found: fit.model.clone(),
        });
    }
    let mut out = vec![fit.diffuse.unwrap_or([0.0; 3])];
    for &(name, expected) in names {
        out.push(fit.rgb(name).ok_or_else(|| ConvertError::Missing {
            material: fit.material.clone(),
            line: fit.line,
            name: name.into(),
            expected: expected.into(),
        })?);
    }
    for (values, name) in out
        .iter()
        .zip(std::iter::once("kd").chain(names.iter().map(|n| n.0)))
    {
        for (k, &v) in values.iter().enumerate() {
            if !v.is_finite() {
                return Err(invalid(fit, name, k, v, "a finite value"));
            }
        }
    }
    Ok(out)
}

/// A value the conversion cannot represent, in channel `k`.
pub(crate) fn invalid(
    fit: &PublishedFit,
    name: &str,
    k: usize,
    value: f64,
    expected: &str,
) -> ConvertError {
    ConvertError::Invalid {
        material: fit.material.clone(),
        line: fit.line,
        name: format!("{name}[{}]", ["red", "green", "blue"][k]),
        value,
        expected: expected.into(),
    }
}

impl NganCookTorrance {
    /// Takes the values of a `NganCookTorrance` fit, checking that they can be converted: every
    /// value finite, `albedo >= 0`, `roughness > 0`.
    pub fn from_fit(fit: &PublishedFit) -> Result<Self, ConvertError> {
        let v = take(
            fit,
            MODEL,
            &[
                ("albedo", "the specular albedo"),
                ("eta", "Schlick's F0"),
                ("roughness", "Beckmann's roughness m"),
            ],
        )?;
        let out = NganCookTorrance {
            material: fit.material.clone(),
            kd: v[0],
            albedo: v[1],
            f0: v[2],
            m: v[3],
        };
        for k in 0..3 {
            if out.albedo[k] < 0.0 {
                return Err(invalid(fit, "albedo", k, out.albedo[k], "a value >= 0"));
            }
            if out.m[k] <= 0.0 {
                return Err(invalid(fit, "roughness", k, out.m[k], "a value > 0"));
            }
        }
        Ok(out)
    }

    /// This crate's `cook-torrance` parameters for one channel: `kd = kd_c / pi` and one
    /// isotropic lobe `ks = 4 albedo_c / pi`, `m = roughness`, `f0 = eta`, pan 0 (exact; see
    /// the module documentation). They may lie outside the family's bounds
    /// ([`super::bounds_violations`] says where).
    pub fn to_params(&self, channel: Channel) -> Params {
        let k = channel_index(channel);
        let fam = family(cook_torrance::NAME).expect("a built-in family");
        let lobe = vec![
            4.0 * self.albedo[k] / PI,
            self.m[k],
            self.m[k],
            self.f0[k],
            0.0,
        ];
        Params::new(fam, vec![self.kd[k] / PI], vec![lobe]).expect("the family's field count")
    }

    /// [`NganCookTorrance::to_params`] for [`super::DEFAULT_CHANNEL`] (green).
    pub fn to_params_default(&self) -> Params {
        self.to_params(super::DEFAULT_CHANNEL)
    }

    /// A `ggx` lobe of about the same shape, for one channel: the same `kd`, `ks` and `f0`
    /// (Schlick's in both), roughness [`ggx_alpha_from_beckmann`]`(m)`. Approximate: GGX's
    /// tails are heavier and its masking is Smith's, not the V-cavity; docs/model.md gives the
    /// measured difference between the two lobes over Ngan's 86 materials.
    pub fn to_ggx_params(&self, channel: Channel) -> Params {
        let k = channel_index(channel);
        let fam = family(ggx::NAME).expect("a built-in family");
        let a = ggx_alpha_from_beckmann(self.m[k]);
        let lobe = vec![4.0 * self.albedo[k] / PI, a, a, self.f0[k], 0.0];
        Params::new(fam, vec![self.kd[k] / PI], vec![lobe]).expect("the family's field count")
    }
}

/// `sqrt(ln 2 / (sqrt 2 - 1))` = 1.29360168677552848 (mpmath): the ratio of GGX's roughness
/// to Beckmann's at which the two distributions fall to half their peak at the same angle.
pub const GGX_PER_BECKMANN: f64 = 1.293_601_686_775_528_5;

/// The GGX roughness whose distribution has the same half-maximum width as Beckmann's with
/// roughness `m`, `alpha = m sqrt(ln 2 / (sqrt 2 - 1))`: Beckmann's `D / D(0)` is
/// `exp(-t^2 / m^2) cos^-4` and GGX's `(1 + t^2 / alpha^2)^-2 cos^-4` (in `t = tan(theta_h)`),
/// so both fall to half their peak (up to the common `cos^-4`) at `t^2 = m^2 ln 2 = alpha^2
/// (sqrt 2 - 1)`. The peaks then differ
/// (`1 / (pi m^2)` against `1 / (pi alpha^2)`) and so do the tails; the accuracy over Ngan's
/// fits is measured in `crates/model/tests/published_families.rs` and given in docs/model.md.
pub fn ggx_alpha_from_beckmann(m: f64) -> f64 {
    m * GGX_PER_BECKMANN
}
