//! Measures stage: the values of the named measures that force expressions read.

use crate::data::Data;
use crate::joint::{Axis, Equation};
use crate::measure::MeasureKind;
use crate::model::Model;

/// Fills `data.measures` (after the kinematics stage).
pub(crate) fn measures(model: &Model, data: &mut Data) {
    for (k, m) in model.measures.iter().enumerate() {
        data.measures[k] = measure_value(model, data, m.kind);
    }
}

/// The value of one measure from the current marker kinematics.
pub(crate) fn measure_value(model: &Model, data: &Data, kind: MeasureKind) -> f64 {
    let mk = |id: crate::model::MarkerId| &data.markers[id.0];
    match kind {
        MeasureKind::JointAngle(j) | MeasureKind::JointRate(j) => {
            let joint = &model.joints[j.0];
            let (mi, mj) = (mk(joint.marker_i), mk(joint.marker_j));
            let terms = Equation::Angle.evaluate(mi, mj, [0.0; 3], data.angle_reference[j.0]);
            if matches!(kind, MeasureKind::JointAngle(_)) {
                terms.phi
            } else {
                terms.rate(mi, mj)
            }
        }
        MeasureKind::JointDisplacement(j) | MeasureKind::JointVelocity(j) => {
            let joint = &model.joints[j.0];
            let (mi, mj) = (mk(joint.marker_i), mk(joint.marker_j));
            let terms = Equation::Dot2(Axis::Z).evaluate(mi, mj, [0.0; 3], 0.0);
            if matches!(kind, MeasureKind::JointDisplacement(_)) {
                terms.phi
            } else {
                terms.rate(mi, mj)
            }
        }
        MeasureKind::Distance(i, j) | MeasureKind::DistanceRate(i, j) => {
            let d = mk(j).position - mk(i).position;
            let l = d.norm();
            if matches!(kind, MeasureKind::Distance(..)) {
                l
            } else if l > 0.0 {
                d.dot(&(mk(j).velocity - mk(i).velocity)) / l
            } else {
                0.0
            }
        }
        MeasureKind::Position(m, c) => mk(m).position[c],
        MeasureKind::Velocity(m, c) => mk(m).velocity[c],
        MeasureKind::Speed(m) => mk(m).velocity.norm(),
        MeasureKind::Parameter(p) => data.parameters[p.0],
    }
}

/// Sets each rotational joint's angle reference to its current angle (after the kinematics stage), so
/// that angles continue past ±π from one accepted step to the next.
pub(crate) fn update_angle_references(model: &Model, data: &mut Data) {
    for (j, joint) in model.joints.iter().enumerate() {
        if joint.kind.has_rotation_about_z() {
            let (mi, mj) = (&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]);
            data.angle_reference[j] = crate::joint::relative_angle(mi, mj, data.angle_reference[j]).phi;
        }
    }
}
