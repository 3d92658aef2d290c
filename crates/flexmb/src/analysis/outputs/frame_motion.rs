//! The rotation of a body's reference frame or of a marker's axes: orientation (Euler parameters,
//! rotation matrix, Euler angles continued over time), angular velocity and angular acceleration,
//! resolved in global, body or marker axes.

use super::super::Accelerations;
use crate::data::Data;
use crate::math::{continue_angle, EulerParameters, EulerSequence, Mat3, Vec3, Vec4};
use crate::model::{Model, OutputAxes, RotatingFrame};

/// Rotation matrix of the frame (global components of its axes as columns).
pub(super) fn rotation(data: &Data, frame: RotatingFrame) -> Mat3 {
    match frame {
        RotatingFrame::Body(b) => data.bodies[b.0].rotation,
        RotatingFrame::Marker(m) => data.markers[m.0].axes,
    }
}

/// Euler parameters of the frame: a body's own (from `q`, as integrated, so `|p| ≠ 1` shows), a
/// marker's from its axes with `e0 ≥ 0`.
pub(super) fn euler_parameters(model: &Model, data: &Data, q: &[f64], frame: RotatingFrame) -> Vec4 {
    match frame {
        RotatingFrame::Body(b) => {
            let o = model.layout.q_offset[b.0] + 3;
            Vec4::new(q[o], q[o + 1], q[o + 2], q[o + 3])
        }
        RotatingFrame::Marker(m) => EulerParameters::from_rotation_matrix(&data.markers[m.0].axes)
            .map_or(Vec4::repeat(f64::NAN), |p| p.0),
    }
}

/// The angles of `sequence` of `a`, each continued from the previous row's value (`None` for the
/// first row); at gimbal lock the third angle keeps its previous value (0 on the first row).
pub(super) fn continued_angles(sequence: EulerSequence, a: &Mat3, previous: Option<[f64; 3]>) -> [f64; 3] {
    let psi_before = previous.map_or(0.0, |p| p[2]);
    let mut angles = sequence.angles(a, psi_before);
    if let Some(previous) = previous {
        for (angle, before) in angles.iter_mut().zip(previous) {
            *angle = continue_angle(*angle, before);
        }
    }
    angles
}

/// Global angular velocity of the frame.
pub(super) fn angular_velocity(data: &Data, frame: RotatingFrame) -> Vec3 {
    match frame {
        RotatingFrame::Body(b) => data.bodies[b.0].omega,
        RotatingFrame::Marker(m) => data.markers[m.0].angular_velocity,
    }
}

/// Global angular acceleration of the frame: a body's `A ω̄̇`; a marker's `J_θ v̇_b + A J Θ ä` plus
/// the part that does not depend on the accelerations (formulation.md §2).
pub(super) fn angular_acceleration(model: &Model, data: &Data, acc: &Accelerations, frame: RotatingFrame) -> Vec3 {
    match frame {
        RotatingFrame::Body(b) => {
            let vo = model.layout.v_offset[b.0];
            data.bodies[b.0].rotation * Vec3::from_column_slice(&acc.vdot[vo + 3..vo + 6])
        }
        RotatingFrame::Marker(m) => {
            let ms = &data.markers[m.0];
            let mut alpha = ms.angular_accel_bias;
            let Some(b) = ms.body else { return alpha };
            let vo = model.layout.v_offset[b.0];
            alpha += ms.jac_rotation * nalgebra::Vector6::from_column_slice(&acc.vdot[vo..vo + 6]);
            if let (Some(node), Some(modal)) = (ms.node, &model.modal[b.0]) {
                let a_ddot = nalgebra::DVectorView::from_slice(&acc.vdot[vo + 6..vo + 6 + modal.modes()], modal.modes());
                alpha += ms.body_rotation * ms.elastic_tangent * (&modal.nodes[node].theta * a_ddot);
            }
            alpha
        }
    }
}

/// Global vector `x` resolved in `axes`; `Body` means the axes of the frame's body (global for a
/// marker on ground).
pub(super) fn resolve(data: &Data, frame: RotatingFrame, axes: OutputAxes, x: Vec3) -> Vec3 {
    match axes {
        OutputAxes::Global => x,
        OutputAxes::Marker(m) => data.markers[m.0].axes.transpose() * x,
        OutputAxes::Body => {
            let body = match frame {
                RotatingFrame::Body(b) => Some(b),
                RotatingFrame::Marker(m) => data.markers[m.0].body,
            };
            body.map_or(x, |b| data.bodies[b.0].rotation.transpose() * x)
        }
    }
}
