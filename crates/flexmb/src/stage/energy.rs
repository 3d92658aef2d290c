//! Energy: kinetic `½ vᵀ M v`, gravitational potential `−gᵀ (m R + A S̄)`, spring potentials, and the
//! strain energy `½ aᵀ K_aa a` of flexible bodies.

use crate::data::Data;
use crate::force::ForceKind;
use crate::joint::Equation;
use crate::model::Model;
use crate::stage::body_mass_entries;

/// Mechanical energy of a state (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    pub kinetic: f64,
    /// Gravity and springs.
    pub potential: f64,
    /// Strain energy of the flexible bodies.
    pub strain: f64,
}

impl Energy {
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.strain
    }
}

/// Energy at the state of the last kinematics stage, with velocities `v`.
pub(crate) fn energy(model: &Model, data: &Data, q: &[f64], v: &[f64]) -> Energy {
    let mut e = Energy::default();
    for (b, body) in model.bodies.iter().enumerate() {
        let vo = model.layout.v_offset[b];
        let qo = model.layout.q_offset[b];
        let mut kinetic = 0.0;
        body_mass_entries(model, data, b, |r, c, m| kinetic += v[vo + r] * m * v[vo + c]);
        e.kinetic += 0.5 * kinetic;
        let r = nalgebra::Vector3::new(q[qo], q[qo + 1], q[qo + 2]);
        let body_moment = match &model.modal[b] {
            Some(_) => data.modal[b].first_moment,
            None => body.first_moment(),
        };
        let first_moment = body.mass * r + data.bodies[b].rotation * body_moment;
        e.potential -= model.gravity.dot(&first_moment);
        if let Some(modal) = &model.modal[b] {
            let a = &data.modal[b].a;
            e.strain += 0.5 * a.dot(&(&modal.stiffness * a));
        }
    }
    for force in &model.forces {
        match &force.kind {
            ForceKind::TranslationalSpringDamper { marker_i, marker_j, stiffness, free_length, .. } => {
                let l = (data.markers[marker_j.0].position - data.markers[marker_i.0].position).norm();
                e.potential += 0.5 * stiffness * (l - free_length).powi(2);
            }
            ForceKind::RotationalSpringDamper { joint, stiffness, free_angle, .. } => {
                let jt = &model.joints[joint.0];
                let (mi, mj) = (&data.markers[jt.marker_i.0], &data.markers[jt.marker_j.0]);
                let theta = Equation::Angle.evaluate(mi, mj, [0.0; 3], data.angle_reference[joint.0]).phi;
                e.potential += 0.5 * stiffness * (theta - free_angle).powi(2);
            }
            _ => {}
        }
    }
    e
}
