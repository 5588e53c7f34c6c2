//! What the conversions of the lobe families' published fits share: taking a fit's values
//! with checks.

use super::{ConvertError, PublishedFit};

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
