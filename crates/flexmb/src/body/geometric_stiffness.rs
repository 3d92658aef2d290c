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
}

/// The factors `f_k` of the unit inertia cases: the frame's acceleration less gravity `ā` and its
/// angular acceleration `ω̄̇`, angular velocity `ω̄` (all body axes).
pub fn inertia_load_factors(acceleration: &Vec3, angular_acceleration: &Vec3, angular_velocity: &Vec3) -> [f64; INERTIA_CASES] {
    let (a, d, w) = (acceleration, angular_acceleration, angular_velocity);
    [a.x, a.y, a.z, d.x, d.y, d.z, w.x * w.x, w.y * w.y, w.z * w.z, w.x * w.y, w.y * w.z, w.z * w.x]
}
