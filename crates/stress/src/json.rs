//! Reading a report back from its JSON: `to_json` writes NaN (an undetermined standard error,
//! the open last bin of a histogram) as `null`, which serde_json cannot read into an `f64`.
//! [`NullAsNan`] reads a JSON value so that `null` where a number is expected is NaN.

use serde::de::value::{MapDeserializer, SeqDeserializer};
use serde::de::{Deserializer, IntoDeserializer, Visitor};
use serde::forward_to_deserialize_any;
use serde_json::Value;

/// A JSON value read with `null` as NaN wherever an `f64` is expected (and as `None` where an
/// option is).
pub struct NullAsNan(pub Value);

impl<'de> IntoDeserializer<'de, serde_json::Error> for NullAsNan {
    type Deserializer = NullAsNan;

    fn into_deserializer(self) -> NullAsNan {
        self
    }
}

impl<'de> Deserializer<'de> for NullAsNan {
    type Error = serde_json::Error;

    fn deserialize_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        match self.0 {
            Value::Array(a) => {
                let mut seq = SeqDeserializer::new(a.into_iter().map(NullAsNan));
                let out = v.visit_seq(&mut seq)?;
                seq.end()?;
                Ok(out)
            }
            Value::Object(m) => {
                let mut map = MapDeserializer::new(m.into_iter().map(|(k, x)| (k, NullAsNan(x))));
                let out = v.visit_map(&mut map)?;
                map.end()?;
                Ok(out)
            }
            other => other.deserialize_any(v),
        }
    }

    fn deserialize_f64<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        match self.0 {
            Value::Null => v.visit_f64(f64::NAN),
            other => other.deserialize_f64(v),
        }
    }

    fn deserialize_f32<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        self.deserialize_f64(v)
    }

    fn deserialize_option<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        match self.0 {
            Value::Null => v.visit_none(),
            other => v.visit_some(NullAsNan(other)),
        }
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        v: V,
    ) -> Result<V::Value, Self::Error> {
        v.visit_newtype_struct(self)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        name: &'static str,
        variants: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, Self::Error> {
        self.0.deserialize_enum(name, variants, v)
    }

    forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 char str string bytes byte_buf unit
        unit_struct seq tuple tuple_struct map struct identifier ignored_any
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize, Debug)]
    struct S {
        x: f64,
        pairs: Vec<(f64, u64)>,
        maybe: Option<f64>,
        name: String,
    }

    #[test]
    fn null_reads_as_nan_where_a_number_is_expected() {
        let v = serde_json::json!({"x": null, "pairs": [[1.0, 2], [null, 0]], "maybe": null, "name": "a"});
        let s: S = serde::Deserialize::deserialize(NullAsNan(v)).unwrap();
        assert!(s.x.is_nan() && s.pairs[1].0.is_nan());
        assert_eq!(
            (s.pairs[0], s.maybe, s.name.as_str()),
            ((1.0, 2), None, "a")
        );
    }
}
