//! Geometric stiffening in the modal equations (formulation.md §11, [`crate::body::ModalGeometricStiffness`]):
//! the modal rows of a flexible body with geometric-stiffness terms gain `K_G a = Σ_k f_k G_k a`,
//! with the factors `f = [ā, ω̄̇, ω̄ products]` of the current motion, `ā = Aᵀ(R̈ − g)`. The term sits
//! with the inertia forces because its factors are accelerations: its derivative in `v̇` is a
//! (non-symmetric) block of `∂g/∂v̇` beside the mass matrix, given by [`geometric_stiffening_entries`].

use crate::body::inertia_load_factors;
use crate::data::Data;
use crate::math::Vec3;
use crate::model::Model;

/// Adds `K_G a` of body `b` (which must be flexible) to its modal rows of `data.inertia`, at the
/// accelerations `vdot`; nothing without terms.
pub(crate) fn add_geometric_stiffening(model: &Model, data: &mut Data, b: usize, vdot: &[f64]) {
    let Some(modal) = &model.modal[b] else { return };
    if modal.geometric_stiffness.is_none() {
        return;
    }
    let o = model.layout.v_offset[b];
    let state = &data.bodies[b];
    let rdd = Vec3::new(vdot[o], vdot[o + 1], vdot[o + 2]);
    let acceleration = state.rotation.transpose() * (rdd - model.gravity);
    let angular_acceleration = Vec3::new(vdot[o + 3], vdot[o + 4], vdot[o + 5]);
    let factors = inertia_load_factors(&acceleration, &angular_acceleration, &state.omega_bar);
    let columns = &data.modal[b].stiffening_columns;
    for j in 0..modal.modes() {
        data.inertia[o + 6 + j] += (0..factors.len()).map(|k| factors[k] * columns[(j, k)]).sum::<f64>();
    }
}

/// Calls `f(r, c, value)` for the entries of `∂(K_G a)/∂v̇` of body `b` (local to its velocity
/// coordinates: modal rows `6 + j`, columns `0..3` for `R̈` through `ā = Aᵀ(R̈ − g)` and `3..6` for
/// `ω̄̇`); nothing for a rigid body or one without terms.
pub(crate) fn geometric_stiffening_entries(model: &Model, data: &Data, b: usize, mut f: impl FnMut(usize, usize, f64)) {
    let Some(modal) = &model.modal[b] else { return };
    if modal.geometric_stiffness.is_none() {
        return;
    }
    let rotation = data.bodies[b].rotation;
    let columns = &data.modal[b].stiffening_columns;
    for j in 0..modal.modes() {
        for r in 0..3 {
            // ∂ā_i/∂R̈_r = A[r, i].
            f(6 + j, r, (0..3).map(|i| columns[(j, i)] * rotation[(r, i)]).sum());
            f(6 + j, 3 + r, columns[(j, 3 + r)]);
        }
    }
}
