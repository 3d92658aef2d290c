//! Joints: named joints composed from Haug's primitive constraint equations (formulation.md §6), and
//! drivers that prescribe a joint's relative angle or displacement as a function of time.
//!
//! Every joint acts between two markers `i` and `j`. Conventions (marker axes `x, y, z`):
//!
//! | kind | equations | meaning |
//! |---|---|---|
//! | spherical | 3 | origins coincide |
//! | revolute | 5 | origins coincide, `z_i ∥ z_j` (rotation about the common z axis) |
//! | universal | 4 | origins coincide, `z_i ⟂ z_j` (the two cross-pin axes) |
//! | cylindrical | 4 | `z_i ∥ z_j` and origin `j` on the z axis of `i` |
//! | translational | 5 | cylindrical and `x_i ⟂ y_j` (no rotation about z) |
//! | fixed | 6 | origins coincide and axes keep their relative orientation |
//! | planar | 3 | `z_i ∥ z_j` and origin `j` in the x–y plane of `i` |
//! | distance | 1 | `|r_j − r_i| = L(t)` |
//! | dot-1 | 1 | a chosen axis of `i` ⟂ a chosen axis of `j` |
//! | dot-2 | 1 | a chosen axis of `i` ⟂ `d = r_j − r_i` |
//! | point-on-line | 2 | origin `j` on the z axis of `i` |
//! | point-in-plane | 1 | origin `j` in the x–y plane of `i` |
//! | angle driver | 1 | angle from `x_i` to `x_j` about `z_i` equals `f(t)` |
//! | displacement driver | 1 | `z_iᵀ (r_j − r_i) = f(t)` |

mod equation;
#[cfg(test)]
mod tests;

pub(crate) use equation::{relative_angle, Equation, EquationTerms};

use crate::function::TimeFunction;
use crate::model::MarkerId;

/// One of a marker's axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// The first axis.
    X,
    /// The second axis.
    Y,
    /// The third axis, the axis of rotation or translation of most joints.
    Z,
}

impl Axis {
    /// Column index in a marker's axes matrix.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    fn letter(self) -> char {
        ['x', 'y', 'z'][self.index()]
    }
}

/// The kind of a joint and the data it needs.
#[derive(Clone, Debug)]
pub enum JointKind {
    /// Origins coincide (3 equations).
    Spherical,
    /// Origins coincide and `z_i ∥ z_j`: rotation about the common z axis (5 equations).
    Revolute,
    /// Origins coincide and `z_i ⟂ z_j`, the two cross-pin axes (4 equations).
    Universal,
    /// `z_i ∥ z_j` and origin `j` on the z axis of `i`: rotation about and translation along it (4
    /// equations).
    Cylindrical,
    /// Cylindrical without the rotation: translation along `z_i` only (5 equations).
    Translational,
    /// Origins coincide and the axes keep their relative orientation (6 equations).
    Fixed,
    /// `z_i ∥ z_j` and origin `j` in the x–y plane of `i` (3 equations).
    Planar,
    /// `|r_j − r_i| = L(t)`.
    Distance {
        /// The prescribed distance `L(t)` (m).
        length: TimeFunction,
    },
    /// Axis `axis_i` of marker `i` stays perpendicular to axis `axis_j` of marker `j`.
    Dot1 {
        /// The axis of marker `i`.
        axis_i: Axis,
        /// The axis of marker `j`.
        axis_j: Axis,
    },
    /// Axis `axis_i` of marker `i` stays perpendicular to `d = r_j − r_i`.
    Dot2 {
        /// The axis of marker `i`.
        axis_i: Axis,
    },
    /// Origin `j` on the z axis of `i` (2 equations).
    PointOnLine,
    /// Origin `j` in the x–y plane of `i` (1 equation).
    PointInPlane,
    /// Relative angle of a revolute or cylindrical joint prescribed: `θ(q) = f(t)`.
    AngleDriver {
        /// The angle `f(t)` (rad).
        function: TimeFunction,
    },
    /// Relative displacement of a translational or cylindrical joint prescribed: `z_iᵀ d = f(t)`.
    DisplacementDriver {
        /// The displacement `f(t)` (m).
        function: TimeFunction,
    },
}

