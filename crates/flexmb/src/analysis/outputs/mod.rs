//! Output columns: names, units and values of the model's output requests at one state.

mod frame_motion;
mod joint_outputs;
mod momentum;

use super::Accelerations;
use crate::data::Data;
use crate::math::Vec3;
use crate::model::{BodyId, Model, OrientationForm, OutputKind, OutputRequest};
use crate::stage::{energy, measure_value};
use momentum::body_momentum;

/// One column of the results table.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputColumn {
    /// The output's name and component, e.g. `tip.x`.
    pub name: String,
    /// Its unit, e.g. `m/s`.
    pub unit: String,
}

const XYZ: [&str; 3] = ["x", "y", "z"];

/// The columns of every output request, in order (time is not included).
pub fn output_columns(model: &Model) -> Vec<OutputColumn> {
    model.outputs.iter().flat_map(|o| columns_of_output(&ColumnSources::of(model), o)).collect()
}

/// The first column of each position output (`marker_position`, `node_position`; its x, with y and z
/// after it), in the columns of [`output_columns`]: the outputs the global error of docs/accuracy.md is
/// measured in.
pub fn position_output_columns(model: &Model) -> Vec<usize> {
    let sources = ColumnSources::of(model);
    let mut first = Vec::new();
    let mut column = 0;
    for output in &model.outputs {
        let n = columns_of_output(&sources, output).len();
        if matches!(output.kind, OutputKind::MarkerPosition(_) | OutputKind::NodePosition(..)) && n == 3 {
            first.push(column);
        }
        column += n;
    }
    first
}

/// What the columns of an output depend on besides its request: the elements it reads, of a model or
/// of a [`ModelBuilder`](crate::ModelBuilder) being filled.
#[derive(Clone, Copy)]
pub struct ColumnSources<'a> {
    pub(crate) modal: &'a [Option<crate::body::ModalBody>],
    pub(crate) joints: &'a [crate::joint::Joint],
    pub(crate) measures: &'a [crate::measure::Measure],
    pub(crate) output_expressions: &'a [crate::model::UserOutput],
}

impl<'a> ColumnSources<'a> {
    /// Those of a model.
    pub fn of(model: &'a Model) -> Self {
        Self {
            modal: &model.modal,
            joints: &model.joints,
            measures: &model.measures,
            output_expressions: &model.output_expressions,
        }
    }
}

/// The columns of one output request.
pub fn columns_of_output(model: &ColumnSources, o: &OutputRequest) -> Vec<OutputColumn> {
    let mut cols = Vec::new();
    let mut push = |name: String, unit: &str| cols.push(OutputColumn { name, unit: unit.to_string() });
    let base = &o.name;
    let mut push3 = |base: &str, suffix: [&str; 3], unit: &str| {
        for s in suffix {
            push(format!("{base}.{s}"), unit);
        }
    };
    match o.kind {
        OutputKind::MarkerPosition(_) => push3(base, XYZ, "m"),
        OutputKind::MarkerVelocity(_) => push3(base, XYZ, "m/s"),
        OutputKind::MarkerAcceleration(_) => push3(base, XYZ, "m/s^2"),
        OutputKind::MarkerAngularVelocity(_) | OutputKind::AngularVelocity(..) => push3(base, XYZ, "rad/s"),
        OutputKind::AngularAcceleration(..) => push3(base, XYZ, "rad/s^2"),
        OutputKind::JointReaction(_) | OutputKind::JointReactionIn(..) => {
            push3(base, ["fx", "fy", "fz"], "N");
            push3(base, ["tx", "ty", "tz"], "N m");
        }
        OutputKind::JointMultipliers(j) => {
            for (k, equation) in model.joints[j.0].kind.equations().into_iter().enumerate() {
                push(format!("{base}.lambda{}", k + 1), joint_outputs::multiplier_unit(equation));
            }
        }
        OutputKind::JointCoordinates(_, set) => {
            for (suffix, unit) in joint_outputs::coordinate_columns(set) {
                push(format!("{base}.{suffix}"), unit);
            }
        }
        OutputKind::Orientation(_, form) => match form {
            OrientationForm::EulerParameters => {
                for s in ["e0", "e1", "e2", "e3"] {
                    push(format!("{base}.{s}"), "-");
                }
            }
            OrientationForm::RotationMatrix => {
                for r in 1..=3 {
                    for c in 1..=3 {
                        push(format!("{base}.a{r}{c}"), "-");
                    }
                }
            }
            OrientationForm::Angles(_) => push3(base, ["phi", "theta", "psi"], "rad"),
        },
        OutputKind::Measure(m) => push(base.clone(), measure_unit(model, m)),
        OutputKind::Energy => {
            for part in ["kinetic", "potential", "strain", "total"] {
                push(format!("{base}.{part}"), "J");
            }
        }
        OutputKind::KineticEnergy(_) | OutputKind::StrainEnergy(_) => push(base.clone(), "J"),
        OutputKind::LinearMomentum(_) => push3(base, XYZ, "N s"),
        OutputKind::AngularMomentum(_) => push3(base, XYZ, "N m s"),
        OutputKind::SystemMomentum => {
            push3(&format!("{base}.linear"), XYZ, "N s");
            push3(&format!("{base}.angular"), XYZ, "N m s");
        }
        OutputKind::ModalCoordinates(b) => {
            for label in model.modal[b.0].iter().flat_map(|m| &m.mode_labels) {
                push(format!("{base}.{label}"), "-");
            }
        }
        OutputKind::NodePosition(..) | OutputKind::NodeDeformation(..) => push3(base, XYZ, "m"),
        OutputKind::NodeVelocity(..) => push3(base, XYZ, "m/s"),
        OutputKind::NodeAcceleration(..) => push3(base, XYZ, "m/s^2"),
        OutputKind::ConstraintResidual => {
            push(format!("{base}.position"), "-");
            push(format!("{base}.velocity"), "-");
        }
        OutputKind::EulerParameterNormError(_) => push(base.clone(), "-"),
        OutputKind::UserExpression(e) => push(base.clone(), &model.output_expressions[e].unit),
    }
    cols
}

