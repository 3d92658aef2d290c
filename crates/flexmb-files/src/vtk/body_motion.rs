//! The motion of a body at an output time, read from the state vectors of the engine's layout (`q`:
//! per body `R, p, a`; `v`: per body `Ṙ, ω̄, ȧ`), and the global position and velocity of points on it
//! (formulation.md §2): a point at `r̄` in the body frame is at `R + A r̄` and moves with
//! `Ṙ + A (ω̄ × r̄ + r̄̇)`; a node of a flexible body has `r̄ = s̄ + Ψ a`, `r̄̇ = Ψ ȧ`.

use flexmb::body::ModalNode;
use flexmb::math::{rotation_matrix, Mat3, Vec3, Vec4};
use flexmb::model::{BodyId, BodyRef, MarkerId};
use flexmb::Model;
use nalgebra::DVectorView;

/// One body frame's position, rotation and velocities, and its modal coordinates and rates.
pub(crate) struct BodyMotion<'a> {
    origin: Vec3,
    rotation: Mat3,
    velocity: Vec3,
    omega_bar: Vec3,
    a: DVectorView<'a, f64>,
    a_dot: DVectorView<'a, f64>,
}

/// Where a point is and how it moves, global.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PointMotion {
    pub position: Vec3,
    pub velocity: Vec3,
    /// The elastic displacement `A Ψ a` (zero for a point of a rigid body).
    pub elastic: Vec3,
}

impl<'a> BodyMotion<'a> {
    pub(crate) fn of(model: &Model, body: BodyId, q: &'a [f64], v: &'a [f64]) -> Self {
        let layout = model.layout();
        let ranges = layout.q_range(body).zip(layout.v_range(body));
        let (q_range, v_range) = ranges.expect("the parts of a loaded model are its own bodies");
        let (qb, vb) = (&q[q_range], &v[v_range]);
        let m = qb.len() - 7;
        Self {
            origin: Vec3::from_column_slice(&qb[0..3]),
            rotation: rotation_matrix(&Vec4::from_column_slice(&qb[3..7])),
            velocity: Vec3::from_column_slice(&vb[0..3]),
            omega_bar: Vec3::from_column_slice(&vb[3..6]),
            a: DVectorView::from_slice(&qb[7..], m),
            a_dot: DVectorView::from_slice(&vb[6..], m),
        }
    }

    /// A point fixed in the body frame at `r_bar`.
    pub(crate) fn point(&self, r_bar: &Vec3) -> PointMotion {
        self.moving_point(r_bar, &Vec3::zeros(), &Vec3::zeros())
    }

    /// A node of a flexible body.
    pub(crate) fn node(&self, node: &ModalNode) -> PointMotion {
        let u: Vec3 = &node.psi * self.a;
        let u_dot: Vec3 = &node.psi * self.a_dot;
        self.moving_point(&(node.position + u), &u_dot, &u)
    }

    /// A point at `r_bar` moving with `r_bar_dot` in the body frame, `u` of it elastic.
    fn moving_point(&self, r_bar: &Vec3, r_bar_dot: &Vec3, u: &Vec3) -> PointMotion {
        PointMotion {
            position: self.origin + self.rotation * r_bar,
            velocity: self.velocity + self.rotation * (self.omega_bar.cross(r_bar) + r_bar_dot),
            elastic: self.rotation * u,
        }
    }
}

/// A marker's origin: fixed on ground, on a rigid body, or at a node of a flexible body.
pub(crate) fn marker_motion(model: &Model, marker: MarkerId, q: &[f64], v: &[f64]) -> PointMotion {
    let m = &model.markers()[marker.0];
    let BodyRef::Body(body) = m.body else {
        return PointMotion { position: m.origin, velocity: Vec3::zeros(), elastic: Vec3::zeros() };
    };
    let motion = BodyMotion::of(model, body, q, v);
    match (model.marker_node(marker), model.modal_body(body)) {
        (Some(node), Some(modal)) => motion.node(&modal.nodes[node]),
        _ => motion.point(&m.origin),
    }
}
