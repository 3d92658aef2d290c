//! Values that take more than one TOML form: a number or an expression string, and the three ways of
//! writing an inertia tensor.

use std::fmt;

use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;

/// A TOML number, or a string holding an expression.
///
/// Where the file expects a constant, the expression may use `[parameters]` only; where it expects a
/// function (actuators, force components, driver functions, distance lengths), it may also use `t` and
/// measures.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum NumberOrExpression {
    Number(f64),
    Expression(String),
}

impl<'de> Deserialize<'de> for NumberOrExpression {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(NumberOrExpressionVisitor)
    }
}

struct NumberOrExpressionVisitor;

impl Visitor<'_> for NumberOrExpressionVisitor {
    type Value = NumberOrExpression;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number or an expression string")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
        Ok(NumberOrExpression::Number(v))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        Ok(NumberOrExpression::Number(v as f64))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        Ok(NumberOrExpression::Number(v as f64))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        Ok(NumberOrExpression::Expression(v.to_string()))
    }
}

/// An inertia tensor about the centre of mass in body axes (kg m²), in any of its three forms.
#[derive(Clone, Debug, Deserialize)]
#[serde(
    untagged,
    expecting = "an inertia: principal moments [Ixx, Iyy, Izz], a symmetric 3x3 matrix \
                 [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]], or a table \
                 { xx = .., yy = .., zz = .., xy = 0, xz = 0, yz = 0 }"
)]
pub(crate) enum InertiaInput {
    Diagonal([NumberOrExpression; 3]),
    Matrix([[NumberOrExpression; 3]; 3]),
    Components(InertiaComponents),
}

/// The table form of an inertia tensor; products of inertia default to zero.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct InertiaComponents {
    pub xx: NumberOrExpression,
    pub yy: NumberOrExpression,
    pub zz: NumberOrExpression,
    pub xy: Option<NumberOrExpression>,
    pub xz: Option<NumberOrExpression>,
    pub yz: Option<NumberOrExpression>,
}