fn measure_unit(model: &ColumnSources, m: crate::model::MeasureId) -> &'static str {
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

/// Writes the output values at a state whose stages (and acceleration solve) are in `data`. `out`
/// holds the previous row's values when `continue_previous` is set: the Euler angles continue from
/// them past ±π.
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate_outputs(
    model: &Model,
    data: &Data,
    (t, q, v): (f64, &[f64], &[f64]),
    acc: &Accelerations,
    active: &[bool],
    out: &mut [f64],
    continue_previous: bool,
) {
    let mut k = 0;
    for o in &model.outputs {
        // What an output reads of the row before its own columns are written: the previous row's
        // angles, the columns before it.
        let previous_angles = match o.kind {
            OutputKind::Orientation(_, OrientationForm::Angles(_)) if continue_previous => Some([out[k], out[k + 1], out[k + 2]]),
            _ => None,
        };
        let user_value = match o.kind {
            OutputKind::UserExpression(e) => model.output_expressions[e].expression.eval_with_columns(t, &data.measures, &out[..k]),
            _ => f64::NAN,
        };
        let mut put = |x: f64| {
            out[k] = x;
            k += 1;
        };
        let put3 = |put: &mut dyn FnMut(f64), x: Vec3| x.iter().for_each(|x| put(*x));
        match o.kind {
            OutputKind::MarkerPosition(m) => put3(&mut put, data.markers[m.0].position),
            OutputKind::MarkerVelocity(m) => put3(&mut put, data.markers[m.0].velocity),
            OutputKind::MarkerAcceleration(m) => put3(&mut put, marker_acceleration(model, data, acc, m)),
            OutputKind::MarkerAngularVelocity(m) => put3(&mut put, data.markers[m.0].angular_velocity),
            OutputKind::AngularVelocity(frame, axes) => {
                put3(&mut put, frame_motion::resolve(data, frame, axes, frame_motion::angular_velocity(data, frame)))
            }
            OutputKind::AngularAcceleration(frame, axes) => {
                let alpha = frame_motion::angular_acceleration(model, data, acc, frame);
                put3(&mut put, frame_motion::resolve(data, frame, axes, alpha))
            }
            OutputKind::Orientation(frame, form) => match form {
                OrientationForm::EulerParameters => {
                    frame_motion::euler_parameters(model, data, q, frame).iter().for_each(|x| put(*x))
                }
                OrientationForm::RotationMatrix => {
                    let a = frame_motion::rotation(data, frame);
                    (0..3).for_each(|r| (0..3).for_each(|c| put(a[(r, c)])));
                }
                OrientationForm::Angles(sequence) => {
                    let a = frame_motion::rotation(data, frame);
                    let angles = frame_motion::continued_angles(sequence, &a, previous_angles);
                    angles.iter().for_each(|x| put(*x));
                }
            },
            OutputKind::JointReaction(j) => {
                let (f, t) = joint_outputs::reaction(model, data, &acc.lambda, j);
                f.iter().chain(t.iter()).for_each(|x| put(*x));
            }
            OutputKind::JointReactionIn(j, m) => {
                let (f, t) = joint_outputs::reaction(model, data, &acc.lambda, j);
                let axes_t = data.markers[m.0].axes.transpose();
                (axes_t * f).iter().chain((axes_t * t).iter()).for_each(|x| put(*x));
            }
            OutputKind::JointMultipliers(j) => model.layout.joint_rows[j.0].clone().for_each(|row| put(acc.lambda[row])),
            OutputKind::JointCoordinates(j, set) => joint_outputs::coordinates(model, data, j, set, put),
            OutputKind::Measure(m) => put(measure_value(model, data, model.measures[m.0].kind)),
            OutputKind::Energy => {
                let e = energy(model, data, q, v);
                [e.kinetic, e.potential, e.strain, e.total()].into_iter().for_each(put);
            }
            OutputKind::KineticEnergy(b) => put(body_momentum(model, data, q, v, b.0).kinetic_energy),
            OutputKind::LinearMomentum(b) => put3(&mut put, body_momentum(model, data, q, v, b.0).linear),
            OutputKind::AngularMomentum(b) => {
                put3(&mut put, body_momentum(model, data, q, v, b.0).angular_about_center_of_mass)
            }
            OutputKind::SystemMomentum => {
                let (mut linear, mut angular) = (Vec3::zeros(), Vec3::zeros());
                for b in 0..model.bodies.len() {
                    let p = body_momentum(model, data, q, v, b);
                    linear += p.linear;
                    angular += p.angular_about_origin;
                }
                put3(&mut put, linear);
                put3(&mut put, angular);
            }
            OutputKind::ModalCoordinates(b) => data.modal[b.0].a.iter().for_each(|x| put(*x)),
            OutputKind::NodePosition(b, node) => put3(&mut put, node_motion(model, data, q, v, &acc.vdot, b, node).0),
            OutputKind::NodeVelocity(b, node) => put3(&mut put, node_motion(model, data, q, v, &acc.vdot, b, node).1),
            OutputKind::NodeAcceleration(b, node) => put3(&mut put, node_motion(model, data, q, v, &acc.vdot, b, node).2),
            OutputKind::NodeDeformation(b, node) => {
                let u = model.modal[b.0].as_ref().map_or(Vec3::zeros(), |m| &m.nodes[node].psi * &data.modal[b.0].a);
                put3(&mut put, u);
            }
            OutputKind::StrainEnergy(b) => {
                let strain = model.modal[b.0].as_ref().map_or(0.0, |m| {
                    let a = &data.modal[b.0].a;
                    0.5 * a.dot(&(&m.stiffness * a))
                });
                put(strain);
            }
            OutputKind::ConstraintResidual => {
                let (p, vel) = constraint_residuals(model, data, active);
                put(p);
                put(vel);
            }
            OutputKind::EulerParameterNormError(body) => put(euler_parameter_norm_error(model, q, body)),
            OutputKind::UserExpression(_) => put(user_value),
        }
    }
}

/// Global acceleration of a marker origin: `J_r v̇_b + A Ψ ä` plus the part that does not depend on
/// the accelerations.
fn marker_acceleration(model: &Model, data: &Data, acc: &Accelerations, m: crate::model::MarkerId) -> Vec3 {
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
    a
}

/// `|pᵀp − 1|` of body `body`'s Euler parameters as integrated, or the largest over all bodies.
fn euler_parameter_norm_error(model: &Model, q: &[f64], body: Option<BodyId>) -> f64 {
    let error = |b: usize| {
        let o = model.layout.q_offset[b] + 3;
        (q[o..o + 4].iter().map(|x| x * x).sum::<f64>() - 1.0).abs()
    };
    match body {
        Some(b) => error(b.0),
        None => (0..model.bodies.len()).map(error).fold(0.0, f64::max),
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
