//! Named measures: scalar functions of the state that force expressions and outputs read
//! (joint angle and rate, distance and speed between markers, marker position and velocity components).

use crate::model::{JointId, MarkerId, ParameterId};

/// What a measure reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeasureKind {
    /// Angle from `x_i` to `x_j` about `z_i` of a revolute or cylindrical joint (rad), continuous past ±π.
    JointAngle(JointId),
    /// Its rate (rad/s).
    JointRate(JointId),
    /// `z_iᵀ (r_j − r_i)` of a translational or cylindrical joint (m).
    JointDisplacement(JointId),
    /// Its rate (m/s).
    JointVelocity(JointId),
    /// `|r_j − r_i|` (m).
    Distance(MarkerId, MarkerId),
    /// `d|r_j − r_i|/dt` (m/s).
    DistanceRate(MarkerId, MarkerId),
    /// Global position component 0, 1, 2 of a marker origin (m).
    Position(MarkerId, usize),
    /// Global velocity component of a marker origin (m/s).
    Velocity(MarkerId, usize),
    /// Speed `|ṙ|` of a marker origin (m/s).
    Speed(MarkerId),
    /// The current value of a parameter (declared with
    /// [`ModelBuilder::add_parameter`](crate::ModelBuilder::add_parameter)).
    Parameter(ParameterId),
}

/// A named value that may be changed between the steps of a simulation (e.g. a gain of a force law's
/// actuator expression); expressions read it through the measure of the same name.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Its name, as expressions name it.
    pub name: String,
    /// Its initial value.
    pub value: f64,
}

/// A named measure.
#[derive(Clone, Debug)]
pub struct Measure {
    /// The name expressions read it by.
    pub name: String,
    /// What it reads.
    pub kind: MeasureKind,
}
