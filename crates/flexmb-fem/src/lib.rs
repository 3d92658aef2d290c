//! # flexmb-fem — the finite-element preprocessor of flexmb
//!
//! A flexible body of flexmb is built, as in the DADS code of Haug's *Dynamics of Articulated
//! Structures*, from a finite-element model (the seed's lumped mass, or the consistent one, the default of
//! beams and solids): 3D beams and flat shells (membrane plus bending) with 6 degrees of freedom per node, and
//! solid elements (CalculiX's C3D4 … C3D20R) whose nodes have the three translations, tied to joints
//! through rigid couplings to reference nodes. This crate
//!
//! 1. holds the model ([`mesh`]: nodes, materials, sections, elements, point masses, generators of
//!    regular meshes, and the Abaqus/CalculiX `.inp` reader in [`inp`]),
//! 2. computes element matrices ([`element`]) and assembles the global sparse stiffness and mass
//!    ([`assembly`]) with boundary conditions per node and degree of freedom,
//! 3. finds the vibration modes ([`modes`]: dense or shift-invert Lanczos, rigid mechanisms left by
//!    under-determined supports detected and set aside) and the static correction modes,
//! 4. reduces the model to a mode set such as `4N5S` and evaluates the inertia invariants of the
//!    equations of motion ([`reduction`]), written as a flexible-body file.
//!
//! [`reduction::reduce`] runs the whole chain on an [`FeModel`] (its documentation reduces a steel
//! cantilever and checks its first frequency and mass); every part of the model that refers to a node,
//! material or section by index is checked first ([`FeModel::check_references`]), so a bad index is a
//! [`FemError`], not a panic.
//!
//! [`input`] holds the guards on what users give it, shared with the `flexmb` program: how input
//! files are read (regular files, a size limit) and the windows of physical magnitudes.

#![warn(missing_docs)]

pub mod assembly;
pub mod element;
pub mod inp;
pub mod input;
mod error;
pub mod memory;
pub mod mesh;
pub mod modes;
pub mod reduction;
pub mod static_correction;
mod symmetric_product;

pub use error::FemError;

pub use mesh::{
    BeamSection, Dof, DofSet, Element, ElementKind, FeModel, Material, Mesh, Node, PointMass,
    DistributingCoupling, MassModel, ModelOptions, RigidCoupling, SectionOutline, ShellSection, SolidFormulation, SolidSection, StaticLoad,
    StaticLoadKind, Support,
};
