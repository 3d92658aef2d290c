//! The geometric stiffening of a flexible body (formulation.md §11): the stress its own rigid-body
//! motion causes stiffens (or softens) its modes. The preprocessor solves the stress state of each
//! unit inertia load once and stores its modal geometric stiffness `G_k`; with the factors `f_k` of
//! the current motion the modal equations gain
//!
//! ```text
//! K_G(ā, ω̄̇, ω̄) a = Σ_k f_k G_k a,    f = [ā_x ā_y ā_z, ω̄̇_x ω̄̇_y ω̄̇_z, ω̄_x² ω̄_y² ω̄_z² ω̄_xω̄_y ω̄_yω̄_z ω̄_zω̄_x]
//! ```
//!
//! with `ā = Aᵀ(R̈ − g)` the frame's acceleration less gravity in body axes. A blade spun about its
//! root gains the centrifugal tension's stiffness `Ω² G_zz`; a column accelerated along its axis
//! (or standing in gravity) loses stiffness. The factors are linear in the accelerations `v̇`, so the
//! columns `∂(K_G a)/∂v̇` are exact entries of the Newton matrix
//! ([`inertia_jacobian_entries`](crate::stage)), not a lagged term.
//!
//! Loads the mechanism applies at the body's interface nodes stress it as well: with the force
//! `F̄` and moment `M̄` (body axes) at interface node `n`, the term gains `Σ_n Σ_c F̄M̄_{n,c} G_{n,c} a`
//! (the six unit loads `F_x … M_z` of each node, [`InterfaceGeometricStiffness`]). Those factors come
//! from the force elements (in the applied forces) and from the joints' multipliers (linear in `λ`).
//!
//! References: O. Wallrapp, R. Schwertassek, "Representation of geometric stiffening in multibody
//! system simulation", Int. J. Numer. Meth. Eng. 32 (1991).

use nalgebra::DMatrix;

use crate::math::Vec3;

/// The number of unit inertia cases: three accelerations, three angular accelerations, six
/// centrifugal products.
pub const INERTIA_CASES: usize = 12;

/// The modal geometric stiffness `G_k` (each `m × m`) of the twelve unit inertia loads of a body,
/// in the order of [`inertia_load_factors`].
#[derive(Clone, Debug, PartialEq)]
pub struct ModalGeometricStiffness {
    /// `G` of a unit `ā_x`, `ā_y`, `ā_z`, of a unit `ω̄̇_x`, `ω̄̇_y`, `ω̄̇_z`, and of the centrifugal
    /// products `ω̄_x²`, `ω̄_y²`, `ω̄_z²`, `ω̄_xω̄_y`, `ω̄_yω̄_z`, `ω̄_zω̄_x`.
    pub inertia_cases: Vec<DMatrix<f64>>,
    /// The six unit loads at each interface node (empty without interface nodes).
    pub interface: Vec<InterfaceGeometricStiffness>,
}

/// The number of unit load cases at an interface node: the forces `F_x F_y F_z` and the moments
/// `M_x M_y M_z`, body axes.
pub const INTERFACE_CASES: usize = 6;

/// The modal geometric stiffness `G` (each `m × m`) of the six unit loads at one interface node.
#[derive(Clone, Debug, PartialEq)]
pub struct InterfaceGeometricStiffness {
    /// The node (index into [`ModalBody::nodes`](super::ModalBody::nodes)).
    pub node: usize,
    /// `G` of a unit force `F_x`, `F_y`, `F_z` and a unit moment `M_x`, `M_y`, `M_z` at the node.
    pub loads: Vec<DMatrix<f64>>,
}

impl ModalGeometricStiffness {
    /// The terms of the inertia cases alone (no interface nodes).
    pub fn of_inertia_cases(inertia_cases: Vec<DMatrix<f64>>) -> Self {
        Self { inertia_cases, interface: Vec::new() }
    }

    /// Every `G`: the inertia cases, then the six loads of each interface node in turn.
    pub fn cases(&self) -> impl Iterator<Item = &DMatrix<f64>> {
        self.inertia_cases.iter().chain(self.interface.iter().flat_map(|i| i.loads.iter()))
    }

    /// The number of cases, [`INERTIA_CASES`] and six per interface node.
    pub fn case_count(&self) -> usize {
        INERTIA_CASES + INTERFACE_CASES * self.interface.len()
    }

    /// The column of the first load case of interface node `node` among [`cases`](Self::cases);
    /// `None` if `node` is not an interface node.
    pub fn interface_column(&self, node: usize) -> Option<usize> {
        self.interface.iter().position(|i| i.node == node).map(|k| INERTIA_CASES + INTERFACE_CASES * k)
    }
}

/// The factors `f_k` of the unit inertia cases: the frame's acceleration less gravity `ā` and its
/// angular acceleration `ω̄̇`, angular velocity `ω̄` (all body axes).
pub fn inertia_load_factors(acceleration: &Vec3, angular_acceleration: &Vec3, angular_velocity: &Vec3) -> [f64; INERTIA_CASES] {
    let (a, d, w) = (acceleration, angular_acceleration, angular_velocity);
    [a.x, a.y, a.z, d.x, d.y, d.z, w.x * w.x, w.y * w.y, w.z * w.z, w.x * w.y, w.y * w.z, w.z * w.x]
}
