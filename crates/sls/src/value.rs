//! An ordered, owned copy of a value in serde's data model, so a configuration whose type is
//! known only to the registry can be serialised and deserialised through any format.
//!
//! Serialising a configuration records every call its `Serialize` makes ([`capture`]); replaying
//! them ([`Value`]'s `Serialize`) makes the same calls on the real serializer, so the output is
//! byte for byte what the configuration type writes itself. Deserialising reads the input into
//! a [`Value`] first (as serde does for internally tagged enums) and then hands the fields to
//! the registered type's `Deserialize`.

use serde::de::value::{Error, MapAccessDeserializer, MapDeserializer, SeqDeserializer};
use serde::de::{self, IntoDeserializer, Visitor};
use serde::ser::{self, Serialize, SerializeMap, SerializeStruct, Serializer};
use std::fmt;

/// One value of serde's data model, with the names the serializer was given.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Value {
    Unit,
    None,
    Some(Box<Value>),
    Bool(bool),
    I64(i64),
    U64(u64),
    F32(f32),
    F64(f64),
    Str(String),
    Bytes(Vec<u8>),
    UnitStruct(&'static str),
    UnitVariant(&'static str, u32, &'static str),
    NewtypeStruct(&'static str, Box<Value>),
    NewtypeVariant(&'static str, u32, &'static str, Box<Value>),
    Seq(Vec<Value>),
    Tuple(Vec<Value>),
    TupleStruct(&'static str, Vec<Value>),
    TupleVariant(&'static str, u32, &'static str, Vec<Value>),
    Map(Vec<(Value, Value)>),
    Struct(&'static str, Vec<(&'static str, Value)>),
    StructVariant(&'static str, u32, &'static str, Vec<(&'static str, Value)>),
}

impl Value {
    /// What kind of value this is, for error messages.
    pub(crate) fn type_name(&self) -> &'static str {
        match self {
            Value::Unit | Value::None | Value::UnitStruct(_) => "nothing",
            Value::Some(v) | Value::NewtypeStruct(_, v) => v.type_name(),
            Value::Bool(_) => "a boolean",
            Value::I64(_) | Value::U64(_) => "an integer",
            Value::F32(_) | Value::F64(_) => "a float",
            Value::Str(_) | Value::UnitVariant(..) => "a string",
            Value::Bytes(_) => "bytes",
            Value::Seq(_) | Value::Tuple(_) | Value::TupleStruct(..) | Value::TupleVariant(..) => {
                "an array"
            }
            _ => "a table",
        }
    }
}

/// Records how `value` serialises.
pub(crate) fn capture<T: Serialize + ?Sized>(value: &T) -> Result<Value, Error> {
    value.serialize(Capture)
}

/// The serializer that records calls as a [`Value`].
struct Capture;

/// A compound value being recorded: the elements of a sequence, tuple or map, or the fields
/// of a struct.
struct Compound {
    shape: Shape,
    items: Vec<Value>,
    fields: Vec<(&'static str, Value)>,
    entries: Vec<(Value, Value)>,
    pending_key: Option<Value>,
}

enum Shape {
    Seq,
    Tuple,
    TupleStruct(&'static str),
    TupleVariant(&'static str, u32, &'static str),
    Map,
    Struct(&'static str),
    StructVariant(&'static str, u32, &'static str),
}

impl Compound {
    fn new(shape: Shape) -> Self {
        Self {
            shape,
            items: Vec::new(),
            fields: Vec::new(),
            entries: Vec::new(),
            pending_key: None,
        }
    }

    fn finish(self) -> Value {
        match self.shape {
            Shape::Seq => Value::Seq(self.items),
            Shape::Tuple => Value::Tuple(self.items),
            Shape::TupleStruct(n) => Value::TupleStruct(n, self.items),
            Shape::TupleVariant(n, i, v) => Value::TupleVariant(n, i, v, self.items),
            Shape::Map => Value::Map(self.entries),
            Shape::Struct(n) => Value::Struct(n, self.fields),
            Shape::StructVariant(n, i, v) => Value::StructVariant(n, i, v, self.fields),
        }
    }

    fn push<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        self.items.push(capture(value)?);
        Ok(())
    }

    fn field<T: Serialize + ?Sized>(&mut self, key: &'static str, v: &T) -> Result<(), Error> {
        self.fields.push((key, capture(v)?));
        Ok(())
    }
}

impl Serializer for Capture {
    type Ok = Value;
    type Error = Error;
    type SerializeSeq = Compound;
    type SerializeTuple = Compound;
    type SerializeTupleStruct = Compound;
    type SerializeTupleVariant = Compound;
    type SerializeMap = Compound;
    type SerializeStruct = Compound;
    type SerializeStructVariant = Compound;

    fn serialize_bool(self, v: bool) -> Result<Value, Error> {
        Ok(Value::Bool(v))
    }
    fn serialize_i8(self, v: i8) -> Result<Value, Error> {
        Ok(Value::I64(v.into()))
    }
    fn serialize_i16(self, v: i16) -> Result<Value, Error> {
        Ok(Value::I64(v.into()))
    }
    fn serialize_i32(self, v: i32) -> Result<Value, Error> {
        Ok(Value::I64(v.into()))
    }
    fn serialize_i64(self, v: i64) -> Result<Value, Error> {
        Ok(Value::I64(v))
    }
    fn serialize_u8(self, v: u8) -> Result<Value, Error> {
        Ok(Value::U64(v.into()))
    }
    fn serialize_u16(self, v: u16) -> Result<Value, Error> {
        Ok(Value::U64(v.into()))
    }
    fn serialize_u32(self, v: u32) -> Result<Value, Error> {
        Ok(Value::U64(v.into()))
    }
    fn serialize_u64(self, v: u64) -> Result<Value, Error> {
        Ok(Value::U64(v))
    }
    fn serialize_f32(self, v: f32) -> Result<Value, Error> {
        Ok(Value::F32(v))
    }
    fn serialize_f64(self, v: f64) -> Result<Value, Error> {
        Ok(Value::F64(v))
    }
    fn serialize_char(self, v: char) -> Result<Value, Error> {
        Ok(Value::Str(v.to_string()))
    }
    fn serialize_str(self, v: &str) -> Result<Value, Error> {
        Ok(Value::Str(v.to_owned()))
    }
    fn serialize_bytes(self, v: &[u8]) -> Result<Value, Error> {
        Ok(Value::Bytes(v.to_vec()))
    }
    fn serialize_none(self) -> Result<Value, Error> {
        Ok(Value::None)
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<Value, Error> {
        Ok(Value::Some(Box::new(capture(v)?)))
    }
    fn serialize_unit(self) -> Result<Value, Error> {
        Ok(Value::Unit)
    }
    fn serialize_unit_struct(self, name: &'static str) -> Result<Value, Error> {
        Ok(Value::UnitStruct(name))
    }
    fn serialize_unit_variant(
        self,
        name: &'static str,
        index: u32,
        variant: &'static str,
    ) -> Result<Value, Error> {
        Ok(Value::UnitVariant(name, index, variant))
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        name: &'static str,
        v: &T,
    ) -> Result<Value, Error> {
        Ok(Value::NewtypeStruct(name, Box::new(capture(v)?)))
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        name: &'static str,
        index: u32,
        variant: &'static str,
        v: &T,
    ) -> Result<Value, Error> {
        let inner = Box::new(capture(v)?);
        Ok(Value::NewtypeVariant(name, index, variant, inner))
    }
    fn serialize_seq(self, _len: Option<usize>) -> Result<Compound, Error> {
        Ok(Compound::new(Shape::Seq))
    }
    fn serialize_tuple(self, _len: usize) -> Result<Compound, Error> {
        Ok(Compound::new(Shape::Tuple))
    }
    fn serialize_tuple_struct(self, name: &'static str, _len: usize) -> Result<Compound, Error> {
        Ok(Compound::new(Shape::TupleStruct(name)))
    }
    fn serialize_tuple_variant(
        self,
        name: &'static str,
        index: u32,
        variant: &'static str,
        _len: usize,
    ) -> Result<Compound, Error> {
        Ok(Compound::new(Shape::TupleVariant(name, index, variant)))
    }
    fn serialize_map(self, _len: Option<usize>) -> Result<Compound, Error> {
        Ok(Compound::new(Shape::Map))
    }
    fn serialize_struct(self, name: &'static str, _len: usize) -> Result<Compound, Error> {
        Ok(Compound::new(Shape::Struct(name)))
    }
    fn serialize_struct_variant(
        self,
        name: &'static str,
        index: u32,
        variant: &'static str,
        _len: usize,
    ) -> Result<Compound, Error> {
        Ok(Compound::new(Shape::StructVariant(name, index, variant)))
    }
}

impl ser::SerializeSeq for Compound {
    type Ok = Value;
    type Error = Error;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
        self.push(v)
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.finish())
    }
}

impl ser::SerializeTuple for Compound {
    type Ok = Value;
    type Error = Error;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
        self.push(v)
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.finish())
    }
}

impl ser::SerializeTupleStruct for Compound {
    type Ok = Value;
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
        self.push(v)
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.finish())
    }
}

