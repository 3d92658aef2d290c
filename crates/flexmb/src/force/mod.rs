//! Force elements. Gravity is a model property; the elements here act between or on markers.
//!
//! Sign conventions follow the common multibody codes:
//! - a translational spring–damper–actuator pushes its markers apart with
//!   `F = −k (l − l₀) − c l̇ + f_act` along `u = (r_j − r_i)/l` (on `j`: `F u`, on `i`: `−F u`);
//! - a rotational spring–damper–actuator on a revolute joint applies `T = −k (θ − θ₀) − c θ̇ + f_act` about
//!   `z_i` to the body of marker `j` and `−T` to the body of marker `i`;
//! - an applied force or torque acts on one marker only (its reaction goes to the inertial frame).

use crate::function::Expression;
use crate::model::{JointId, MarkerId};

/// The axes in which applied force or torque components are given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForceFrame {
    /// Global axes.
    Global,
    /// The axes of the body the marker is fixed on.
    Body,
    /// The marker's own axes.
    Marker,
}

/// A force element and its data.
#[derive(Clone, Debug)]
pub enum ForceKind {
    /// A spring, damper and actuator along the line between two marker origins.
    TranslationalSpringDamper {
        /// The marker the line starts at.
        marker_i: MarkerId,
        /// The marker the line ends at.
        marker_j: MarkerId,
        /// `k` (N/m).
        stiffness: f64,
        /// `c` (N s/m).
        damping: f64,
        /// `l₀` (m).
        free_length: f64,
        /// `f_act(t, measures)` (N), positive pushes apart.
        actuator: Option<Expression>,
    },
    /// A torsional spring, damper and actuator about the axis of a joint.
    RotationalSpringDamper {
        /// A revolute or cylindrical joint; the torque acts about its `z_i`.
        joint: JointId,
        /// `k` (N m/rad).
        stiffness: f64,
        /// `c` (N m s/rad).
        damping: f64,
        /// `θ₀` (rad).
        free_angle: f64,
        /// `f_act(t, measures)` (N m), positive drives `θ` up.
        actuator: Option<Expression>,
    },
    /// A force at a marker origin, its components functions of time and measures (N).
    AppliedForce {
        /// The marker the force acts at.
        marker: MarkerId,
        /// The components along the axes of `frame`.
        components: [Expression; 3],
        /// The axes the components are given in.
        frame: ForceFrame,
    },
    /// A torque on a marker's body, its components functions of time and measures (N m).
    AppliedTorque {
        /// The marker whose body the torque acts on.
        marker: MarkerId,
        /// The components along the axes of `frame`.
        components: [Expression; 3],
        /// The axes the components are given in.
        frame: ForceFrame,
    },
}

impl ForceKind {
    /// The keyword used in model files and messages.
    pub fn keyword(&self) -> &'static str {
        match self {
            ForceKind::TranslationalSpringDamper { .. } => "translational spring-damper",
            ForceKind::RotationalSpringDamper { .. } => "rotational spring-damper",
            ForceKind::AppliedForce { .. } => "applied force",
            ForceKind::AppliedTorque { .. } => "applied torque",
        }
    }

    /// Every expression of this element.
    pub fn expressions(&self) -> Vec<&Expression> {
        match self {
            ForceKind::TranslationalSpringDamper { actuator, .. }
            | ForceKind::RotationalSpringDamper { actuator, .. } => actuator.iter().collect(),
            ForceKind::AppliedForce { components, .. } | ForceKind::AppliedTorque { components, .. } => {
                components.iter().collect()
            }
        }
    }
}

/// A named force element.
#[derive(Clone, Debug)]
pub struct ForceElement {
    /// The element's name.
    pub name: String,
    /// What it is and its data.
    pub kind: ForceKind,
}
