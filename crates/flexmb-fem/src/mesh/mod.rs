//! The finite-element model of one flexible body: nodes with 6 degrees of freedom (three
//! translations, three rotations), materials, beam, shell and solid sections, elements, point masses,
//! and, in [`FeModel`], the boundary conditions and the unit loads of the static correction modes.
//!
//! Solid elements have translations only: a node that solids touch and no beam or shell does has no
//! rotational degrees of freedom in the assembled model (no stiffness, no mass); see
//! [`crate::assembly::DofMap`].
//!
//! Elements refer to nodes by index into [`Mesh::nodes`]; each node also keeps the label it has in
//! the user's input (an `.inp` node number or a generated one), which is what messages show.

mod coupling;
mod distributing_coupling;
mod dof;
mod generate;
mod imported_matrices;
mod references;
mod rigid_coupling;

use std::collections::BTreeMap;

use nalgebra::Vector3;

pub use distributing_coupling::DistributingCoupling;
pub use dof::{Dof, DofSet};
pub use generate::ShellShape;
pub use imported_matrices::ImportedMatrices;
pub(crate) use imported_matrices::{NodeShare, SplitMass};
pub use rigid_coupling::RigidCoupling;
pub(crate) use coupling::{dependent_dofs, DependentDof};


/// A node of the mesh: its label in the input and its undeformed position in the body frame (m).
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The label in the input (an `.inp` node number or a generated one), for messages.
    pub label: u64,
    /// Undeformed position in the body frame (m).
    pub position: Vector3<f64>,
}

/// An isotropic linear-elastic material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The material's name.
    pub name: String,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν (-); the shear modulus is G = E / (2 (1 + ν)).
    pub poisson_ratio: f64,
    /// Mass density ρ (kg/m³).
    pub density: f64,
}

impl Material {
    /// Shear modulus G = E / (2 (1 + ν)).
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }
}

/// The cross-section of a 3D beam, in its local axes: x along the beam from its first node to its
/// second, y the cross-section axis given by [`orientation`](Self::orientation), z = x × y.
#[derive(Clone, Debug, PartialEq)]
pub struct BeamSection {
    /// The section's name.
    pub name: String,
    /// Index into [`Mesh::materials`].
    pub material: usize,
    /// Area A (m²).
    pub area: f64,
    /// Second moment of area about the local y axis, ∫ z² dA (m⁴): bending in the x–z plane.
    pub iy: f64,
    /// Second moment of area about the local z axis, ∫ y² dA (m⁴): bending in the x–y plane.
    pub iz: f64,
    /// Torsion constant J (m⁴).
    pub torsion_constant: f64,
    /// A vector, in body-frame components, that fixes the local y axis: y is its part normal to the
    /// beam axis (Abaqus' first cross-section direction n₁). Must not be parallel to the beam.
    pub orientation: Vector3<f64>,
    /// Timoshenko shear coefficient k (shear area k A in both directions, e.g. 5/6 for a rectangle);
    /// `None` for Euler–Bernoulli beams (no shear deformation).
    pub shear_coefficient: Option<f64>,
    /// The section's outline, where the stress recovery looks for the largest bending stress.
    pub outline: SectionOutline,
}

/// A beam section's outline in its local y–z plane, centred on the beam axis: where the bending
/// stress is largest (the element's stress recovery checks its extreme fibres).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum SectionOutline {
    /// Only the properties are known: the rectangle with the same area and second moments,
    /// half-widths `√(3 Iz / A)` along y and `√(3 Iy / A)` along z.
    #[default]
    Equivalent,
    /// A rectangle (solid or a box) with half-widths along local y and z (m).
    Rectangle {
        /// Half the width along local y (m).
        half_y: f64,
        /// Half the width along local z (m).
        half_z: f64,
    },
    /// A circle or a tube of outside radius `radius` (m).
    Round {
        /// The outside radius (m).
        radius: f64,
    },
}

/// The section of a flat shell (membrane plus bending) element: material and uniform thickness.
#[derive(Clone, Debug, PartialEq)]
pub struct ShellSection {
    /// The section's name.
    pub name: String,
    /// Index into [`Mesh::materials`].
    pub material: usize,
    /// Thickness t (m).
    pub thickness: f64,
}

/// The section of solid (continuum) elements: the material fills the element.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidSection {
    /// The section's name.
    pub name: String,
    /// Index into [`Mesh::materials`].
    pub material: usize,
}

