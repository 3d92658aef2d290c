//! What can go wrong in the preprocessor, with the node, element or mode it concerns.

use crate::element::ElementError;

/// Bytes in a MiB, the unit of the memory messages (as `FLEXMB_MEMORY_LIMIT`'s `M`).
const MIB: f64 = 1024.0 * 1024.0;

/// An error of the finite-element preprocessor.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FemError {
    /// An element's matrices cannot be formed.
    #[error("element {label}: {source}")]
    Element {
        /// The element's label.
        label: u64,
        /// Why.
        source: ElementError,
    },
    /// Every degree of freedom is supported.
    #[error("the model has no free degree of freedom")]
    NoFreeDofs,
    /// A degree of freedom no element resists.
    #[error("node {label} dof {dof} has no stiffness: the node is not connected to any element that resists this motion; support it or connect it")]
    NoStiffness {
        /// The node's label.
        label: u64,
        /// The dof's name (`ux` … `rz`).
        dof: &'static str,
    },
    /// A point mass that is negative or not finite.
    #[error("node {label}: point mass must be non-negative and finite, got {mass}")]
    InvalidPointMass {
        /// The node's label.
        label: u64,
        /// The mass given (kg).
        mass: f64,
    },
    /// No element or point mass has mass.
    #[error("the model has no mass: the vibration modes are undefined")]
    NoMass,
    /// The stiffness is singular beyond the rigid motions: a mechanism.
    #[error("the stiffness matrix is singular beyond the rigid motions the supports leave ({rigid} of them): the mesh has a mechanism (disconnected parts, a hinge, or a dof held by nothing)")]
    Mechanism {
        /// How many rigid motions the supports leave.
        rigid: usize,
    },
    /// More modes asked for than the model has.
    #[error("asked for {asked} vibration modes but the model has only {available} elastic degrees of freedom with mass")]
    TooManyModes {
        /// Modes asked for.
        asked: usize,
        /// Elastic dofs with mass.
        available: usize,
    },
    /// The eigensolver did not find every mode asked for.
    #[error("the eigensolver found {converged} of {asked} modes; try more Lanczos vectors or the dense solver")]
    EigenNotConverged {
        /// Modes asked for.
        asked: usize,
        /// Modes found.
        converged: usize,
    },
    /// A mode's residual `‖K φ − ω² M φ‖` is too large.
    #[error("mode {mode}: eigen residual {residual:.2e} exceeds {tolerance:.0e}")]
    EigenResidual {
        /// The mode's number (from 1).
        mode: usize,
        /// Its relative residual.
        residual: f64,
        /// The largest residual accepted.
        tolerance: f64,
    },
    /// A rigid coupling that cannot be formed.
    #[error("the rigid coupling of reference node {reference}: {reason}")]
    InvalidCoupling {
        /// The reference node's label.
        reference: u64,
        /// Why.
        reason: String,
    },
    /// A distributing coupling that cannot be formed.
    #[error("the distributing coupling of reference node {reference}: {reason}")]
    InvalidDistributingCoupling {
        /// The reference node's label.
        reference: u64,
        /// Why.
        reason: String,
    },
    /// A point mass with rotary inertia at a node that only solid elements touch (no rotations).
    #[error("node {label}: a point mass with rotary inertia at a node of solid elements only, which has no rotations; put it at a reference node coupled to the solid, or give the mass alone")]
    RotaryInertiaWithoutRotations {
        /// The node's label.
        label: u64,
    },
    /// A static load acts on a dof the node does not have (a rotation of a solid-only node).
    #[error("static load {name}: acts on node {label} dof {dof}, which the node does not have (only solid elements touch it: translations only); apply it at a reference node coupled to the solid")]
    LoadOnAbsentDof {
        /// The static load's name.
        name: String,
        /// The node's label.
        label: u64,
        /// The dof's name.
        dof: &'static str,
    },
    /// A static load acts on a supported dof.
    #[error("static load {name}: acts on node {label} dof {dof}, which is supported; a static correction mode needs a deleted constraint, not a supported one")]
    LoadOnSupport {
        /// The static load's name.
        name: String,
        /// The node's label.
        label: u64,
        /// The dof's name.
        dof: &'static str,
    },
    /// A mode set that cannot be read or does not fit the model.
    #[error("mode set `{text}`: {message}")]
    ModeSet {
        /// The mode set as written.
        text: String,
        /// What is wrong.
        message: String,
    },
    /// The modes of the basis are linearly dependent.
    #[error("the mode basis is singular: {message}")]
    SingularBasis {
        /// Which modes depend on the others.
        message: String,
    },
    /// The mode analysis would need more memory than it may use.
    #[error(
        "the mesh is too large for the mode analysis: {elements} elements and {nodes} nodes need about {:.1} MiB, \
         more than the {:.1} MiB it may use; use a coarser mesh",
        *needed as f64 / MIB,
        *limit as f64 / MIB
    )]
    TooLarge {
        /// Elements of the mesh.
        elements: usize,
        /// Nodes of the mesh.
        nodes: usize,
        /// Bytes the analysis would need.
        needed: u64,
        /// Bytes it may use.
        limit: u64,
    },
    /// The dense eigensolver would need more memory than it may use.
    #[error(
        "the dense eigensolver needs about {:.1} MiB for an operator of dimension {dimension}, more than the \
         {:.1} MiB it may use; use the Lanczos solver",
        *needed as f64 / MIB,
        *limit as f64 / MIB
    )]
    DenseTooLarge {
        /// The operator's dimension.
        dimension: usize,
        /// Bytes the solver would need.
        needed: u64,
        /// Bytes it may use.
        limit: u64,
    },
    /// The shifted operator has values that are not finite.
    #[error("the mode analysis's operator is not finite: the model's coordinates or properties overflow double precision")]
    NotFinite,
    /// The inputs of [`InertiaInvariants::new`](crate::reduction::InertiaInvariants::new) disagree in
    /// size.
    #[error("inertia invariants: {message}")]
    InvariantInputs {
        /// What disagrees.
        message: String,
    },
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
    /// Stiffness and mass matrices exported by another program that flexmb cannot take.
    #[error("the matrices of {origin}: {message}")]
    ImportedMatrices {
        /// The stiffness file they came from.
        origin: String,
        /// What is wrong.
        message: String,
    },
    /// A factorization failed for a reason not covered above.
    #[error("linear algebra: {0}")]
    LinearAlgebra(String),
}
