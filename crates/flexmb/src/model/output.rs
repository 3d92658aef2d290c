//! Output requests: what a simulation reports at each output time.

use crate::model::{BodyId, JointId, MarkerId, MeasureId};

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
    /// Kinetic, potential (gravity and springs), strain (flexible bodies) and total energy (J):
    /// `.kinetic .potential .strain .total`.
    Energy,
    /// The modal coordinates of a flexible body, one column per mode named by its label (`.N1`, …).
    ModalCoordinates(BodyId),
    /// Global position of a node of a flexible body (m): `.x .y .z`.
    NodePosition(BodyId, usize),
    /// Global velocity of a node (m/s).
    NodeVelocity(BodyId, usize),
    /// Global acceleration of a node (m/s²).
    NodeAcceleration(BodyId, usize),
    /// Elastic displacement `Ψ a` of a node in the body frame (m).
    NodeDeformation(BodyId, usize),
    /// Strain energy `½ aᵀ K a` of a flexible body (J).
    StrainEnergy(BodyId),
    /// Largest position and velocity constraint residual.
    ConstraintResidual,
}
