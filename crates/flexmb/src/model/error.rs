//! Errors found while building a model. Each names the element it concerns; the model-file layer adds
//! the file, key path and line.

use crate::function::ExpressionError;

/// Why a model could not be built.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum ModelError {
    #[error("{kind} name '{name}' is used twice")]
    DuplicateName { kind: &'static str, name: String },
    #[error("body '{body}': mass must be positive and finite, got {mass}")]
    NonPositiveMass { body: String, mass: f64 },
    #[error("body '{body}': inertia {problem}")]
    BadInertia { body: String, problem: String },
    #[error("{what}: {problem}")]
    BadFrame { what: String, problem: String },
    #[error("joint '{joint}': both markers are on {body}")]
    JointOnOneBody { joint: String, body: String },
    #[error("{element} '{name}' needs a joint that allows {motion}, but '{joint}' is a {kind} joint")]
    WrongJointKind { element: &'static str, name: String, joint: String, kind: &'static str, motion: &'static str },
    #[error("{element} '{name}': {source}")]
    Expression {
        element: &'static str,
        name: String,
        #[source]
        source: ExpressionError,
    },
    #[error("{element} '{name}': {problem}")]
    BadValue { element: &'static str, name: String, problem: String },
}
