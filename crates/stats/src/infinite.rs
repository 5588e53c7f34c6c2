//! Serde for an optional statistic that may be infinite. JSON has no infinity (serde_json
//! writes it as `null`, which a reader cannot tell from "no statistic"), so `+inf` and `-inf`
//! are written as the strings `"inf"` and `"-inf"`, the spelling the CSV files use; finite
//! values stay numbers and `None` stays `null`. Reading also accepts the plain numbers and
//! `null` of files written before.

use serde::de::{self, Deserializer, Visitor};
use serde::ser::Serializer;

/// Writes `value` (see the module documentation).
pub fn serialize<S: Serializer>(value: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match value {
        None => s.serialize_none(),
        Some(x) if *x == f64::INFINITY => s.serialize_some("inf"),
        Some(x) if *x == f64::NEG_INFINITY => s.serialize_some("-inf"),
        Some(x) => s.serialize_some(x),
    }
}

/// Reads what [`serialize`] writes.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    d.deserialize_option(OptionalNumber)
}

struct OptionalNumber;

impl<'de> Visitor<'de> for OptionalNumber {
    type Value = Option<f64>;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a number, \"inf\", \"-inf\" or null")
    }

    fn visit_none<E: de::Error>(self) -> Result<Self::Value, E> {
        Ok(None)
    }

    fn visit_unit<E: de::Error>(self) -> Result<Self::Value, E> {
        Ok(None)
    }

    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(OptionalNumber)
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
        Ok(Some(v))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        Ok(Some(v as f64))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        Ok(Some(v as f64))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        match v {
            "inf" => Ok(Some(f64::INFINITY)),
            "-inf" => Ok(Some(f64::NEG_INFINITY)),
            _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
        }
    }
}