impl ser::SerializeTupleVariant for Compound {
    type Ok = Value;
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
        self.push(v)
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.finish())
    }
}

impl ser::SerializeMap for Compound {
    type Ok = Value;
    type Error = Error;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Error> {
        self.pending_key = Some(capture(key)?);
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
        let key = self
            .pending_key
            .take()
            .ok_or_else(|| <Error as ser::Error>::custom("map value without a key"))?;
        self.entries.push((key, capture(v)?));
        Ok(())
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.finish())
    }
}

impl ser::SerializeStruct for Compound {
    type Ok = Value;
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        key: &'static str,
        v: &T,
    ) -> Result<(), Error> {
        self.field(key, v)
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.finish())
    }
}

impl ser::SerializeStructVariant for Compound {
    type Ok = Value;
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        key: &'static str,
        v: &T,
    ) -> Result<(), Error> {
        self.field(key, v)
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.finish())
    }
}

/// Replays the recorded calls on `serializer`.
impl Serialize for Value {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use ser::{SerializeTupleStruct, SerializeTupleVariant};
        match self {
            Value::Unit => s.serialize_unit(),
            Value::None => s.serialize_none(),
            Value::Some(v) => s.serialize_some(v),
            Value::Bool(v) => s.serialize_bool(*v),
            Value::I64(v) => s.serialize_i64(*v),
            Value::U64(v) => s.serialize_u64(*v),
            Value::F32(v) => s.serialize_f32(*v),
            Value::F64(v) => s.serialize_f64(*v),
            Value::Str(v) => s.serialize_str(v),
            Value::Bytes(v) => s.serialize_bytes(v),
            Value::UnitStruct(n) => s.serialize_unit_struct(n),
            Value::UnitVariant(n, i, v) => s.serialize_unit_variant(n, *i, v),
            Value::NewtypeStruct(n, v) => s.serialize_newtype_struct(n, v),
            Value::NewtypeVariant(n, i, var, v) => s.serialize_newtype_variant(n, *i, var, v),
            Value::Seq(items) => s.collect_seq(items),
            Value::Tuple(items) => {
                let mut t = s.serialize_tuple(items.len())?;
                for v in items {
                    ser::SerializeTuple::serialize_element(&mut t, v)?;
                }
                ser::SerializeTuple::end(t)
            }
            Value::TupleStruct(n, items) => {
                let mut t = s.serialize_tuple_struct(n, items.len())?;
                for v in items {
                    t.serialize_field(v)?;
                }
                t.end()
            }
            Value::TupleVariant(n, i, var, items) => {
                let mut t = s.serialize_tuple_variant(n, *i, var, items.len())?;
                for v in items {
                    t.serialize_field(v)?;
                }
                t.end()
            }
            Value::Map(entries) => {
                let mut m = s.serialize_map(Some(entries.len()))?;
                for (k, v) in entries {
                    m.serialize_entry(k, v)?;
                }
                m.end()
            }
            Value::Struct(n, fields) => {
                let mut st = s.serialize_struct(n, fields.len())?;
                for (k, v) in fields {
                    st.serialize_field(k, v)?;
                }
                st.end()
            }
            Value::StructVariant(n, i, var, fields) => {
                let mut st = s.serialize_struct_variant(n, *i, var, fields.len())?;
                for (k, v) in fields {
                    ser::SerializeStructVariant::serialize_field(&mut st, k, v)?;
                }
                ser::SerializeStructVariant::end(st)
            }
        }
    }
}

