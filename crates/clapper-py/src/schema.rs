//! The keys of a request and the kind of value each takes, read from the
//! request's own `Deserialize` (so they cannot drift from what the
//! library accepts). The Python half checks keyword options against these
//! before it writes JSON: it names an unknown option with the near ones,
//! and says what a wrong value should have been, in Python's terms, where
//! serde's message would quote JSON line and column numbers the user never
//! wrote.
//!
//! How: the request is deserialized from a deserializer that holds no
//! data. Asked for a struct, it first gives up with the struct's field
//! names (serde passes them); then, once per field, it offers just that
//! key, and the value's deserializer gives up with the kind of value the
//! field asked for (`deserialize_f64`: a number, `deserialize_enum`: one
//! of its variants, ...).

use std::cell::RefCell;
use std::fmt;
use std::rc::Rc;

use serde::de::{self, DeserializeOwned, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

/// The kind of value a request's key takes.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// A floating-point number.
    Number,
    /// A whole number; `true` when it cannot be negative.
    Whole(bool),
    /// Text.
    Text,
    /// true or false.
    Bool,
    /// One of these names.
    Choice(Vec<&'static str>),
    /// A fixed number of values of one kind.
    Array(usize, Box<Kind>),
    /// Anything else (a table, a list of any length).
    Other,
}

impl Kind {
    /// The kind as Python reads it: a tag, the choices, and for an array
    /// its length and its elements' tag.
    pub fn describe(&self) -> (String, Vec<String>, usize) {
        match self {
            Kind::Number => ("number".into(), vec![], 0),
            Kind::Whole(true) => ("count".into(), vec![], 0),
            Kind::Whole(false) => ("integer".into(), vec![], 0),
            Kind::Text => ("text".into(), vec![], 0),
            Kind::Bool => ("bool".into(), vec![], 0),
            Kind::Choice(v) => ("choice".into(), v.iter().map(|s| s.to_string()).collect(), 0),
            Kind::Array(n, inner) => {
                let (tag, choices, _) = inner.describe();
                (format!("array of {tag}"), choices, *n)
            }
            Kind::Other => ("other".into(), vec![], 0),
        }
    }
}

/// Why the probe stopped; never seen outside this module.
#[derive(Debug)]
struct Stop;

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("probe stopped")
    }
}

impl std::error::Error for Stop {}

impl de::Error for Stop {
    fn custom<T: fmt::Display>(_: T) -> Self {
        Stop
    }
}

/// What the probe found out.
#[derive(Default)]
struct Found {
    fields: Option<&'static [&'static str]>,
    kind: Option<Kind>,
}

type Shared = Rc<RefCell<Found>>;

/// Stands in for a whole request: asked for a struct, it records the
/// field names, then offers the one key `key` if there is one.
struct Request {
    found: Shared,
    key: Option<&'static str>,
}

impl<'de> Deserializer<'de> for Request {
    type Error = Stop;

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Stop> {
        self.found.borrow_mut().fields = Some(fields);
        match self.key {
            Some(key) => visitor.visit_map(OneKey {
                key: Some(key),
                found: self.found,
            }),
            None => Err(Stop),
        }
    }

    fn deserialize_any<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        Err(Stop)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf option unit unit_struct newtype_struct seq tuple
        tuple_struct map enum identifier ignored_any
    }
}

/// A map of one key whose value is a [`Value`] probe.
struct OneKey {
    key: Option<&'static str>,
    found: Shared,
}

impl<'de> MapAccess<'de> for OneKey {
    type Error = Stop;

    fn next_key_seed<K: DeserializeSeed<'de>>(&mut self, seed: K) -> Result<Option<K::Value>, Stop> {
        match self.key.take() {
            Some(k) => seed
                .deserialize(de::value::BorrowedStrDeserializer::<Stop>::new(k))
                .map(Some),
            None => Ok(None),
        }
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, Stop> {
        seed.deserialize(Value {
            found: self.found.clone(),
        })
    }
}

/// Stands in for one value: records what it was asked for, then stops.
struct Value {
    found: Shared,
}

impl Value {
    fn stop<T>(self, kind: Kind) -> Result<T, Stop> {
        self.found.borrow_mut().kind = Some(kind);
        Err(Stop)
    }
}

/// Stands in for the elements of a fixed-length array: the first element
/// records its kind.
struct Elements {
    found: Shared,
}

impl<'de> SeqAccess<'de> for Elements {
    type Error = Stop;

    fn next_element_seed<T: DeserializeSeed<'de>>(&mut self, seed: T) -> Result<Option<T::Value>, Stop> {
        seed.deserialize(Value {
            found: self.found.clone(),
        })
        .map(Some)
    }
}

impl<'de> Deserializer<'de> for Value {
    type Error = Stop;

    fn deserialize_any<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Other)
    }
    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Stop> {
        // Optional keys take what their value takes.
        visitor.visit_some(self)
    }
    fn deserialize_f64<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Number)
    }
    fn deserialize_f32<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Number)
    }
    fn deserialize_u8<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(true))
    }
    fn deserialize_u16<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(true))
    }
    fn deserialize_u32<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(true))
    }
    fn deserialize_u64<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(true))
    }
    fn deserialize_i8<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(false))
    }
    fn deserialize_i16<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(false))
    }
    fn deserialize_i32<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(false))
    }
    fn deserialize_i64<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Whole(false))
    }
    fn deserialize_str<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Text)
    }
    fn deserialize_string<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Text)
    }
    fn deserialize_bool<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Stop> {
        self.stop(Kind::Bool)
    }
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, Stop> {
        self.stop(Kind::Choice(variants.to_vec()))
    }
    fn deserialize_tuple<V: Visitor<'de>>(self, len: usize, visitor: V) -> Result<V::Value, Stop> {
        let found = self.found.clone();
        let _ = visitor.visit_seq(Elements { found: found.clone() });
        let inner = found.borrow_mut().kind.take().unwrap_or(Kind::Other);
        self.stop(Kind::Array(len, Box::new(inner)))
    }

    serde::forward_to_deserialize_any! {
        i128 u128 char bytes byte_buf unit unit_struct newtype_struct seq
        tuple_struct map struct identifier ignored_any
    }
}

/// The keys `T` accepts (every spelling serde knows, aliases too), each
/// with the kind of value it takes.
pub fn fields<T: DeserializeOwned>() -> Vec<(&'static str, Kind)> {
    let found: Shared = Rc::default();
    let _ = T::deserialize(Request {
        found: found.clone(),
        key: None,
    });
    let names = found.borrow().fields.unwrap_or(&[]);
    names
        .iter()
        .map(|&name| {
            found.borrow_mut().kind = None;
            let _ = T::deserialize(Request {
                found: found.clone(),
                key: Some(name),
            });
            let kind = found.borrow_mut().kind.take().unwrap_or(Kind::Other);
            (name, kind)
        })
        .collect()
}

/// A bell file's keys, as a type [`fields`] can read: its `Deserialize`
/// is the bell file's own.
pub struct BellFileKeys;

impl<'de> serde::Deserialize<'de> for BellFileKeys {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        clapper_io::bell_file::deserialize_bell_file(d).map(|()| BellFileKeys)
    }
}
