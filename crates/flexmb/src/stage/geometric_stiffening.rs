//! Geometric stiffening in the modal equations (formulation.md §11, [`crate::body::ModalGeometricStiffness`]):
//! the modal rows of a flexible body with geometric-stiffness terms gain `K_G a = Σ_k f_k G_k a`,
//! with the factors `f = [ā, ω̄̇, ω̄ products]` of the current motion, `ā = Aᵀ(R̈ − g)`. The term sits
//! with the inertia forces because its factors are accelerations: its derivative in `v̇` is a
//! (non-symmetric) block of `∂g/∂v̇` beside the mass matrix, given by [`geometric_stiffening_entries`].
//!
//! The loads at the body's interface nodes add `Σ_c F̄M̄_c G_{n,c} a` ([`interface_stiffening`]): a
//! force element's with its force (in the applied forces, whose derivatives in `q` and `v` are the
//! finite-difference parts as every force's), a joint's with its reaction `−λ_k (∂Φ_k/∂r, ∂Φ_k/∂θ)`,
//! linear in `λ` ([`interface_reaction_entries`]: columns beside `Bᵀ` in every matrix that has `Bᵀ`).

use crate::body::inertia_load_factors;
use crate::data::Data;
use crate::math::Vec3;
use crate::model::Model;
use crate::stage::{MarkerState, ModalState};

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

/// Calls `f(j, value)` with modal row `j` of `Σ_c F̄M̄_c G_{n,c} a`, the stiffening of a global force
/// `force` at marker `m` and a global torque `torque` on it, when the marker sits at an interface
/// node `n` of a body with geometric stiffening (`F̄M̄ = [Aᵀ force; Aᵀ torque]`, body axes); nothing
/// otherwise. The value goes where `K a` goes: the left of the equations (subtracted from `Q`).
#[inline]
pub(crate) fn interface_stiffening(
    model: &Model,
    modal_states: &[ModalState],
    m: &MarkerState,
    force: &Vec3,
    torque: &Vec3,
    mut f: impl FnMut(usize, f64),
) {
    let (Some(node), Some(b)) = (m.node, m.body) else { return };
    let Some(terms) = model.modal[b.0].as_ref().and_then(|modal| modal.geometric_stiffness.as_ref()) else { return };
    let Some(first) = terms.interface_column(node) else { return };
    let load_force = m.body_rotation.transpose() * force;
    let load_torque = m.body_rotation.transpose() * torque;
    let load = [load_force.x, load_force.y, load_force.z, load_torque.x, load_torque.y, load_torque.z];
    let columns = &modal_states[b.0].stiffening_columns;
    for j in 0..columns.nrows() {
        f(j, (0..load.len()).map(|c| load[c] * columns[(j, first + c)]).sum());
    }
}

/// Calls `f(row, v_column, value)` for every entry of `∂(K_G a)/∂λ`: the interface stiffening of the
/// joints' reactions per unit multiplier (the reaction of row `k` on a marker's body is the force
/// `−λ_k ∂Φ_k/∂r` at the marker and the torque `−λ_k ∂Φ_k/∂θ`). Columns beside `Bᵀ` in the dynamic
/// rows; exact, as the term is linear in `λ`.
pub(crate) fn interface_reaction_entries(model: &Model, data: &Data, mut f: impl FnMut(usize, usize, f64)) {
    for (j, joint) in model.joints.iter().enumerate() {
        for marker in [joint.marker_i, joint.marker_j] {
            let m = &data.markers[marker.0];
            let Some(b) = m.body else { continue };
            let o = model.layout.v_offset[b.0] + 6;
            for row in model.layout.joint_rows[j].clone() {
                let terms = &data.equations[row];
                let (d_point, d_rot) =
                    if marker == joint.marker_i { (terms.d_point_i, terms.d_rot_i) } else { (terms.d_point_j, terms.d_rot_j) };
                interface_stiffening(model, &data.modal, m, &-d_point, &-d_rot, |k, x| f(row, o + k, x));
            }
        }
    }
}

/// `out += ∂(K_G a)/∂λ · λ` over the velocity rows: the interface stiffening of the joints' reactions.
pub(crate) fn add_interface_reactions(model: &Model, data: &Data, lambda: &[f64], out: &mut [f64]) {
    interface_reaction_entries(model, data, |row, c, x| out[c] += lambda[row] * x);
}
