//! Forces stage: generalized applied forces `Q = [F; N̄; Q_a]` per body (gravity, force elements,
//! and a flexible body's modal stiffness and damping). Conventions are those of [`crate::force`]. Run
//! after kinematics and measures.

use crate::data::Data;
use crate::force::{ForceFrame, ForceKind};
use crate::joint::Equation;
use crate::math::{Mat3, Vec3};
use crate::model::{MarkerId, Model};
use crate::stage::geometric_stiffening::interface_stiffening;
use crate::stage::{modal_row, MarkerState, ModalState};

/// Fills `data.applied` with `Q(q, v, t)`.
pub(crate) fn applied_forces(model: &Model, data: &mut Data, t: f64) {
    let Data { bodies, markers, measures, angle_reference, applied, interface_stiffening, modal: modal_states, .. } = data;
    applied.fill(0.0);
    interface_stiffening.fill(0.0);
    let g = model.gravity;
    for (b, body) in model.bodies.iter().enumerate() {
        let o = model.layout.v_offset[b];
        let g_bar = bodies[b].rotation.transpose() * g;
        let f = body.mass * g;
        let first_moment = match &model.modal[b] {
            Some(_) => modal_states[b].first_moment,
            None => body.first_moment(),
        };
        let n = first_moment.cross(&g_bar);
        for k in 0..3 {
            applied[o + k] += f[k];
            applied[o + 3 + k] += n[k];
        }
        if let Some(modal) = &model.modal[b] {
            // Gravity C2ᵀ Aᵀ g, strain −K a, damping −D ȧ (formulation.md §4).
            let state = &modal_states[b];
            let inv = &modal.invariants;
            for j in 0..modal.modes() {
                let mut q = inv.c2.column(j).dot(&g_bar);
                for k in 0..modal.modes() {
                    q -= modal.stiffness[(j, k)] * state.a[k] + modal.damping[(j, k)] * state.a_dot[k];
                }
                applied[o + 6 + j] += q;
            }
        }
    }
    let modal_states: &[ModalState] = modal_states;
    for force in &model.forces {
        match &force.kind {
            ForceKind::TranslationalSpringDamper { marker_i, marker_j, stiffness, damping, free_length, actuator } => {
                let (mi, mj) = (&markers[marker_i.0], &markers[marker_j.0]);
                let d = mj.position - mi.position;
                let l = d.norm();
                if l == 0.0 {
                    continue; // direction undefined; a coincident pair carries no force
                }
                let u = d / l;
                let l_rate = u.dot(&(mj.velocity - mi.velocity));
                let act = actuator.as_ref().map_or(0.0, |e| e.eval(t, measures));
                let f = -stiffness * (l - free_length) - damping * l_rate + act;
                add_at(model, modal_states, applied, interface_stiffening, mj, &(f * u), &Vec3::zeros());
                add_at(model, modal_states, applied, interface_stiffening, mi, &(-f * u), &Vec3::zeros());
            }
            ForceKind::RotationalSpringDamper { joint, stiffness, damping, free_angle, actuator } => {
                let jt = &model.joints[joint.0];
                let (mi, mj) = (&markers[jt.marker_i.0], &markers[jt.marker_j.0]);
                let terms = Equation::Angle.evaluate(mi, mj, [0.0; 3], angle_reference[joint.0]);
                let theta = terms.phi;
                let rate = terms.rate(mi, mj);
                let act = actuator.as_ref().map_or(0.0, |e| e.eval(t, measures));
                let torque = -stiffness * (theta - free_angle) - damping * rate + act;
                let axis: Vec3 = mi.axes.column(2).into();
                add_at(model, modal_states, applied, interface_stiffening, mj, &Vec3::zeros(), &(torque * axis));
                add_at(model, modal_states, applied, interface_stiffening, mi, &Vec3::zeros(), &(-torque * axis));
            }
            ForceKind::AppliedForce { marker, components, frame } => {
                let m = &markers[marker.0];
                let f = in_global(model, bodies, *marker, m, *frame, components, t, measures);
                add_at(model, modal_states, applied, interface_stiffening, m, &f, &Vec3::zeros());
            }
            ForceKind::AppliedTorque { marker, components, frame } => {
                let m = &markers[marker.0];
                let tau = in_global(model, bodies, *marker, m, *frame, components, t, measures);
                add_at(model, modal_states, applied, interface_stiffening, m, &Vec3::zeros(), &tau);
            }
        }
    }
}

/// The global force or torque of an applied force or torque element at the current state (zero for
/// the spring-dampers).
pub(crate) fn applied_load(model: &Model, data: &Data, force: &crate::force::ForceElement, t: f64) -> Vec3 {
    match &force.kind {
        ForceKind::AppliedForce { marker, components, frame } | ForceKind::AppliedTorque { marker, components, frame } => {
            in_global(model, &data.bodies, *marker, &data.markers[marker.0], *frame, components, t, &data.measures)
        }
        _ => Vec3::zeros(),
    }
}

#[allow(clippy::too_many_arguments)]
fn in_global(
    model: &Model,
    bodies: &[crate::stage::BodyState],
    id: MarkerId,
    m: &MarkerState,
    frame: ForceFrame,
    components: &[crate::function::Expression; 3],
    t: f64,
    measures: &[f64],
) -> Vec3 {
    let local = Vec3::new(components[0].eval(t, measures), components[1].eval(t, measures), components[2].eval(t, measures));
    let axes: Mat3 = match frame {
        ForceFrame::Global => return local,
        ForceFrame::Marker => m.axes,
        ForceFrame::Body => match model.markers[id.0].body.body() {
            Some(b) => bodies[b.0].rotation,
            None => Mat3::identity(),
        },
    };
    axes * local
}

/// Adds a global force at a marker origin and a global torque to the marker's body (and, at a node
/// of a flexible body, to its modal forces, with the geometric stiffening of the load at an
/// interface node, which also goes to `stiffening`).
#[inline]
fn add_at(model: &Model, modal_states: &[ModalState], applied: &mut [f64], stiffening: &mut [f64], m: &MarkerState, f: &Vec3, tau: &Vec3) {
    if let Some(b) = m.body {
        let q = m.generalized_force(f, tau);
        let o = model.layout.v_offset[b.0];
        for k in 0..6 {
            applied[o + k] += q[k];
        }
        modal_row(model, m, f, tau, |j, x| applied[o + 6 + j] += x);
        interface_stiffening(model, modal_states, m, f, tau, |j, x| {
            applied[o + 6 + j] -= x;
            stiffening[o + 6 + j] += x;
        });
    }
}
