//! Output columns: names, units and values of the model's output requests at one state.

use super::Accelerations;
use crate::data::Data;
use crate::math::Vec3;
use crate::model::{Model, OutputKind};
use crate::stage::{energy, measure_value};

/// One column of the results table.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputColumn {
    pub name: String,
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
            OutputKind::Energy => push3(&mut cols, &o.name, ["kinetic", "potential", "total"], "J"),
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
                put(out, e.total());
            }
            OutputKind::ConstraintResidual => {
                let (p, vel) = constraint_residuals(model, data, active);
                put(out, p);
                put(out, vel);
            }
        }
    }
}
