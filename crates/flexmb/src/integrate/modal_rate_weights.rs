//! The error weights of a flexible body's modal rates: a rate error weighed by the displacement it
//! makes.
//!
//! The tolerances promise a global error of positions (docs/accuracy.md), and the error test weighs
//! velocities with the same `atol + rtol |y|` as positions, in m/s for m: a velocity error `δv` of a
//! rigid coordinate moves the positions by `δv t` over the time `t` after it, so the weight says that one
//! second of drift is what a velocity error stands for. A modal rate error `δȧ` of a mode of circular
//! frequency `ω` does not drift: it is an oscillation of the mode's coordinate of amplitude `δȧ / ω`.
//! Its weight is therefore [`DRIFT_TIME`]` · ω` times looser (never tighter: a mode slower than one
//! radian per second drifts as a rigid coordinate does within the second), so that a stiff mode's rate is
//! held to the displacement it makes, as every position is. Without it the rates of modes of hundreds of
//! hertz set the steps of error per unit step (the peer's beam pendulum at rtol 1e-4: 79,304 BDF steps
//! for an error of 6e-10 of the tip, docs/accuracy.md).
//!
//! The frequency of a modal coordinate is its Rayleigh quotient `√(K_jj / M_jj)` (modal stiffness over
//! modal mass): the natural frequency itself for a basis of natural modes, and between the lowest and the
//! highest natural frequency for any other basis.

use crate::model::Model;

/// The time (s) over which the error weight of a velocity stands for a drift of the positions: the
/// second in which `atol` is given in m/s for m.
const DRIFT_TIME: f64 = 1.0;

/// The factor of each velocity coordinate's error weight (length `nv`, in the layout's velocity order):
/// `max(1, DRIFT_TIME · ωⱼ)` for the rate of modal coordinate `j` of a flexible body, 1 for every rigid
/// velocity.
pub(crate) fn velocity_weight_factors(model: &Model) -> Vec<f64> {
    let layout = &model.layout;
    let mut factors = vec![1.0; layout.nv];
    for (b, modal) in model.modal.iter().enumerate() {
        let Some(modal) = modal else { continue };
        let mass = modal.invariants.modal_mass();
        for j in 0..layout.modes[b] {
            let (k, m) = (modal.stiffness[(j, j)], mass[(j, j)]);
            if k > 0.0 && m > 0.0 {
                factors[layout.v_offset[b] + 6 + j] = (DRIFT_TIME * (k / m).sqrt()).max(1.0);
            }
        }
    }
    factors
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{InitialState, LumpedNode, ModalBody};
    use crate::math::{Mat3, Vec3};
    use crate::model::ModelBuilder;
    use nalgebra::{DMatrix, Matrix3xX};

    /// A strip of two lumped nodes (1 kg each, rotary inertia 1e-3 kg m²) whose one mode bends the far
    /// node by 1 m and turns both by 1 rad: modal mass 1 + 2e-3, stiffness `k`.
    fn strip(k: f64) -> ModalBody {
        let node = |x: f64| LumpedNode {
            position: Vec3::new(x, 0.0, 0.0),
            mass: 1.0,
            rotary_inertia: Mat3::identity() * 1e-3,
            psi: Matrix3xX::from_column_slice(&[0.0, 0.0, x]),
            theta: Matrix3xX::from_column_slice(&[0.0, -1.0, 0.0]),
        };
        ModalBody::from_lumped_nodes(&[node(0.0), node(1.0)], DMatrix::from_element(1, 1, k)).unwrap()
    }

    /// A rigid model's velocities keep their weights; a modal rate's weight is its mode's `ω` times
    /// looser (`ω` in rad/s over one second), so that a rate error weighs what the oscillation it makes
    /// moves the coordinate by; a mode slower than 1 rad/s keeps its weight.
    #[test]
    fn a_modal_rate_is_weighed_by_the_displacement_it_makes() {
        let rigid = crate::analysis::test_models::double_pendulum_with_spring();
        assert!(velocity_weight_factors(&rigid).iter().all(|&f| f == 1.0));
        for (k, expected) in [(1e4, (1e4 / 1.002f64).sqrt()), (0.5, 1.0)] {
            let mut b = ModelBuilder::new("strip");
            b.add_flexible_body("strip", InitialState::default(), strip(k)).unwrap();
            let model = b.build().unwrap();
            let factors = velocity_weight_factors(&model);
            assert_eq!(factors.len(), 7);
            assert!(factors[..6].iter().all(|&f| f == 1.0), "{factors:?}");
            assert!((factors[6] - expected).abs() < 1e-12 * expected, "{factors:?} against {expected}");
        }
    }
}
