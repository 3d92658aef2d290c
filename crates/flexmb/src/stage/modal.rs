//! The modal state of each flexible body, and the elastic kinematics of its nodes (formulation.md §2).
//!
//! A node's deformed position in the body frame is `r̄ = s̄ + Ψ a`. A marker at the node turns with the
//! elastic rotation `θ = Θ a` through the exponential map, its axes `A exp(θ̃) Ā`; its global angular
//! velocity is `A (ω̄ + J(θ) θ̇)` with `J` the (left) tangent of the exponential map. To first order
//! this is the seed's `A (I + θ̃) Ā`; unlike that, it keeps the marker axes orthonormal, so every joint
//! primitive and its Jacobian stay exact.

use nalgebra::{DMatrix, DVector, Matrix3xX};

use crate::body::ModalBody;
use crate::math::{skew, Mat3, Vec3};
use crate::model::Model;
use crate::stage::MarkerState;

/// Modal coordinates of one flexible body and the invariant expansions at them (filled by the
/// kinematics stage; empty for a rigid body).
#[derive(Clone, Debug)]
pub struct ModalState {
    /// `a`.
    pub a: DVector<f64>,
    /// `ȧ`.
    pub a_dot: DVector<f64>,
    /// `S(a) = C1 + C2 a`.
    pub first_moment: Vec3,
    /// `J̄(a) = −(C3 + Σⱼ (C4(j) + C4(j)ᵀ) aⱼ + Σⱼₖ C5(j,k) aⱼ aₖ) + Σ Jᵢ`.
    pub inertia: Mat3,
    /// `C6 + Σₖ C7(k) aₖ + Σ Jᵢ Θᵢ` (3×m): the rotation–deformation block of the mass matrix.
    pub coupling: Matrix3xX<f64>,
    /// `Eⱼ = Σₖ aₖ C5(j,k)`.
    pub c5a: Vec<Mat3>,
    /// `G_k a` (m × cases), column k for the k-th case of the body's geometric stiffness (the 12
    /// unit inertia cases, then six per interface node, [`ModalGeometricStiffness::cases`](crate::body::ModalGeometricStiffness::cases));
    /// zero without one.
    pub stiffening_columns: DMatrix<f64>,
}

impl ModalState {
    /// The state of a body with `modes` modes and `cases` geometric-stiffness cases.
    pub(crate) fn new(modes: usize, cases: usize) -> Self {
        Self {
            a: DVector::zeros(modes),
            a_dot: DVector::zeros(modes),
            first_moment: Vec3::zeros(),
            inertia: Mat3::zeros(),
            coupling: Matrix3xX::zeros(modes),
            c5a: vec![Mat3::zeros(); modes],
            stiffening_columns: DMatrix::zeros(modes, cases),
        }
    }

    /// Reads `a`, `ȧ` and evaluates the expansions of the invariants.
    pub(crate) fn update(&mut self, body: &ModalBody, a: &[f64], a_dot: &[f64]) {
        let inv = &body.invariants;
        let m = body.modes();
        self.a.as_mut_slice().copy_from_slice(a);
        self.a_dot.as_mut_slice().copy_from_slice(a_dot);
        self.first_moment = inv.c1 + &inv.c2 * &self.a;
        let mut j = inv.c3;
        self.coupling.copy_from(&inv.c6);
        self.coupling += &inv.rotary_coupling;
        for p in 0..m {
            let mut e = Mat3::zeros();
            for k in 0..m {
                e += inv.c5(p, k) * a[k];
            }
            self.c5a[p] = e;
            j += (inv.c4[p] + inv.c4[p].transpose()) * a[p] + e * a[p];
            for c in 0..m {
                for r in 0..3 {
                    self.coupling[(r, c)] += a[p] * inv.c7[p][(r, c)];
                }
            }
        }
        self.inertia = -j + inv.rotary_inertia;
        if let Some(terms) = &body.geometric_stiffness {
            for (k, g) in terms.cases().enumerate() {
                for r in 0..m {
                    self.stiffening_columns[(r, k)] = (0..m).map(|c| g[(r, c)] * a[c]).sum();
                }
            }
        }
    }
}

