//! What a joint reports: its relative coordinates and their rates, its Lagrange multipliers, and the
//! force and torque it applies (its reaction) in global or marker axes.

use crate::data::Data;
use crate::joint::Equation;
use crate::math::{EulerParameters, Vec3};
use crate::measure::MeasureKind;
use crate::model::{JointCoordinateSet, JointId, Model};
use crate::stage::measure_value;

/// Column suffixes and units of a joint's relative coordinates.
pub(super) fn coordinate_columns(set: JointCoordinateSet) -> &'static [(&'static str, &'static str)] {
    const ANGLE: &[(&str, &str)] = &[("angle", "rad"), ("rate", "rad/s")];
    const DISPLACEMENT: &[(&str, &str)] = &[("displacement", "m"), ("velocity", "m/s")];
    const BOTH: &[(&str, &str)] = &[("angle", "rad"), ("rate", "rad/s"), ("displacement", "m"), ("velocity", "m/s")];
    const ROTATION: &[(&str, &str)] = &[
        ("rotation.x", "rad"),
        ("rotation.y", "rad"),
        ("rotation.z", "rad"),
        ("angular_velocity.x", "rad/s"),
        ("angular_velocity.y", "rad/s"),
        ("angular_velocity.z", "rad/s"),
    ];
    match set {
        JointCoordinateSet::Angle => ANGLE,
        JointCoordinateSet::Displacement => DISPLACEMENT,
        JointCoordinateSet::AngleAndDisplacement => BOTH,
        JointCoordinateSet::RelativeRotation => ROTATION,
    }
}

/// The values of [`coordinate_columns`], in order. The angle and displacement are those of the
/// joint-angle and joint-displacement measures; the relative rotation is the rotation vector
/// `θ u` (`0 ≤ θ ≤ π`) of `A_iᵀ A_j` and the relative angular velocity `ω_j − ω_i`, both in the axes of
/// marker `i`.
pub(super) fn coordinates(model: &Model, data: &Data, j: JointId, set: JointCoordinateSet, mut put: impl FnMut(f64)) {
    let angle = |put: &mut dyn FnMut(f64)| {
        put(measure_value(model, data, MeasureKind::JointAngle(j)));
        put(measure_value(model, data, MeasureKind::JointRate(j)));
    };
    let displacement = |put: &mut dyn FnMut(f64)| {
        put(measure_value(model, data, MeasureKind::JointDisplacement(j)));
        put(measure_value(model, data, MeasureKind::JointVelocity(j)));
    };
    match set {
        JointCoordinateSet::Angle => angle(&mut put),
        JointCoordinateSet::Displacement => displacement(&mut put),
        JointCoordinateSet::AngleAndDisplacement => {
            angle(&mut put);
            displacement(&mut put);
        }
        JointCoordinateSet::RelativeRotation => {
            let joint = &model.joints[j.0];
            let (mi, mj) = (&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]);
            let relative = mi.axes.transpose() * mj.axes;
            let rotation = EulerParameters::from_rotation_matrix(&relative).map_or(Vec3::repeat(f64::NAN), |p| {
                let e = Vec3::new(p.0[1], p.0[2], p.0[3]);
                let sin_half = e.norm();
                if sin_half == 0.0 {
                    Vec3::zeros()
                } else {
                    e * (2.0 * sin_half.atan2(p.0[0]) / sin_half)
                }
            });
            let omega = mi.axes.transpose() * (mj.angular_velocity - mi.angular_velocity);
            rotation.iter().chain(omega.iter()).for_each(|x| put(*x));
        }
    }
}

/// The unit of the multiplier of a constraint equation: the generalized force per unit of the
/// equation's `Φ`.
pub(super) fn multiplier_unit(equation: Equation) -> &'static str {
    match equation {
        Equation::Point(_) | Equation::Dot2(_) | Equation::Displacement => "N",
        Equation::Dot1(..) | Equation::Angle => "N m",
        Equation::Distance => "N/m",
    }
}

/// Force and torque joint `j` applies to the body of marker `i`, at the origin of marker `i`, global:
/// `−Σ λ_r ∂Φ_r/∂(r_i, θ_i)` over its rows.
pub(super) fn reaction(model: &Model, data: &Data, lambda: &[f64], j: JointId) -> (Vec3, Vec3) {
    let mut f = Vec3::zeros();
    let mut t = Vec3::zeros();
    for row in model.layout.joint_rows[j.0].clone() {
        f -= lambda[row] * data.equations[row].d_point_i;
        t -= lambda[row] * data.equations[row].d_rot_i;
    }
    (f, t)
}
