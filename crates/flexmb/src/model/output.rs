//! Output requests: what a simulation reports at each output time.

use crate::model::{JointId, MarkerId, MeasureId};

/// One requested output; each expands to one or more named columns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// Global position of a marker origin (m): `.x .y .z`.
    MarkerPosition(MarkerId),
    /// Global velocity of a marker origin (m/s).
    MarkerVelocity(MarkerId),
    /// Global acceleration of a marker origin (m/s²).
    MarkerAcceleration(MarkerId),
    /// Global angular velocity of a marker (rad/s).
    MarkerAngularVelocity(MarkerId),
    /// Force (N) and torque (N m) the joint applies to the body of marker `i`, at the origin of marker `i`,
    /// global components: `.fx .fy .fz .tx .ty .tz`.
    JointReaction(JointId),
    /// A named measure.
    Measure(MeasureId),
    /// Kinetic, potential (gravity and springs) and total energy (J).
    Energy,
    /// Largest position and velocity constraint residual.
    ConstraintResidual,
}
