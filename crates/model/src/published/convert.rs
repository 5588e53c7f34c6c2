//! What the conversions of the lobe families' published fits share: taking a fit's values
//! with checks, and the fields of a converted parameter set outside their family's bounds.

use super::{BoxViolation, ConvertError, PublishedFit};
use crate::params::Params;

/// The values of `names` (each with what the conversion needs it for) of a fit of `model`,
/// red, green, blue, each finite and, where `nonnegative`, at least 0; the Lambertian albedo
/// (0 when the line has none) comes first.
pub(super) fn take(
    fit: &PublishedFit,
    model: &str,
    names: &[(&str, &str, bool)],
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
    for &(name, expected, _) in names {
        out.push(fit.rgb(name).ok_or_else(|| ConvertError::Missing {
            material: fit.material.clone(),
            line: fit.line,
            name: name.into(),
            expected: expected.into(),
        })?);
    }
    let checks = std::iter::once(("kd", false)).chain(names.iter().map(|&(n, _, nn)| (n, nn)));
    for ((name, nonnegative), values) in checks.zip(&out) {
        for (k, &value) in values.iter().enumerate() {
            if !value.is_finite() || (nonnegative && value < 0.0) {
                return Err(ConvertError::Invalid {
                    material: fit.material.clone(),
                    line: fit.line,
                    name: format!("{name}[{}]", ["red", "green", "blue"][k]),
                    value,
                    expected: if nonnegative {
                        "a finite value >= 0"
                    } else {
                        "a finite value"
                    }
                    .into(),
                });
            }
        }
    }
    Ok(out)
}

/// Every field of `p` outside its family's bounds or not finite, in order (`kd`, then each
/// lobe's fields; names as in [`Params::get`]). [`Params::validate`] stops at the first; this
/// lists them all.
pub fn field_violations(p: &Params) -> Vec<BoxViolation> {
    let fam = p.family();
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
    for (d, &v) in fam.shared_fields().iter().zip(p.shared()) {
        check(d.name.to_string(), v, d.bounds);
    }
    for (k, lobe) in p.lobes().iter().enumerate() {
        for (d, &v) in fam.lobe_fields().iter().zip(lobe) {
            check(format!("lobe{}.{}", k + 1, d.name), v, d.bounds);
        }
    }
    out
}
