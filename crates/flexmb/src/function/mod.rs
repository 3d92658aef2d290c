//! User functions written in the model file: expressions of time and of named measures; and laws
//! given as code (closures) in their place.

mod expression;
pub mod expression_text;
mod time_function;
mod user_function;

pub use expression::{Expression, ExpressionError, Variable};
pub use time_function::TimeFunction;
pub use user_function::{ForceLaw, MotionLaw, UserFunction, UserLawFailure, UserMotion};
