//! Element matrices: stiffness and mass of one element, in body-frame components, 6 degrees of
//! freedom per node (`ux uy uz rx ry rz`) in the order of the element's nodes (solids, which have no
//! rotations, have zero rows and columns there).
//!
//! A lumped mass is, at each node, a point mass (the same in all three translations) and optionally a
//! 3×3 rotary inertia about the node; with rotary inertia off the mass matrix is diagonal, as in the
//! seed. A consistent mass is a set of [`MassPoint`]s at the element's Gauss points that move with
//! its displacement field.

pub mod beam;
mod mass_point;
pub mod shell;
pub mod solid;
mod stress_points;
#[cfg(test)]
mod test_support;
mod validate;

use nalgebra::{DMatrix, Matrix3};

pub use mass_point::MassPoint;
pub use stress_points::{element_stress, ElementStress, StressPlace};
pub(crate) use mass_point::gauss_legendre_4;

use crate::mesh::{Element, ElementKind, Mesh, ModelOptions};

/// The stiffness matrix (symmetric, 6n × 6n) and the mass of one element.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementMatrices {
    /// The stiffness in body-frame components (6n × 6n).
    pub stiffness: DMatrix<f64>,
    /// The lumped mass, one entry per node (always computed: the nodes' share of the mass).
    pub lumped_mass: Vec<NodalMass>,
    /// When the element's mass is [`MassModel::Consistent`](crate::mesh::MassModel::Consistent) ([`ModelOptions::mass_of`]), the
    /// mass points of the consistent mass (interpolation indices are the element's node positions
    /// 0..n); empty when it is lumped.
    pub consistent_mass: Vec<MassPoint>,
}

/// The mass an element lumps at one of its nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodalMass {
    /// Translational mass (kg), the same along the three axes.
    pub mass: f64,
    /// Rotary inertia about the node in body-frame components (kg m²), symmetric; zero unless the
    /// model asks for rotary inertia.
    pub rotary_inertia: Matrix3<f64>,
}

/// Why an element's matrices cannot be formed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// The element has the wrong number of nodes for its kind.
    #[error("the element has {found} nodes; a {kind} needs {expected}")]
    NodeCount {
        /// `beam`, `shell` or the solid's Abaqus name.
        kind: &'static str,
        /// The numbers it may have.
        expected: &'static str,
        /// The number it has.
        found: usize,
    },
    /// The element refers to a node, section or material the mesh does not have.
    #[error("{kind} index {index} is beyond the mesh's {count}")]
    UnknownIndex {
        /// `node`, `beam section`, `shell section` or `material`.
        kind: &'static str,
        /// The index given.
        index: usize,
        /// How many the mesh has.
        count: usize,
    },
    /// A beam's two nodes coincide.
    #[error("the beam has zero length (its two nodes coincide)")]
    ZeroLength,
    /// A beam's orientation vector does not fix its cross-section axes.
    #[error("the beam's orientation vector is parallel to the beam axis")]
    OrientationParallel,
    /// A shell without area.
    #[error("the shell is degenerate (zero or negative area, or collinear nodes)")]
    DegenerateShape,
    /// A quadrilateral shell whose nodes are not in one plane.
    #[error("the shell's nodes are not in one plane: warp {warp:.3e} relative to its size")]
    Warped {
        /// The distance from the mean plane relative to the element's size.
        warp: f64,
    },
    /// A solid element whose Jacobian determinant is not positive at an integration point: its
    /// nodes are out of order (inverted) or collapsed.
    #[error("the solid element is inverted or degenerate: its Jacobian determinant is {determinant:.3e} ({relative:.2e} of its size cubed over the reference volume) at natural coordinates ({:.3}, {:.3}, {:.3}); check the node order", at[0], at[1], at[2])]
    InvertedSolid {
        /// `det J` at that point (m³ per reference volume).
        determinant: f64,
        /// `det J` relative to the element's size cubed over the reference volume.
        relative: f64,
        /// The integration point's natural coordinates.
        at: [f64; 3],
    },
    /// A property that must be positive is not.
    #[error("{property} must be positive and finite, got {value}")]
    InvalidProperty {
        /// The property's name.
        property: &'static str,
        /// The value given.
        value: f64,
    },
    /// A property that may be zero or negative (density, Poisson's ratio, the drilling stiffness
    /// factor) is outside its range; `requirement` says what the range is.
    #[error("{property} must be {requirement}, got {value}")]
    OutOfRange {
        /// The property's name.
        property: &'static str,
        /// Its range, in words.
        requirement: &'static str,
        /// The value given.
        value: f64,
    },
}

/// The matrices of `element` of `mesh`.
pub fn element_matrices(
    mesh: &Mesh,
    element: &Element,
    options: &ModelOptions,
) -> Result<ElementMatrices, ElementError> {
    let points = element_points(mesh, element)?;
    match element.kind {
        ElementKind::Beam { section } => {
            let section = lookup(&mesh.beam_sections, "beam section", section)?;
            let material = lookup(&mesh.materials, "material", section.material)?;
            if points.len() != 2 {
                return Err(ElementError::NodeCount { kind: "beam", expected: "2", found: points.len() });
            }
            beam::beam_matrices(&points[0], &points[1], section, material, options)
        }
        ElementKind::Shell { section } => {
            let section = lookup(&mesh.shell_sections, "shell section", section)?;
            let material = lookup(&mesh.materials, "material", section.material)?;
            if points.len() != 3 && points.len() != 4 {
                return Err(ElementError::NodeCount { kind: "shell", expected: "3 or 4", found: points.len() });
            }
            shell::shell_matrices(&points, section, material, options)
        }
        ElementKind::Solid { section, formulation } => {
            let section = lookup(&mesh.solid_sections, "solid section", section)?;
            let material = lookup(&mesh.materials, "material", section.material)?;
            solid::solid_matrices(&points, formulation, material, options)
        }
    }
}

/// The positions of `element`'s nodes.
fn element_points(mesh: &Mesh, element: &Element) -> Result<Vec<nalgebra::Vector3<f64>>, ElementError> {
    element.nodes.iter().map(|&n| lookup(&mesh.nodes, "node", n).map(|node| node.position)).collect()
}

/// `items[index]`, or the error that says the mesh has no such `kind`.
fn lookup<'a, T>(items: &'a [T], kind: &'static str, index: usize) -> Result<&'a T, ElementError> {
    items.get(index).ok_or(ElementError::UnknownIndex { kind, index, count: items.len() })
}
