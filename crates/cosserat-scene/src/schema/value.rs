//! Scene values that are one of several TOML types: a shell named by index or name, a number or an
//! expression string, a world axis or a vector. Each has its own deserialiser, so a wrong type is
//! reported with a message that says what is accepted (an untagged serde enum would only say that no
//! variant matched).

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use std::fmt;

/// A shell named by index or name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ShellRef {
    /// Index in the shell list.
    Index(usize),
    /// Name.
    Name(String),
}

impl<'de> Deserialize<'de> for ShellRef {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = ShellRef;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a shell name or a shell index")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<ShellRef, E> {
                Ok(ShellRef::Name(v.to_string()))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ShellRef, E> {
                usize::try_from(v)
                    .map(ShellRef::Index)
                    .map_err(|_| E::custom(format!("a shell index must be non-negative, got {v}")))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ShellRef, E> {
                Ok(ShellRef::Index(v as usize))
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// A number or an expression string.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprValue {
    /// A constant.
    Number(f64),
    /// A formula.
    Text(String),
}

impl<'de> Deserialize<'de> for ExprValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = ExprValue;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an expression string")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<ExprValue, E> {
                Ok(ExprValue::Text(v.to_string()))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<ExprValue, E> {
                Ok(ExprValue::Number(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ExprValue, E> {
                Ok(ExprValue::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ExprValue, E> {
                Ok(ExprValue::Number(v as f64))
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// World axis names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxisName {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

impl AxisName {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            AxisName::X => 0,
            AxisName::Y => 1,
            AxisName::Z => 2,
        }
    }
}

/// An axis: `"x"`, `"y"`, `"z"` or a vector `[ax, ay, az]` (normalised in validation).
#[derive(Debug, Clone, PartialEq)]
pub enum AxisValue {
    /// A world axis.
    Named(AxisName),
    /// A direction.
    Vector([f64; 3]),
}

impl<'de> Deserialize<'de> for AxisValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = AxisValue;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("\"x\", \"y\", \"z\" or a vector [ax, ay, az]")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<AxisValue, E> {
                match v {
                    "x" => Ok(AxisValue::Named(AxisName::X)),
                    "y" => Ok(AxisValue::Named(AxisName::Y)),
                    "z" => Ok(AxisValue::Named(AxisName::Z)),
                    _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<AxisValue, A::Error> {
                let mut v = [0.0; 3];
                for (i, c) in v.iter_mut().enumerate() {
                    *c = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<f64>()?.is_some() {
                    return Err(de::Error::invalid_length(4, &self));
                }
                Ok(AxisValue::Vector(v))
            }
        }
        deserializer.deserialize_any(V)
    }
}
