//! User functions written in the model file: expressions of time and of named measures.

mod expression;
pub mod expression_text;
mod time_function;

pub use expression::{Expression, ExpressionError, Variable};
pub use time_function::TimeFunction;
