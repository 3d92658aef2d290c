//! Joint reactions from the multipliers: the constraint force of row `k` on the body of marker `i` is
//! `−λ_k ∂Φ_k/∂r_i` at the marker's origin and the torque `−λ_k ∂Φ_k/∂ω_i` (global axes; the
//! equations of motion carry `+Bᵀλ` on the left, Haug 1989 §11.1), and likewise on marker `j`'s body.
//! The same force the `joint_reaction` output writes for marker `i`.

use crate::data::Data;
use crate::model::Model;

/// The reaction of one joint (or driver) on the bodies it connects, in global axes.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointReaction {
    /// The joint's name.
    pub joint: String,
    /// The two sides, marker `i` first; a side on ground is left out.
    pub sides: Vec<ReactionSide>,
}

/// The force and torque a joint puts on one of its bodies.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReactionSide {
    /// The body's name.
    pub body: String,
    /// The marker the force acts at.
    pub marker: String,
    /// Where the force acts: the marker's origin (global, m).
    pub point: [f64; 3],
    /// Force on the body (global, N).
    pub force: [f64; 3],
    /// Torque on the body about `point` (global, N m).
    pub torque: [f64; 3],
}

/// The reactions of every joint for the multipliers `lambda`, at the state of the last kinematic
/// stages in `data`.
pub fn joint_reactions(model: &Model, data: &Data, lambda: &[f64]) -> Vec<JointReaction> {
    model
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            let mut sides = Vec::new();
            for (side, marker) in [joint.marker_i, joint.marker_j].into_iter().enumerate() {
                let state = &data.markers[marker.0];
                let Some(body) = state.body else { continue };
                let (mut force, mut torque) = ([0.0; 3], [0.0; 3]);
                for row in model.layout.joint_rows[j].clone() {
                    let terms = &data.equations[row];
                    let (d_point, d_rot) = if side == 0 { (terms.d_point_i, terms.d_rot_i) } else { (terms.d_point_j, terms.d_rot_j) };
                    for k in 0..3 {
                        force[k] -= lambda[row] * d_point[k];
                        torque[k] -= lambda[row] * d_rot[k];
                    }
                }
                sides.push(ReactionSide {
                    body: model.bodies[body.0].name.clone(),
                    marker: model.markers[marker.0].name.clone(),
                    point: state.position.into(),
                    force,
                    torque,
                });
            }
            JointReaction { joint: joint.name.clone(), sides }
        })
        .collect()
}
