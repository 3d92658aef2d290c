//! Inertia stage: `M(q) v̇ + h(q, v)` per body, in velocities `[Ṙ (global), ω̄ (body)]`
//! (formulation.md §4 with no modes):
//!
//! ```text
//! m R̈ − A S̄̃ ω̄̇ + A ω̄̃ ω̄̃ S̄        (translation, global)
//! S̄̃ Aᵀ R̈ + J̄ ω̄̇ + ω̄̃ J̄ ω̄          (rotation, body frame)
//! ```
//! with `S̄ = m c̄` the first moment and `J̄` the inertia about the body-frame origin.

use crate::data::Data;
use crate::math::{skew, Mat3, Mat6, Vec3};
use crate::model::Model;

/// The 6×6 mass matrix of body `b` at its current rotation.
pub(crate) fn body_mass_matrix(model: &Model, data: &Data, b: usize) -> Mat6 {
    let body = &model.bodies[b];
    let a = data.bodies[b].rotation;
    let s_tilde = skew(&body.first_moment());
    let coupling = -a * s_tilde; // rows: translation, cols: ω̄
    let mut m = Mat6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&(body.mass * Mat3::identity()));
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(&coupling);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&coupling.transpose());
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&body.inertia_about_origin());
    m
}

/// Fills `data.inertia` with `M v̇ + h(q, v)` (after the kinematics stage).
pub(crate) fn inertia_forces(model: &Model, data: &mut Data, vdot: &[f64]) {
    for (b, body) in model.bodies.iter().enumerate() {
        let o = model.layout.v_offset[b];
        let state = &data.bodies[b];
        let a = state.rotation;
        let w = state.omega_bar;
        let s = body.first_moment();
        let j = body.inertia_about_origin();
        let rdd = Vec3::new(vdot[o], vdot[o + 1], vdot[o + 2]);
        let wd = Vec3::new(vdot[o + 3], vdot[o + 4], vdot[o + 5]);
        let trans = body.mass * rdd - a * s.cross(&wd) + a * w.cross(&w.cross(&s));
        let rot = s.cross(&(a.transpose() * rdd)) + j * wd + w.cross(&(j * w));
        for k in 0..3 {
            data.inertia[o + k] = trans[k];
            data.inertia[o + 3 + k] = rot[k];
        }
    }
}
