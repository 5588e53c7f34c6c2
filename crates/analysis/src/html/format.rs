//! Numbers formatted for reading on a page: targets with their distance from the best-known
//! RMSE, p-values floored where the tests' tails stop being exact, ratios and rates; at most a
//! few significant digits, so cells stay short and align.

use crate::stats::fmt_num;

/// Below this a p-value is written `< 1e-16`: the tails are computed far lower, but no test
/// on a few hundred trials means anything there, and 7.4e-300 reads as noise.
pub const P_FLOOR: f64 = 1e-16;

/// A p-value: `< 1e-16`, `2.3e-7` below 1e-4, else four decimals; `-` for none.
pub fn p_value(p: Option<f64>) -> String {
    match p {
        None => "-".into(),
        Some(p) if p < P_FLOOR => "&lt; 1e-16".into(),
        Some(p) if p < 1e-4 => format!("{p:.1e}"),
        Some(p) => format!("{p:.4}"),
    }
}

pub use crate::stats::{significant, target_digits, target_text as target};

/// A ratio to the best: `×4.28`, `×10.5`, `×108`, `×1.2e3`.
pub fn ratio(r: f64) -> String {
    let s = if r >= 1e4 {
        format!("{r:.1e}")
    } else if r >= 100.0 {
        format!("{r:.0}")
    } else if r >= 10.0 {
        format!("{r:.1}")
    } else {
        format!("{r:.2}")
    };
    format!("&times;{s}")
}

/// A share as a percentage: `100%`, `95%`, `2.5%`.
pub fn rate(r: f64) -> String {
    let p = r * 100.0;
    if p == 0.0 || p == 100.0 || p >= 10.0 {
        format!("{p:.0}%")
    } else {
        format!("{}%", significant(p, 2))
    }
}

/// A number for a table cell (at most four significant digits; `-` for none).
pub fn num(v: Option<f64>) -> String {
    fmt_num(v)
}
