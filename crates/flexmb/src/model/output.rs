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
    /// The force and torque of [`JointReaction`](Self::JointReaction) resolved in the axes of a marker:
    /// `.fx .fy .fz .tx .ty .tz`.
    JointReactionIn(JointId, MarkerId),
    /// The Lagrange multipliers of a joint's constraint rows, one column per row: `.lambda1 .lambda2 …`.
    JointMultipliers(JointId),
    /// A joint's relative coordinates and their rates.
    JointCoordinates(JointId, JointCoordinateSet),
    /// A frame's orientation.
    Orientation(RotatingFrame, OrientationForm),
    /// A frame's angular velocity (rad/s): `.x .y .z`.
    AngularVelocity(RotatingFrame, OutputAxes),
    /// A frame's angular acceleration (rad/s²): `.x .y .z`.
    AngularAcceleration(RotatingFrame, OutputAxes),
    /// A body's kinetic energy `½ vᵀ M v` (J), elastic motion included.
    KineticEnergy(BodyId),
    /// A body's linear momentum (N s), global: `.x .y .z`.
    LinearMomentum(BodyId),
    /// A body's angular momentum about its centre of mass (N m s), global axes: `.x .y .z`.
    AngularMomentum(BodyId),
    /// The system's linear momentum and its angular momentum about the global origin, global axes:
    /// `.linear.x .linear.y .linear.z .angular.x .angular.y .angular.z`.
    SystemMomentum,
    /// `|pᵀp − 1|` of a body's Euler parameters, or the largest over all bodies (`None`).
    EulerParameterNormError(Option<BodyId>),
    /// The user output expression of this index in [`Model::output_expressions`](crate::Model::output_expressions).
    UserExpression(usize),
}

/// The frame whose rotation an orientation, angular velocity or angular acceleration output reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RotatingFrame {
    /// A body's reference frame (for a flexible body, its floating frame).
    Body(BodyId),
    /// A marker's axes (on a flexible body they turn with the node's elastic rotation).
    Marker(MarkerId),
}

/// The axes a vector output is resolved in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputAxes {
    /// Global axes.
    Global,
    /// The axes of the body the output reads (for a marker, the reference frame of its body; ground's
    /// are the global axes).
    Body,
    /// The axes of a marker, at the same instant.
    Marker(MarkerId),
}

/// How an orientation output writes a rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrientationForm {
    /// Euler parameters `e0 e1 e2 e3` (`e0 ≥ 0` for a marker; a body's own parameters as integrated).
    EulerParameters,
    /// The rotation matrix `A` (global components of the frame's axes as columns), row by row.
    RotationMatrix,
    /// Three angles of successive rotations about body-fixed axes, continued past ±π over time.
    Angles(crate::math::EulerSequence),
}

/// What a joint's relative coordinates output writes, chosen from the joint's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointCoordinateSet {
    /// The angle about `z_i` and its rate (revolute, angle driver).
    Angle,
    /// The displacement along `z_i` and its rate (translational, displacement driver).
    Displacement,
    /// Both (cylindrical).
    AngleAndDisplacement,
    /// The rotation vector of marker `j`'s axes relative to marker `i`'s and the relative angular
    /// velocity `ω_j − ω_i`, both in the axes of marker `i` (spherical, universal and the others).
    RelativeRotation,
}

/// A user output: an expression of time, measures and the output columns listed before it, with the
/// unit it is written in.
#[derive(Clone, Debug)]
pub struct UserOutput {
    /// The expression ([`Variable::OutputColumn`](crate::function::Variable::OutputColumn) reads a
    /// column of an earlier output).
    pub expression: crate::function::Expression,
    /// Its unit, as written in the column list (free text, e.g. `N m`).
    pub unit: String,
}

impl crate::Model {
    /// The model if every user output reads only columns before its own; else the error naming it.
    pub(super) fn with_checked_output_expressions(self) -> Result<Self, super::ModelError> {
        let mut first = 0;
        for o in &self.outputs {
            let count = crate::analysis::columns_of_output(&crate::analysis::ColumnSources::of(&self), o).len();
            if let OutputKind::UserExpression(e) = o.kind {
                if let Some(c) = self.output_expressions[e].expression.output_columns().find(|c| *c >= first) {
                    return Err(super::ModelError::BadValue {
                        element: "output",
                        name: o.name.clone(),
                        problem: format!(
                            "its expression reads output column {c}, but only the {first} columns of the outputs before it can be read"
                        ),
                    });
                }
            }
            first += count;
        }
        Ok(self)
    }
}