/// `(1 − cos φ)/φ²`, `(φ − sin φ)/φ³` and their derivatives divided by `φ`, by series near zero.
fn tangent_coefficients(phi: f64) -> [f64; 4] {
    if phi < 1e-2 {
        let p2 = phi * phi;
        let p4 = p2 * p2;
        [
            0.5 - p2 / 24.0 + p4 / 720.0,
            1.0 / 6.0 - p2 / 120.0 + p4 / 5040.0,
            -1.0 / 12.0 + p2 / 180.0 - p4 / 6720.0,
            -1.0 / 60.0 + p2 / 1260.0 - p4 / 60480.0,
        ]
    } else {
        let (s, c) = phi.sin_cos();
        let (p2, p3, p4, p5) = (phi * phi, phi.powi(3), phi.powi(4), phi.powi(5));
        [
            (1.0 - c) / p2,
            (phi - s) / p3,
            (phi * s - 2.0 * (1.0 - c)) / p4,
            (1.0 - c) / p4 - 3.0 * (phi - s) / p5,
        ]
    }
}

/// The tangent `J(θ) = I + c₁ θ̃ + c₂ θ̃²` of the exponential map (`d/dt exp(θ̃) = (J θ̇)~ exp(θ̃)`) and
/// `J̇ θ̇` along the rate `θ̇`.
pub(crate) fn exponential_tangent(theta: &Vec3, theta_dot: &Vec3) -> (Mat3, Vec3) {
    let phi = theta.norm();
    let [c1, c2, d1, d2] = tangent_coefficients(phi);
    let t = skew(theta);
    let jac = Mat3::identity() + c1 * t + c2 * t * t;
    let rate = theta.dot(theta_dot);
    let cross = theta.cross(theta_dot);
    let jdot_thetadot = d1 * rate * cross + d2 * rate * theta.cross(&cross) + c2 * theta_dot.cross(&cross);
    (jac, jdot_thetadot)
}

/// The kinematics of a marker at node `node` of flexible body `body`: body frame at `position` (`R`),
/// rotation `rotation` (`A`), body-frame angular velocity `omega_bar`, origin velocity `velocity` (`Ṙ`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn node_marker_state(
    body_id: crate::model::BodyId,
    modal: &ModalBody,
    state: &ModalState,
    node: usize,
    marker_axes: &Mat3,
    position: &Vec3,
    rotation: &Mat3,
    omega_bar: &Vec3,
    velocity: &Vec3,
) -> MarkerState {
    let n = &modal.nodes[node];
    let u: Vec3 = &n.psi * &state.a;
    let u_dot: Vec3 = &n.psi * &state.a_dot;
    let theta: Vec3 = &n.theta * &state.a;
    let theta_dot: Vec3 = &n.theta * &state.a_dot;
    let r_bar = n.position + u;
    let a = rotation;
    let (tangent, tangent_rate) = exponential_tangent(&theta, &theta_dot);
    let elastic = nalgebra::Rotation3::new(theta).into_inner();
    let omega_elastic = tangent * theta_dot;
    let mut jac_point = crate::math::Mat3x6::zeros();
    jac_point.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
    jac_point.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-a * skew(&r_bar)));
    let mut jac_rotation = crate::math::Mat3x6::zeros();
    jac_rotation.fixed_view_mut::<3, 3>(0, 3).copy_from(a);
    let w_cross_r = omega_bar.cross(&r_bar);
    MarkerState {
        body: Some(body_id),
        position: position + a * r_bar,
        axes: a * elastic * marker_axes,
        velocity: velocity + a * (w_cross_r + u_dot),
        angular_velocity: a * (omega_bar + omega_elastic),
        accel_bias: a * (omega_bar.cross(&w_cross_r) + 2.0 * omega_bar.cross(&u_dot)),
        angular_accel_bias: a * (omega_bar.cross(&omega_elastic) + tangent_rate),
        jac_point,
        jac_rotation,
        node: Some(node),
        body_rotation: *a,
        elastic_tangent: tangent,
    }
}

/// Calls `f(j, value)` with the modal part of a marker's generalized-force row: for a global force
/// `d_point` at its origin and a global torque `d_rot`, `Ψᵀ Aᵀ d_point + Θᵀ Jᵀ Aᵀ d_rot` (the modal
/// columns of `J_rᵀ d_point + J_θᵀ d_rot`). Nothing for a marker that is not at a node.
#[inline]
pub(crate) fn modal_row(model: &Model, m: &MarkerState, d_point: &Vec3, d_rot: &Vec3, mut f: impl FnMut(usize, f64)) {
    let (Some(node), Some(b)) = (m.node, m.body) else { return };
    let Some(modal) = model.modal[b.0].as_ref() else { return };
    let n = &modal.nodes[node];
    let local_point = m.body_rotation.transpose() * d_point;
    let local_rot = m.elastic_tangent.transpose() * (m.body_rotation.transpose() * d_rot);
    for j in 0..modal.modes() {
        let value = n.psi.column(j).dot(&local_point) + n.theta.column(j).dot(&local_rot);
        f(j, value);
    }
}
