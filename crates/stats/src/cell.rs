//! One column's value in the derived files and the Python package's records: the writers
//! render lists of named cells, so a statistic added to a list reaches every writer.

use serde::Serialize;

/// The value of one column of a derived file (`stats.csv`, `tests.csv`) or of a Python record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cell {
    /// A statistic or p-value: empty in CSV and `null` in JSON when there is none.
    Number(Option<f64>),
    /// An effect that may be infinite: as [`Cell::Number`], but an infinity is `"inf"` in
    /// JSON (where `null` means no test).
    Effect(Option<f64>),
    /// A flag.
    Flag(bool),
    /// A count.
    Count(usize),
    /// A run time, `None` when it is not reached: `inf` in CSV, `null` in JSON.
    Time(Option<f64>),
}

/// What kind of value a column holds (for reading it back).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellKind {
    /// [`Cell::Number`].
    Number,
    /// [`Cell::Effect`].
    Effect,
    /// [`Cell::Flag`].
    Flag,
}

impl Cell {
    /// The cell as a CSV field: empty for none, `inf` for an infinity.
    pub fn csv(&self) -> String {
        match self {
            Cell::Number(v) | Cell::Effect(v) => v.map_or_else(String::new, |x| format!("{x}")),
            Cell::Flag(b) => b.to_string(),
            Cell::Count(n) => n.to_string(),
            Cell::Time(v) => v.map_or_else(|| "inf".to_string(), |x| format!("{x}")),
        }
    }
}

impl Serialize for Cell {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Cell::Number(v) => v.serialize(s),
            Cell::Effect(v) => super::infinite::serialize(v, s),
            Cell::Flag(b) => b.serialize(s),
            Cell::Count(n) => n.serialize(s),
            Cell::Time(v) => v.serialize(s),
        }
    }
}