impl JointKind {
    /// The keyword used in model files and messages.
    pub fn keyword(&self) -> &'static str {
        match self {
            JointKind::Spherical => "spherical",
            JointKind::Revolute => "revolute",
            JointKind::Universal => "universal",
            JointKind::Cylindrical => "cylindrical",
            JointKind::Translational => "translational",
            JointKind::Fixed => "fixed",
            JointKind::Planar => "planar",
            JointKind::Distance { .. } => "distance",
            JointKind::Dot1 { .. } => "dot-1",
            JointKind::Dot2 { .. } => "dot-2",
            JointKind::PointOnLine => "point-on-line",
            JointKind::PointInPlane => "point-in-plane",
            JointKind::AngleDriver { .. } => "angle driver",
            JointKind::DisplacementDriver { .. } => "displacement driver",
        }
    }

    /// The primitive equations this joint is made of, in row order.
    pub(crate) fn equations(&self) -> Vec<Equation> {
        use Axis::*;
        use Equation as E;
        let point = [E::Point(0), E::Point(1), E::Point(2)];
        let parallel_z = [E::Dot1(X, Z), E::Dot1(Y, Z)];
        match self {
            JointKind::Spherical => point.to_vec(),
            JointKind::Revolute => [&point[..], &parallel_z[..]].concat(),
            JointKind::Universal => [&point[..], &[E::Dot1(Z, Z)]].concat(),
            JointKind::Cylindrical => [&parallel_z[..], &[E::Dot2(X), E::Dot2(Y)]].concat(),
            JointKind::Translational => {
                [&parallel_z[..], &[E::Dot2(X), E::Dot2(Y), E::Dot1(X, Y)]].concat()
            }
            JointKind::Fixed => [&point[..], &parallel_z[..], &[E::Dot1(X, Y)]].concat(),
            JointKind::Planar => [&parallel_z[..], &[E::Dot2(Z)]].concat(),
            JointKind::Distance { .. } => vec![E::Distance],
            JointKind::Dot1 { axis_i, axis_j } => vec![E::Dot1(*axis_i, *axis_j)],
            JointKind::Dot2 { axis_i } => vec![E::Dot2(*axis_i)],
            JointKind::PointOnLine => vec![E::Dot2(X), E::Dot2(Y)],
            JointKind::PointInPlane => vec![E::Dot2(Z)],
            JointKind::AngleDriver { .. } => vec![E::Angle],
            JointKind::DisplacementDriver { .. } => vec![E::Displacement],
        }
    }

    /// The time function of a driver or distance joint.
    pub(crate) fn time_function(&self) -> Option<&TimeFunction> {
        match self {
            JointKind::Distance { length } => Some(length),
            JointKind::AngleDriver { function } | JointKind::DisplacementDriver { function } => {
                Some(function)
            }
            _ => None,
        }
    }

    /// Whether the joint prescribes a motion (an angle or displacement driver).
    pub fn is_driver(&self) -> bool {
        matches!(self, JointKind::AngleDriver { .. } | JointKind::DisplacementDriver { .. })
    }

    /// Whether the joint allows a relative rotation about `z_i` that an angle measure can read.
    pub fn has_rotation_about_z(&self) -> bool {
        matches!(self, JointKind::Revolute | JointKind::Cylindrical | JointKind::AngleDriver { .. })
    }

    /// Whether the joint allows a relative translation along `z_i` that a displacement measure can read.
    pub fn has_translation_along_z(&self) -> bool {
        matches!(
            self,
            JointKind::Translational | JointKind::Cylindrical | JointKind::DisplacementDriver { .. }
        )
    }
}

/// A joint, primitive or driver between markers `i` and `j`.
#[derive(Clone, Debug)]
pub struct Joint {
    /// The joint's name.
    pub name: String,
    /// What it is and its data.
    pub kind: JointKind,
    /// The first marker: the joint's reference frame (its `z_i` is the axis of angles and
    /// displacements).
    pub marker_i: MarkerId,
    /// The second marker.
    pub marker_j: MarkerId,
}

impl Equation {
    /// A short label such as `dot-1(x_i, z_j)`, used in diagnostics.
    pub fn label(&self) -> String {
        match self {
            Equation::Point(k) => format!("coincident origins, {} component", ['x', 'y', 'z'][*k]),
            Equation::Dot1(a, b) => format!("dot-1({}_i, {}_j)", a.letter(), b.letter()),
            Equation::Dot2(a) => format!("dot-2({}_i, d_ij)", a.letter()),
            Equation::Distance => "distance |d_ij| = L(t)".to_string(),
            Equation::Angle => "angle about z_i = f(t)".to_string(),
            Equation::Displacement => "displacement along z_i = f(t)".to_string(),
        }
    }
}