/// Reads any self-describing input (JSON, TOML) into a [`Value`].
impl<'de> de::Deserialize<'de> for Value {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(Reader)
    }
}

struct Reader;

impl<'de> Visitor<'de> for Reader {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any value")
    }
    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::I64(v))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::U64(v))
    }
    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(Value::F64(v))
    }
    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::Str(v.to_owned()))
    }
    fn visit_string<E>(self, v: String) -> Result<Value, E> {
        Ok(Value::Str(v))
    }
    fn visit_bytes<E>(self, v: &[u8]) -> Result<Value, E> {
        Ok(Value::Bytes(v.to_vec()))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Unit)
    }
    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::None)
    }
    fn visit_some<D: de::Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        Ok(Value::Some(Box::new(d.deserialize_any(Reader)?)))
    }
    fn visit_newtype_struct<D: de::Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(Reader)
    }
    fn visit_seq<A: de::SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(v) = seq.next_element()? {
            items.push(v);
        }
        Ok(Value::Seq(items))
    }
    fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut entries = Vec::new();
        while let Some(entry) = map.next_entry()? {
            entries.push(entry);
        }
        Ok(Value::Map(entries))
    }
}

impl<'de> IntoDeserializer<'de, Error> for Value {
    type Deserializer = Self;
    fn into_deserializer(self) -> Self {
        self
    }
}

