//! Labels of swept values: as short as they can be while telling every value of a sweep apart.

/// Significant digits of a swept value in a label when they suffice to tell the values apart.
const LABEL_DIGITS: usize = 4;

/// Formats `x` with `digits` significant digits: integers plainly, reals between 1e-3 and 1e6
/// in fixed notation without trailing zeros, others in scientific notation.
pub fn format_digits(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if x == x.trunc() && x.abs() < 1e15 {
        format!("{x:.0}")
    } else if x.abs() >= 1e-3 && x.abs() < 1e6 {
        let decimals = (digits as i32 - 1 - x.abs().log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{:.*e}", digits - 1, x)
    }
}

fn value_label(v: &toml::Value, digits: usize) -> String {
    match v {
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => format_digits(*f, digits),
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// The labels of one key's swept `values`, in order: with [`LABEL_DIGITS`] significant digits
/// when those tell the distinct values apart (the labels of every sweep that fits in them stay
/// as they are), else with the fewest more digits that do, else each float's shortest
/// round-trip form (distinct for distinct values).
pub fn distinct_labels(values: &[toml::Value]) -> Vec<String> {
    let distinct_values = count_distinct(values.iter().map(|v| v.to_string()));
    for digits in LABEL_DIGITS..=17 {
        let labels: Vec<String> = values.iter().map(|v| value_label(v, digits)).collect();
        if count_distinct(labels.iter().cloned()) == distinct_values {
            return labels;
        }
    }
    values
        .iter()
        .map(|v| match v {
            toml::Value::Float(f) => f.to_string(),
            other => value_label(other, LABEL_DIGITS),
        })
        .collect()
}

fn count_distinct(items: impl Iterator<Item = String>) -> usize {
    items.collect::<std::collections::HashSet<_>>().len()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floats(xs: &[f64]) -> Vec<toml::Value> {
        xs.iter().map(|&x| toml::Value::Float(x)).collect()
    }

    #[test]
    fn values_apart_in_four_digits_keep_four_digit_labels() {
        let labels = distinct_labels(&floats(&[0.0123456, 1.2, 25.0, 1e-7]));
        assert_eq!(labels, ["0.01235", "1.2", "25", "1.000e-7"]);
    }

    #[test]
    fn close_values_get_the_digits_that_tell_them_apart() {
        let labels = distinct_labels(&floats(&[0.1, 0.10001, 0.10002]));
        assert_eq!(labels, ["0.1", "0.10001", "0.10002"]);
        // A 10,000-step range over a narrow interval: every label distinct.
        let xs: Vec<f64> = (0..10_000).map(|i| 0.5 + i as f64 * 1e-9).collect();
        let labels = distinct_labels(&floats(&xs));
        assert_eq!(count_distinct(labels.into_iter()), 10_000);
    }

    #[test]
    fn a_repeated_value_keeps_its_repeated_label() {
        let labels = distinct_labels(&floats(&[0.5, 0.5, 0.7]));
        assert_eq!(labels, ["0.5", "0.5", "0.7"]);
    }
}
