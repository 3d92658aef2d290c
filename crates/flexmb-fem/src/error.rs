//! What can go wrong in the preprocessor, with the node, element or mode it concerns.

use crate::element::ElementError;

/// Bytes in a MiB, the unit of the memory messages (as `FLEXMB_MEMORY_LIMIT`'s `M`).
const MIB: f64 = 1024.0 * 1024.0;

/// An error of the finite-element preprocessor.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FemError {
    #[error("element {label}: {source}")]
    Element { label: u64, source: ElementError },
    #[error("the model has no free degree of freedom")]
    NoFreeDofs,
    #[error("node {label} dof {dof} has no stiffness: the node is not connected to any element that resists this motion; support it or connect it")]
    NoStiffness { label: u64, dof: &'static str },
    #[error("node {label}: point mass must be non-negative and finite, got {mass}")]
    InvalidPointMass { label: u64, mass: f64 },
    #[error("the model has no mass: the vibration modes are undefined")]
    NoMass,
    #[error("the stiffness matrix is singular beyond the rigid motions the supports leave ({rigid} of them): the mesh has a mechanism (disconnected parts, a hinge, or a dof held by nothing)")]
    Mechanism { rigid: usize },
    #[error("asked for {asked} vibration modes but the model has only {available} elastic degrees of freedom with mass")]
    TooManyModes { asked: usize, available: usize },
    #[error("the eigensolver found {converged} of {asked} modes; try more Lanczos vectors or the dense solver")]
    EigenNotConverged { asked: usize, converged: usize },
    #[error("mode {mode}: eigen residual {residual:.2e} exceeds {tolerance:.0e}")]
    EigenResidual { mode: usize, residual: f64, tolerance: f64 },
    #[error("static load {name}: acts on node {label} dof {dof}, which is supported; a static correction mode needs a deleted constraint, not a supported one")]
    LoadOnSupport { name: String, label: u64, dof: &'static str },
    #[error("mode set `{text}`: {message}")]
    ModeSet { text: String, message: String },
    #[error("the mode basis is singular: {message}")]
    SingularBasis { message: String },
    #[error(
        "the mesh is too large for the mode analysis: {elements} elements and {nodes} nodes need about {:.1} MiB, \
         more than the {:.1} MiB it may use; use a coarser mesh",
        *needed as f64 / MIB,
        *limit as f64 / MIB
    )]
    TooLarge { elements: usize, nodes: usize, needed: u64, limit: u64 },
    #[error(
        "the dense eigensolver needs about {:.1} MiB for an operator of dimension {dimension}, more than the \
         {:.1} MiB it may use; use the Lanczos solver",
        *needed as f64 / MIB,
        *limit as f64 / MIB
    )]
    DenseTooLarge { dimension: usize, needed: u64, limit: u64 },
    #[error("the mode analysis's operator is not finite: the model's coordinates or properties overflow double precision")]
    NotFinite,
    /// A mesh generator was asked for nothing (no elements along a line, no cells across a plate).
    #[error("{generator}: {problem}")]
    Generator {
        /// `beam line` or `plate`.
        generator: &'static str,
        /// What was expected.
        problem: &'static str,
    },
    /// A part of the model refers to a node, material or section the model does not have.
    #[error("{part}: {kind} index {index} is beyond the model's {count}")]
    UnknownIndex {
        /// The part that refers to it: `element 12`, `beam section 'rod'`, `a support`, ….
        part: String,
        /// What the index should name: `node`, `material`, `beam section` or `shell section`.
        kind: &'static str,
        /// The index given.
        index: usize,
        /// How many the model has.
        count: usize,
    },
    #[error("linear algebra: {0}")]
    LinearAlgebra(String),
}
