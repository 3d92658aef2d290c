//! Errors found while building a model. Each names the element it concerns; the model-file layer adds
//! the file, key path and line.

use crate::function::ExpressionError;

/// Why an element could not be added to a [`ModelBuilder`](super::ModelBuilder), or a model built.
///
/// Every variant names the element (`element` is its kind, such as `"marker"` or `"rotational
/// spring-damper"`, `name` its name) and says what was expected.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum ModelError {
    /// Two elements of one kind share a name.
    #[error("{kind} name '{name}' is used twice")]
    DuplicateName {
        /// The kind of element: `body`, `marker`, `joint`, `force`, `measure` or `output`.
        kind: &'static str,
        /// The name given twice.
        name: String,
    },
    /// An element refers to a body, marker, joint or measure by an id the builder did not hand out.
    #[error("{element} '{name}': no {kind} has id {index} (this builder has {count})")]
    UnknownId {
        /// The kind of the element that refers to the id.
        element: &'static str,
        /// Its name.
        name: String,
        /// What the id should name: `body`, `marker`, `joint` or `measure`.
        kind: &'static str,
        /// The id's index.
        index: usize,
        /// How many elements of that kind the builder holds.
        count: usize,
    },
    /// A body's mass is zero, negative or not finite.
    #[error("body '{body}': mass must be positive and finite, got {mass}")]
    NonPositiveMass {
        /// The body's name.
        body: String,
        /// The mass given (kg).
        mass: f64,
    },
    /// A body's inertia tensor is not a physical one (not finite, not symmetric, not positive
    /// definite, or violating the triangle inequality).
    #[error("body '{body}': inertia {problem}")]
    BadInertia {
        /// The body's name.
        body: String,
        /// What is wrong, with the principal moments where they matter.
        problem: String,
    },
    /// A marker's axes or a body's initial orientation are not a proper orthonormal frame, or a
    /// marker's origin is not finite.
    #[error("{what}: {problem}")]
    BadFrame {
        /// The frame: `marker 'name'` or `body 'name' initial orientation`.
        what: String,
        /// What is wrong.
        problem: String,
    },
    /// A joint's two markers are on the same body (or both on ground).
    #[error("joint '{joint}': both markers are on {body}")]
    JointOnOneBody {
        /// The joint's name.
        joint: String,
        /// `ground` or `body 'name'`.
        body: String,
    },
    /// A force element or measure needs a joint that allows a motion the joint it names does not.
    #[error("{element} '{name}' needs a joint that allows {motion}, but '{joint}' is a {kind} joint")]
    WrongJointKind {
        /// The kind of the element that names the joint.
        element: &'static str,
        /// Its name.
        name: String,
        /// The joint's name.
        joint: String,
        /// The joint's kind (its keyword).
        kind: &'static str,
        /// The motion needed: `a rotation about z_i` or `a translation along z_i`.
        motion: &'static str,
    },
    /// An element's expression could not be used.
    #[error("{element} '{name}': {source}")]
    Expression {
        /// The kind of the element.
        element: &'static str,
        /// Its name.
        name: String,
        /// Why the expression failed.
        #[source]
        source: ExpressionError,
    },
    /// A value of an element is out of its range (a negative stiffness, a node index beyond a flexible
    /// body's nodes, sizes of a modal body that disagree, …).
    #[error("{element} '{name}': {problem}")]
    BadValue {
        /// The kind of the element.
        element: &'static str,
        /// Its name.
        name: String,
        /// What is wrong and what was expected.
        problem: String,
    },
}