/// Hands a [`Value`] read by [`Reader`] to a type's `Deserialize`, as the original input would
/// have (numbers and strings as they were read, `Option`s and enums as serde expects them).
impl<'de> de::Deserializer<'de> for Value {
    type Error = Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        match self {
            Value::Unit | Value::UnitStruct(_) => visitor.visit_unit(),
            Value::None => visitor.visit_none(),
            Value::Some(v) => visitor.visit_some(*v),
            Value::Bool(v) => visitor.visit_bool(v),
            Value::I64(v) => visitor.visit_i64(v),
            Value::U64(v) => visitor.visit_u64(v),
            Value::F32(v) => visitor.visit_f32(v),
            Value::F64(v) => visitor.visit_f64(v),
            Value::Str(v) => visitor.visit_string(v),
            Value::Bytes(v) => visitor.visit_byte_buf(v),
            Value::UnitVariant(_, _, v) => visitor.visit_str(v),
            Value::NewtypeStruct(_, v) => visitor.visit_newtype_struct(*v),
            Value::Seq(items)
            | Value::Tuple(items)
            | Value::TupleStruct(_, items)
            | Value::TupleVariant(_, _, _, items) => {
                visitor.visit_seq(SeqDeserializer::new(items.into_iter()))
            }
            Value::Map(entries) => visitor.visit_map(MapDeserializer::new(entries.into_iter())),
            Value::Struct(_, fields) | Value::StructVariant(_, _, _, fields) => {
                visitor.visit_map(MapDeserializer::new(fields.into_iter()))
            }
            Value::NewtypeVariant(_, _, variant, v) => {
                let entry = std::iter::once((variant, *v));
                visitor.visit_map(MapDeserializer::new(entry))
            }
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        match self {
            Value::Unit | Value::None => visitor.visit_none(),
            Value::Some(v) => visitor.visit_some(*v),
            other => visitor.visit_some(other),
        }
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        match self {
            Value::Str(v) => visitor.visit_enum(v.into_deserializer()),
            Value::Map(entries) => visitor.visit_enum(MapAccessDeserializer::new(
                MapDeserializer::new(entries.into_iter()),
            )),
            other => other.deserialize_any(visitor),
        }
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        visitor.visit_newtype_struct(self)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        unit unit_struct seq tuple tuple_struct map struct identifier ignored_any
    }
}