/// The isoparametric solid element formulations, each the CalculiX/Abaqus element of that name (see
/// [`element::solid`](crate::element::solid)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolidFormulation {
    /// C3D4: 4-node linear tetrahedron (constant strain).
    LinearTetrahedron,
    /// C3D10: 10-node quadratic tetrahedron.
    QuadraticTetrahedron,
    /// C3D6: 6-node linear wedge (triangular prism).
    LinearWedge,
    /// C3D15: 15-node quadratic wedge.
    QuadraticWedge,
    /// C3D8: 8-node trilinear brick, full 2 × 2 × 2 integration.
    LinearBrick,
    /// C3D8I: 8-node brick enhanced by incompatible (bubble) modes, condensed out.
    IncompatibleModeBrick,
    /// C3D20: 20-node serendipity brick, full 3 × 3 × 3 integration.
    QuadraticBrick,
    /// C3D20R: 20-node serendipity brick, reduced 2 × 2 × 2 integration.
    ReducedQuadraticBrick,
}

impl SolidFormulation {
    /// All of them, in the order of the documentation.
    pub const ALL: [SolidFormulation; 8] = [
        SolidFormulation::LinearTetrahedron,
        SolidFormulation::QuadraticTetrahedron,
        SolidFormulation::LinearWedge,
        SolidFormulation::QuadraticWedge,
        SolidFormulation::LinearBrick,
        SolidFormulation::IncompatibleModeBrick,
        SolidFormulation::QuadraticBrick,
        SolidFormulation::ReducedQuadraticBrick,
    ];

    /// The Abaqus/CalculiX element type.
    pub fn abaqus_name(self) -> &'static str {
        match self {
            SolidFormulation::LinearTetrahedron => "C3D4",
            SolidFormulation::QuadraticTetrahedron => "C3D10",
            SolidFormulation::LinearWedge => "C3D6",
            SolidFormulation::QuadraticWedge => "C3D15",
            SolidFormulation::LinearBrick => "C3D8",
            SolidFormulation::IncompatibleModeBrick => "C3D8I",
            SolidFormulation::QuadraticBrick => "C3D20",
            SolidFormulation::ReducedQuadraticBrick => "C3D20R",
        }
    }

    /// The formulation of an Abaqus/CalculiX element type.
    pub fn from_abaqus_name(name: &str) -> Option<SolidFormulation> {
        SolidFormulation::ALL.into_iter().find(|f| f.abaqus_name().eq_ignore_ascii_case(name))
    }

    /// The number of nodes.
    pub fn node_count(self) -> usize {
        match self {
            SolidFormulation::LinearTetrahedron => 4,
            SolidFormulation::QuadraticTetrahedron => 10,
            SolidFormulation::LinearWedge => 6,
            SolidFormulation::QuadraticWedge => 15,
            SolidFormulation::LinearBrick | SolidFormulation::IncompatibleModeBrick => 8,
            SolidFormulation::QuadraticBrick | SolidFormulation::ReducedQuadraticBrick => 20,
        }
    }
}

/// What an element is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementKind {
    /// A 2-node 3D beam; `section` indexes [`Mesh::beam_sections`].
    Beam {
        /// Index into [`Mesh::beam_sections`].
        section: usize,
    },
    /// A 3-node (triangle) or 4-node (quadrilateral) flat shell; `section` indexes
    /// [`Mesh::shell_sections`]. Nodes go around the element in order.
    Shell {
        /// Index into [`Mesh::shell_sections`].
        section: usize,
    },
    /// A solid (continuum) element with translations only at its nodes; `section` indexes
    /// [`Mesh::solid_sections`]. Nodes in the Abaqus/CalculiX order of `formulation`.
    Solid {
        /// Index into [`Mesh::solid_sections`].
        section: usize,
        /// Which element.
        formulation: SolidFormulation,
    },
}

impl ElementKind {
    /// `beam`, `shell`, or the solid's Abaqus name.
    pub fn name(self) -> &'static str {
        match self {
            ElementKind::Beam { .. } => "beam",
            ElementKind::Shell { .. } => "shell",
            ElementKind::Solid { formulation, .. } => formulation.abaqus_name(),
        }
    }

    /// Whether its nodes carry rotations (beams and shells) or translations only (solids).
    pub fn has_rotations(self) -> bool {
        !matches!(self, ElementKind::Solid { .. })
    }
}

