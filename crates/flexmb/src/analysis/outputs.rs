//! Output columns: names, units and values of the model's output requests at one state.

use super::Accelerations;
use crate::data::Data;
use crate::math::Vec3;
use crate::model::{Model, OutputKind};
use crate::stage::{energy, measure_value};

/// One column of the results table.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputColumn {
    /// The output's name and component, e.g. `tip.x`.
    pub name: String,
    /// Its unit, e.g. `m/s`.
    pub unit: &'static str,
}

const XYZ: [&str; 3] = ["x", "y", "z"];

/// The columns of every output request, in order (time is not included).
pub fn output_columns(model: &Model) -> Vec<OutputColumn> {
    let mut cols = Vec::new();
    let push3 = |cols: &mut Vec<OutputColumn>, base: &str, suffix: [&str; 3], unit| {
        for s in suffix {
            cols.push(OutputColumn { name: format!("{base}.{s}"), unit });
        }
    };
    for o in &model.outputs {
        match o.kind {
            OutputKind::MarkerPosition(_) => push3(&mut cols, &o.name, XYZ, "m"),
            OutputKind::MarkerVelocity(_) => push3(&mut cols, &o.name, XYZ, "m/s"),
            OutputKind::MarkerAcceleration(_) => push3(&mut cols, &o.name, XYZ, "m/s^2"),
            OutputKind::MarkerAngularVelocity(_) => push3(&mut cols, &o.name, XYZ, "rad/s"),
            OutputKind::JointReaction(_) => {
                push3(&mut cols, &o.name, ["fx", "fy", "fz"], "N");
                push3(&mut cols, &o.name, ["tx", "ty", "tz"], "N m");
            }
            OutputKind::Measure(m) => cols.push(OutputColumn { name: o.name.clone(), unit: measure_unit(model, m) }),
            OutputKind::Energy => {
                for part in ["kinetic", "potential", "strain", "total"] {
                    cols.push(OutputColumn { name: format!("{}.{part}", o.name), unit: "J" });
                }
            }
            OutputKind::ModalCoordinates(b) => {
                for label in model.modal[b.0].iter().flat_map(|m| &m.mode_labels) {
                    cols.push(OutputColumn { name: format!("{}.{label}", o.name), unit: "-" });
                }
            }
            OutputKind::NodePosition(..) | OutputKind::NodeDeformation(..) => push3(&mut cols, &o.name, XYZ, "m"),
            OutputKind::NodeVelocity(..) => push3(&mut cols, &o.name, XYZ, "m/s"),
            OutputKind::NodeAcceleration(..) => push3(&mut cols, &o.name, XYZ, "m/s^2"),
            OutputKind::StrainEnergy(_) => cols.push(OutputColumn { name: o.name.clone(), unit: "J" }),
            OutputKind::ConstraintResidual => {
                cols.push(OutputColumn { name: format!("{}.position", o.name), unit: "-" });
                cols.push(OutputColumn { name: format!("{}.velocity", o.name), unit: "-" });
            }
        }
    }
    cols
}

fn measure_unit(model: &Model, m: crate::model::MeasureId) -> &'static str {
    use crate::measure::MeasureKind::*;
    match model.measures[m.0].kind {
        JointAngle(_) => "rad",
        JointRate(_) => "rad/s",
        JointDisplacement(_) | Distance(..) | Position(..) => "m",
        JointVelocity(_) | DistanceRate(..) | Velocity(..) | Speed(_) => "m/s",
        Parameter(_) => "-",
    }
}

/// Largest `|Φ|` and `|B v + Φ_t|` over the rows in force (after the constraints stage).
pub(crate) fn constraint_residuals(model: &Model, data: &Data, active: &[bool]) -> (f64, f64) {
    let mut pos = 0.0_f64;
    let mut vel = 0.0_f64;
    for (row, terms) in data.equations.iter().enumerate() {
        if !active[row] {
            continue;
        }
        let joint = &model.joints[model.layout.equations[row].0 .0];
        let (mi, mj) = (&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]);
        pos = pos.max(terms.phi.abs());
        vel = vel.max(terms.rate(mi, mj).abs());
    }
    (pos, vel)
}

