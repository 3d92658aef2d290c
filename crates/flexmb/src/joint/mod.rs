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
    X,
    Y,
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
    Spherical,
    Revolute,
    Universal,
    Cylindrical,
    Translational,
    Fixed,
    Planar,
    /// `|r_j − r_i| = L(t)`.
    Distance { length: TimeFunction },
    Dot1 { axis_i: Axis, axis_j: Axis },
    Dot2 { axis_i: Axis },
    PointOnLine,
    PointInPlane,
    /// Relative angle of a revolute or cylindrical joint prescribed: `θ(q) = f(t)`.
    AngleDriver { function: TimeFunction },
    /// Relative displacement of a translational or cylindrical joint prescribed: `z_iᵀ d = f(t)`.
    DisplacementDriver { function: TimeFunction },
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
    pub name: String,
    pub kind: JointKind,
    pub marker_i: MarkerId,
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