/// One element: its kind and its nodes (indices into [`Mesh::nodes`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Label in the input (an `.inp` element number or a generated one), for messages.
    pub label: u64,
    /// What it is and its section.
    pub kind: ElementKind,
    /// Its nodes, indices into [`Mesh::nodes`].
    pub nodes: Vec<usize>,
}

/// A concentrated mass at a node, with optional rotary inertia about the node (body axes, diagonal).
#[derive(Clone, Debug, PartialEq)]
pub struct PointMass {
    /// The node, an index into [`Mesh::nodes`].
    pub node: usize,
    /// Mass (kg).
    pub mass: f64,
    /// Rotary inertia about the node in body axes (kg m²), diagonal entries `[Jxx, Jyy, Jzz]`.
    pub rotary_inertia: Vector3<f64>,
}

/// A finite-element mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// The nodes; elements, point masses, supports and loads refer to them by index.
    pub nodes: Vec<Node>,
    /// The materials; sections refer to them by index.
    pub materials: Vec<Material>,
    /// The sections of beam elements.
    pub beam_sections: Vec<BeamSection>,
    /// The sections of shell elements.
    pub shell_sections: Vec<ShellSection>,
    /// The sections of solid elements.
    pub solid_sections: Vec<SolidSection>,
    /// The elements.
    pub elements: Vec<Element>,
    /// Concentrated masses at nodes.
    pub point_masses: Vec<PointMass>,
    /// Named sets of nodes (indices into [`nodes`](Self::nodes)), from `*NSET` or from the mesh
    /// generators.
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Rigid couplings of nodes to reference nodes (`*KINEMATIC COUPLING`, `*RIGID BODY`).
    pub rigid_couplings: Vec<RigidCoupling>,
    /// Distributing couplings of reference nodes to the weighted average motion of nodes
    /// (`*DISTRIBUTING COUPLING`).
    pub distributing_couplings: Vec<DistributingCoupling>,
    /// Stiffness and mass matrices another program exported, assembled with the elements.
    pub imported: Option<ImportedMatrices>,
}

impl Mesh {
    /// Adds a node and returns its index.
    pub fn add_node(&mut self, label: u64, position: Vector3<f64>) -> usize {
        self.nodes.push(Node { label, position });
        self.nodes.len() - 1
    }

    /// The index of the node with this label.
    pub fn node_index(&self, label: u64) -> Option<usize> {
        self.nodes.iter().position(|n| n.label == label)
    }

    /// The largest node label in use, 0 for an empty mesh.
    pub fn max_node_label(&self) -> u64 {
        self.nodes.iter().map(|n| n.label).max().unwrap_or(0)
    }

    /// The largest element label in use, 0 for an empty mesh.
    pub fn max_element_label(&self) -> u64 {
        self.elements.iter().map(|e| e.label).max().unwrap_or(0)
    }

    /// The node nearest to `position` and its distance, `None` for an empty mesh.
    pub fn nearest_node(&self, position: &Vector3<f64>) -> Option<(usize, f64)> {
        self.nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (i, (n.position - position).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// The diagonal of the box around all nodes (m), the length scale of tolerances.
    pub fn size(&self) -> f64 {
        let mut lo = Vector3::repeat(f64::INFINITY);
        let mut hi = Vector3::repeat(f64::NEG_INFINITY);
        for n in &self.nodes {
            lo = lo.inf(&n.position);
            hi = hi.sup(&n.position);
        }
        if self.nodes.is_empty() { 0.0 } else { (hi - lo).norm() }
    }
}

/// A boundary condition of the mode analysis: these degrees of freedom of this node are held at zero.
#[derive(Clone, Debug, PartialEq)]
pub struct Support {
    /// The node, an index into [`Mesh::nodes`].
    pub node: usize,
    /// The dofs held.
    pub dofs: DofSet,
}

/// What a static correction mode's unit load is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StaticLoadKind {
    /// A force along this direction (normalized to unit length, N) at the node.
    Force(Vector3<f64>),
    /// A torque about this axis (normalized to unit length, N m) at the node.
    Torque(Vector3<f64>),
}

/// The unit load of one static correction mode: a deleted joint constraint at a node.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticLoad {
    /// The mode's name (e.g. `bottom_hinge_rx`), for tables and files.
    pub name: String,
    /// The node it acts at, an index into [`Mesh::nodes`].
    pub node: usize,
    /// A force or a torque, and its direction.
    pub kind: StaticLoadKind,
}