/// Writes the output values at a state whose stages (and acceleration solve) are in `data`.
pub(crate) fn evaluate_outputs(
    model: &Model,
    data: &Data,
    q: &[f64],
    v: &[f64],
    acc: &Accelerations,
    active: &[bool],
    out: &mut [f64],
) {
    let mut k = 0;
    let mut put = |out: &mut [f64], x: f64| {
        out[k] = x;
        k += 1;
    };
    for o in &model.outputs {
        match o.kind {
            OutputKind::MarkerPosition(m) => data.markers[m.0].position.iter().for_each(|x| put(out, *x)),
            OutputKind::MarkerVelocity(m) => data.markers[m.0].velocity.iter().for_each(|x| put(out, *x)),
            OutputKind::MarkerAcceleration(m) => {
                let ms = &data.markers[m.0];
                let mut a = ms.accel_bias;
                if let Some(b) = ms.body {
                    let vo = model.layout.v_offset[b.0];
                    let vdot = nalgebra::Vector6::from_column_slice(&acc.vdot[vo..vo + 6]);
                    a += ms.jac_point * vdot;
                    if let (Some(node), Some(modal)) = (ms.node, &model.modal[b.0]) {
                        let m = modal.modes();
                        let add = nalgebra::DVectorView::from_slice(&acc.vdot[vo + 6..vo + 6 + m], m);
                        a += ms.body_rotation * (&modal.nodes[node].psi * add);
                    }
                }
                a.iter().for_each(|x| put(out, *x));
            }
            OutputKind::MarkerAngularVelocity(m) => data.markers[m.0].angular_velocity.iter().for_each(|x| put(out, *x)),
            OutputKind::JointReaction(j) => {
                let mut f = Vec3::zeros();
                let mut t = Vec3::zeros();
                for row in model.layout.joint_rows[j.0].clone() {
                    let lam = acc.lambda[row];
                    f -= lam * data.equations[row].d_point_i;
                    t -= lam * data.equations[row].d_rot_i;
                }
                f.iter().chain(t.iter()).for_each(|x| put(out, *x));
            }
            OutputKind::Measure(m) => put(out, measure_value(model, data, model.measures[m.0].kind)),
            OutputKind::Energy => {
                let e = energy(model, data, q, v);
                put(out, e.kinetic);
                put(out, e.potential);
                put(out, e.strain);
                put(out, e.total());
            }
            OutputKind::ModalCoordinates(b) => data.modal[b.0].a.iter().for_each(|x| put(out, *x)),
            OutputKind::NodePosition(b, node) => node_motion(model, data, q, v, &acc.vdot, b, node).0.iter().for_each(|x| put(out, *x)),
            OutputKind::NodeVelocity(b, node) => node_motion(model, data, q, v, &acc.vdot, b, node).1.iter().for_each(|x| put(out, *x)),
            OutputKind::NodeAcceleration(b, node) => {
                node_motion(model, data, q, v, &acc.vdot, b, node).2.iter().for_each(|x| put(out, *x))
            }
            OutputKind::NodeDeformation(b, node) => {
                let u = model.modal[b.0].as_ref().map_or(Vec3::zeros(), |m| &m.nodes[node].psi * &data.modal[b.0].a);
                u.iter().for_each(|x| put(out, *x));
            }
            OutputKind::StrainEnergy(b) => {
                let strain = model.modal[b.0].as_ref().map_or(0.0, |m| {
                    let a = &data.modal[b.0].a;
                    0.5 * a.dot(&(&m.stiffness * a))
                });
                put(out, strain);
            }
            OutputKind::ConstraintResidual => {
                let (p, vel) = constraint_residuals(model, data, active);
                put(out, p);
                put(out, vel);
            }
        }
    }
}

/// Global position, velocity and acceleration of node `node` of flexible body `b` (formulation.md §2):
/// `R + A r̄`, `Ṙ + A (ω̄ × r̄ + Ψ ȧ)`, `R̈ + A (ω̄̇ × r̄ + Ψ ä + ω̄ × (ω̄ × r̄) + 2 ω̄ × Ψ ȧ)`.
fn node_motion(model: &Model, data: &Data, q: &[f64], v: &[f64], vdot: &[f64], b: crate::model::BodyId, node: usize) -> (Vec3, Vec3, Vec3) {
    let Some(modal) = &model.modal[b.0] else { return (Vec3::zeros(), Vec3::zeros(), Vec3::zeros()) };
    let (qo, vo) = (model.layout.q_offset[b.0], model.layout.v_offset[b.0]);
    let m = modal.modes();
    let n = &modal.nodes[node];
    let state = &data.modal[b.0];
    let a_mat = data.bodies[b.0].rotation;
    let w = data.bodies[b.0].omega_bar;
    let r_bar: Vec3 = n.position + &n.psi * &state.a;
    let u_dot: Vec3 = &n.psi * &state.a_dot;
    let add = nalgebra::DVectorView::from_slice(&vdot[vo + 6..vo + 6 + m], m);
    let u_ddot: Vec3 = &n.psi * add;
    let wd = Vec3::from_column_slice(&vdot[vo + 3..vo + 6]);
    let position = Vec3::from_column_slice(&q[qo..qo + 3]) + a_mat * r_bar;
    let velocity = Vec3::from_column_slice(&v[vo..vo + 3]) + a_mat * (w.cross(&r_bar) + u_dot);
    let acceleration = Vec3::from_column_slice(&vdot[vo..vo + 3])
        + a_mat * (wd.cross(&r_bar) + u_ddot + w.cross(&w.cross(&r_bar)) + 2.0 * w.cross(&u_dot));
    (position, velocity, acceleration)
}
