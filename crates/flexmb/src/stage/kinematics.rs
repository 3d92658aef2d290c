//! Kinematics stage: body rotations and the global kinematics of every marker (formulation.md §2).

use crate::data::Data;
use crate::math::{euler_parameters::rotation_matrix, skew, Mat3, Mat3x6, Vec3, Vec4};
use crate::model::{BodyId, BodyRef, Model};

/// Rotation and angular velocity of one body.
#[derive(Clone, Copy, Debug)]
pub struct BodyState {
    /// Unit Euler parameters.
    pub p: Vec4,
    /// `A(p)`.
    pub rotation: Mat3,
    /// Body-frame angular velocity `ω̄`.
    pub omega_bar: Vec3,
    /// Global angular velocity `ω = A ω̄`.
    pub omega: Vec3,
}

impl Default for BodyState {
    fn default() -> Self {
        Self { p: Vec4::new(1.0, 0.0, 0.0, 0.0), rotation: Mat3::identity(), omega_bar: Vec3::zeros(), omega: Vec3::zeros() }
    }
}

/// Global kinematics of a marker and its Jacobians with respect to its body's velocity `[Ṙ, ω̄]`.
#[derive(Clone, Copy, Debug)]
pub struct MarkerState {
    /// The body the marker moves with (`None` on ground).
    pub body: Option<BodyId>,
    /// Origin, global (m).
    pub position: Vec3,
    /// Axes, global (columns x, y, z).
    pub axes: Mat3,
    /// Velocity of the origin (m/s).
    pub velocity: Vec3,
    /// Angular velocity, global (rad/s).
    pub angular_velocity: Vec3,
    /// Acceleration of the origin when all generalized accelerations vanish: `ω × (ω × s)`.
    pub accel_bias: Vec3,
    /// Angular acceleration when all generalized accelerations vanish (zero for a rigid body).
    pub angular_accel_bias: Vec3,
    /// `δr = J_r δv_b`: `[I, −A s̄̃]`.
    pub jac_point: Mat3x6,
    /// `δθ = J_θ δv_b`: `[0, A]` (global virtual rotation).
    pub jac_rotation: Mat3x6,
    /// The node of a flexible body the marker sits at; its modal Jacobian columns are
    /// `A Ψ` (point) and `A J Θ` (rotation), see the stage function `modal_row`.
    pub node: Option<usize>,
    /// `A` of the marker's body (for the modal columns).
    pub body_rotation: Mat3,
    /// `J(θ)`, the tangent of the node's elastic rotation (identity off nodes).
    pub elastic_tangent: Mat3,
}

impl Default for MarkerState {
    fn default() -> Self {
        Self {
            body: None,
            position: Vec3::zeros(),
            axes: Mat3::identity(),
            velocity: Vec3::zeros(),
            angular_velocity: Vec3::zeros(),
            accel_bias: Vec3::zeros(),
            angular_accel_bias: Vec3::zeros(),
            jac_point: Mat3x6::zeros(),
            jac_rotation: Mat3x6::zeros(),
            node: None,
            body_rotation: Mat3::identity(),
            elastic_tangent: Mat3::identity(),
        }
    }
}

impl MarkerState {
    /// Generalized force on the marker's body `[F; N̄]` of a global force `f` at the origin and a
    /// global torque `tau`: `J_rᵀ f + J_θᵀ τ` (the modal part, at a node of a flexible body, is
    /// added by the stage function `modal_row`).
    #[inline]
    pub fn generalized_force(&self, f: &Vec3, tau: &Vec3) -> nalgebra::Vector6<f64> {
        self.jac_point.transpose() * f + self.jac_rotation.transpose() * tau
    }
}

/// Fills `data.bodies` and `data.markers` from positions `q` and velocities `v`.
pub(crate) fn kinematics(model: &Model, data: &mut Data, q: &[f64], v: &[f64]) {
    let layout = &model.layout;
    for (b, state) in data.bodies.iter_mut().enumerate() {
        let qo = layout.q_offset[b];
        let vo = layout.v_offset[b];
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        state.p = p / p.norm();
        state.rotation = rotation_matrix(&p);
        state.omega_bar = Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
        state.omega = state.rotation * state.omega_bar;
        if let Some(modal) = &model.modal[b] {
            let m = modal.modes();
            data.modal[b].update(modal, &q[qo + 7..qo + 7 + m], &v[vo + 6..vo + 6 + m]);
        }
    }
    for ((marker, state), node) in model.markers.iter().zip(data.markers.iter_mut()).zip(&model.marker_node) {
        match marker.body {
            BodyRef::Ground => {
                *state = MarkerState { position: marker.origin, axes: marker.axes, ..MarkerState::default() };
            }
            BodyRef::Body(b) if node.is_some() => {
                let body = &data.bodies[b.0];
                let (qo, vo) = (layout.q_offset[b.0], layout.v_offset[b.0]);
                let modal = model.modal[b.0].as_ref().expect("node markers are on flexible bodies");
                *state = super::modal::node_marker_state(
                    b,
                    modal,
                    &data.modal[b.0],
                    node.expect("checked"),
                    &marker.axes,
                    &Vec3::new(q[qo], q[qo + 1], q[qo + 2]),
                    &body.rotation,
                    &body.omega_bar,
                    &Vec3::new(v[vo], v[vo + 1], v[vo + 2]),
                );
            }
            BodyRef::Body(b) => {
                let body = &data.bodies[b.0];
                let qo = layout.q_offset[b.0];
                let vo = layout.v_offset[b.0];
                let a = body.rotation;
                let s = a * marker.origin;
                let w = body.omega;
                let w_cross_s = w.cross(&s);
                let mut jac_point = Mat3x6::zeros();
                jac_point.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
                jac_point.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-a * skew(&marker.origin)));
                let mut jac_rotation = Mat3x6::zeros();
                jac_rotation.fixed_view_mut::<3, 3>(0, 3).copy_from(&a);
                *state = MarkerState {
                    body: Some(b),
                    position: Vec3::new(q[qo], q[qo + 1], q[qo + 2]) + s,
                    axes: a * marker.axes,
                    velocity: Vec3::new(v[vo], v[vo + 1], v[vo + 2]) + w_cross_s,
                    angular_velocity: w,
                    accel_bias: w.cross(&w_cross_s),
                    angular_accel_bias: Vec3::zeros(),
                    jac_point,
                    jac_rotation,
                    ..MarkerState::default()
                };
            }
        }
    }
}
