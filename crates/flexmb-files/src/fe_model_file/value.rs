//! Values of the FE model file that take a form of their own: node labels (positive integers) and the
//! degrees of freedom of a support (a keyword or a list of names).

use std::fmt;

use serde::de::{self, Deserializer, SeqAccess, Unexpected, Visitor};
use serde::Deserialize;

use crate::model_file::schema::Name;

/// A node label: a positive integer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct NodeLabel(pub u64);

impl<'de> Deserialize<'de> for NodeLabel {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(NodeLabelVisitor)
    }
}

struct NodeLabelVisitor;

impl Visitor<'_> for NodeLabelVisitor {
    type Value = NodeLabel;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a node label (a positive integer)")
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        match u64::try_from(v) {
            Ok(label) if label > 0 => Ok(NodeLabel(label)),
            _ => Err(E::invalid_value(Unexpected::Signed(v), &self)),
        }
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        if v > 0 {
            Ok(NodeLabel(v))
        } else {
            Err(E::invalid_value(Unexpected::Unsigned(v), &self))
        }
    }
}

/// The `dofs` of a support: a keyword (`"all"`, `"translations"`, `"rotations"`) or a list of degree
/// of freedom names (`["x", "rz"]`).
#[derive(Clone, Debug)]
pub(crate) enum DofsInput {
    Keyword(String),
    List(Vec<Name>),
}

impl<'de> Deserialize<'de> for DofsInput {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(DofsVisitor)
    }
}

struct DofsVisitor;

impl<'de> Visitor<'de> for DofsVisitor {
    type Value = DofsInput;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(r#"degrees of freedom: "all", "translations", "rotations" or an array such as ["x", "y", "rz"]"#)
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        Ok(DofsInput::Keyword(v.to_string()))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut names = Vec::new();
        while let Some(name) = seq.next_element::<Name>()? {
            names.push(name);
        }
        Ok(DofsInput::List(names))
    }
}
