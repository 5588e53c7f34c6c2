//! Where a converted parameter set of any family leaves the family's bounds.

use super::BoxViolation;
use brdf_model::Params;

/// Every field of `p` outside its family's bounds ([`brdf_model::FieldDef::bounds`]) or not finite,
/// in canonical order (`kd`, then each lobe's fields). [`Params::validate`] stops at the first;
/// this lists them all.
pub fn bounds_violations(p: &Params) -> Vec<BoxViolation> {
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
    for (f, &v) in fam.shared_fields().iter().zip(p.shared()) {
        check(f.name.to_string(), v, f.bounds);
    }
    for (k, lobe) in p.lobes().iter().enumerate() {
        for (f, &v) in fam.lobe_fields().iter().zip(lobe) {
            check(format!("lobe{}.{}", k + 1, f.name), v, f.bounds);
        }
    }
    out
}
