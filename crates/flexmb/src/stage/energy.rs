//! Energy: kinetic `½ vᵀ M v`, gravitational potential `−gᵀ (m R + A S̄)`, spring potentials, and the
//! strain energy `½ aᵀ K_aa a` of flexible bodies.

use crate::data::Data;
use crate::force::ForceKind;
use crate::joint::Equation;
use crate::model::Model;
use crate::stage::body_mass_entries;
use crate::stage::forces::applied_load;
use crate::stage::geometric_stiffening::interface_reaction_entries;

/// Mechanical energy of a state (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// Kinetic energy of all bodies, elastic motion included.
    pub kinetic: f64,
    /// Gravity and springs.
    pub potential: f64,
    /// Strain energy of the flexible bodies.
    pub strain: f64,
}

impl Energy {
    /// Kinetic, potential and strain energy together.
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

/// Power of the non-conservative forces (W) at the state of the last kinematics, measures and
/// constraint stages, with multipliers `lambda`: the dampers' and actuators' part of the spring-dampers,
/// applied forces and torques, modal damping `−ȧᵀ D ȧ`, and the constraints that depend on time
/// (drivers, distances of varying length), `λᵀ Φ_t` (the constraint forces are `−Φ_qᵀ λ` and `Φ_q v = −Φ_t`), and the geometric
/// stiffening of the loads at interface nodes ([`interface_stiffening_power`]). Gravity, spring
/// stiffness and strain are conservative: their work is in the potential and strain energy. So
/// `dE/dt = P` along a solution, and `E(t) − E(0) − ∫ P dt` measures how well a run keeps its energy
/// balance.
pub(crate) fn nonconservative_power(model: &Model, data: &Data, t: f64, lambda: &[f64]) -> f64 {
    let mut p = 0.0;
    for (b, modal) in model.modal.iter().enumerate() {
        if let Some(modal) = modal {
            let a_dot = &data.modal[b].a_dot;
            p -= a_dot.dot(&(&modal.damping * a_dot));
        }
    }
    for force in &model.forces {
        p += match &force.kind {
            ForceKind::TranslationalSpringDamper { marker_i, marker_j, damping, actuator, .. } => {
                let (mi, mj) = (&data.markers[marker_i.0], &data.markers[marker_j.0]);
                let d = mj.position - mi.position;
                let l = d.norm();
                if l == 0.0 {
                    continue;
                }
                let rate = (d / l).dot(&(mj.velocity - mi.velocity));
                let act = actuator.as_ref().map_or(0.0, |e| e.eval(t, &data.measures));
                (-damping * rate + act) * rate
            }
            ForceKind::RotationalSpringDamper { joint, damping, actuator, .. } => {
                let jt = &model.joints[joint.0];
                let (mi, mj) = (&data.markers[jt.marker_i.0], &data.markers[jt.marker_j.0]);
                let rate = Equation::Angle.evaluate(mi, mj, [0.0; 3], data.angle_reference[joint.0]).rate(mi, mj);
                let act = actuator.as_ref().map_or(0.0, |e| e.eval(t, &data.measures));
                (-damping * rate + act) * rate
            }
            ForceKind::AppliedForce { marker, .. } => {
                let m = &data.markers[marker.0];
                applied_load(model, data, force, t).dot(&m.velocity)
            }
            ForceKind::AppliedTorque { marker, .. } => {
                let m = &data.markers[marker.0];
                applied_load(model, data, force, t).dot(&m.angular_velocity)
            }
        };
    }
    p + data.equations.iter().zip(lambda).map(|(e, l)| l * e.phi_t).sum::<f64>() + interface_stiffening_power(model, data, lambda)
}

/// The power `−ȧᵀ K_G,I a` of the geometric stiffening of the loads at interface nodes (force
/// elements' and joints'): the work those loads do through the second-order (foreshortening)
/// displacement of their nodes, which the linear modal kinematics leave out of `F · ṙ`.
fn interface_stiffening_power(model: &Model, data: &Data, lambda: &[f64]) -> f64 {
    let l = &model.layout;
    let mut p = 0.0;
    for (b, modal) in model.modal.iter().enumerate() {
        if modal.is_some() {
            let o = l.v_offset[b] + 6;
            p -= data.modal[b].a_dot.iter().enumerate().map(|(k, x)| x * data.interface_stiffening[o + k]).sum::<f64>();
        }
    }
    if lambda.is_empty() {
        return p;
    }
    interface_reaction_entries(model, data, |row, c, x| {
        let b = l.velocity_body(c);
        p -= lambda[row] * x * data.modal[b].a_dot[c - l.v_offset[b] - 6];
    });
    p
}