/// How an element's mass is distributed over the degrees of freedom.
///
/// A model that names none ([`ModelOptions::mass`] `None`) gives each kind of element its own
/// default ([`ModelOptions::mass_of`]): the consistent mass for beams and solids, the lumped mass for
/// shells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MassModel {
    /// Each element's mass lumped at its nodes: a diagonal mass matrix (block-diagonal with rotary
    /// inertia), as in the seed. The inertia invariants are sums over the nodes.
    Lumped,
    /// The element's mass spread along its displacement field (the Hermite cubics of a beam, the
    /// bilinear or linear field of a shell, a solid's shape functions): the consistent mass matrix,
    /// `∫ ρ Nᵀ N`. The inertia invariants are integrals over the elements (Gauss points, exact for
    /// these fields).
    Consistent,
}

impl MassModel {
    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MassModel::Lumped => "lumped",
            MassModel::Consistent => "consistent",
        }
    }
}

/// Modelling options that change the element matrices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelOptions {
    /// The mass model of every element, or `None` (the default) for each kind's own
    /// ([`ModelOptions::mass_of`]).
    pub mass: Option<MassModel>,
    /// Rotary inertia as well as translational mass (default false, as in the seed): lumped at the
    /// nodes, or with a consistent mass the sections' own rotary inertia along the element.
    pub rotary_inertia: bool,
    /// Drilling stiffness of shells (about the element normal), as a fraction α of the plate
    /// bending stiffness E t³ / (12 (1 − ν²)) (see [`element::shell`](crate::element::shell)).
    /// Default 1e-3, which changes bending frequencies by less than 1e-4.
    pub drilling_stiffness: f64,
}

impl Default for ModelOptions {
    fn default() -> Self {
        Self { mass: None, rotary_inertia: false, drilling_stiffness: 1e-3 }
    }
}

impl ModelOptions {
    /// The mass model of an element of this kind: [`ModelOptions::mass`] if the model names one, else
    /// the kind's default.
    ///
    /// - **Beams: consistent.** Lumped, the nodes miss the kinetic energy of the Hermite field: a
    ///   cantilever's frequencies converge at second order instead of fourth, and a pendulum's
    ///   inertia about its hinge is `m L² (1/3 + 1/(6 n²))` instead of `m L² / 3`, which moves the
    ///   swing of a 10-element beam by many times its own elastic deflection.
    /// - **Solids: consistent**, CalculiX's and Abaqus'/ANSYS' mass for these elements; HRZ lumping
    ///   of the quadratic ones converges at second order from below.
    /// - **Shells: lumped**, more accurate on the plate tests than the consistent mass of these
    ///   elements (both converge at second order).
    pub fn mass_of(&self, kind: ElementKind) -> MassModel {
        match kind {
            ElementKind::Beam { .. } => self.beam_mass(),
            ElementKind::Shell { .. } => self.shell_mass(),
            ElementKind::Solid { .. } => self.solid_mass(),
        }
    }

    /// The mass model of beams: [`ModelOptions::mass`], else consistent.
    pub fn beam_mass(&self) -> MassModel {
        self.mass.unwrap_or(MassModel::Consistent)
    }

    /// The mass model of shells: [`ModelOptions::mass`], else lumped.
    pub fn shell_mass(&self) -> MassModel {
        self.mass.unwrap_or(MassModel::Lumped)
    }

    /// The mass model of solids: [`ModelOptions::mass`], else consistent.
    pub fn solid_mass(&self) -> MassModel {
        self.mass.unwrap_or(MassModel::Consistent)
    }
}

/// A flexible body's FE model: the mesh, the supports of the mode analysis, the unit loads of the
/// static correction modes, the interface nodes, and the modelling options.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FeModel {
    /// Nodes, materials, sections, elements, point masses.
    pub mesh: Mesh,
    /// The boundary conditions of the mode analysis.
    pub supports: Vec<Support>,
    /// The unit loads of the static correction modes.
    pub static_loads: Vec<StaticLoad>,
    /// The interface nodes (mesh indices, each once): the nodes where joints and force elements act
    /// on the body. The geometric-stiffness terms get six unit load cases at each.
    pub interface_nodes: Vec<usize>,
    /// Mass model, rotary inertia, drilling stiffness.
    pub options: ModelOptions,
}
