//! The kinematic equations of the bodies' coordinates: the position rates `q̇ = T(q) v` of the velocity
//! variables, and the unit norm of the Euler parameters.
//!
//! Each body has 7 + m positions `q = [R, p, a]` (origin, Euler parameters, modal coordinates) and 6 + m
//! velocities `v = [Ṙ, ω̄, ȧ]` (global origin velocity, body-frame angular velocity, modal rates), related
//! by (Haug 1989; formulation.md §1)
//!
//! ```text
//! Ṙ = Ṙ,      ṗ = ½ Gᵀ(p) ω̄,      ȧ = ȧ
//! ```
//! with `G(p) = [−e, −ẽ + e0 I]`. The same map takes a velocity-space increment `δv` to the position
//! increment `δq = T(q) δv` to first order.

use crate::math::euler_parameters::g_matrix;
use crate::math::{Vec3, Vec4};
use crate::model::Model;

/// `ṗ = ½ Gᵀ(p) ω̄`: the rate of the Euler parameters `p` of a body turning at the body-frame angular
/// velocity `ω̄`.
#[inline]
pub(crate) fn euler_parameter_rates(p: &Vec4, w_bar: &Vec3) -> Vec4 {
    0.5 * g_matrix(p).transpose() * w_bar
}

/// `q̇ = T(q) v` of every body: `Ṙ`, `ṗ = ½ Gᵀ(p) ω̄`, `ȧ` (length `nq`).
pub(crate) fn position_rates(model: &Model, q: &[f64], v: &[f64], qdot: &mut [f64]) {
    let l = &model.layout;
    for b in 0..model.bodies.len() {
        let (qo, vo, m) = (l.q_offset[b], l.v_offset[b], l.modes[b]);
        qdot[qo..qo + 3].copy_from_slice(&v[vo..vo + 3]);
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        let w_bar = Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
        qdot[qo + 3..qo + 7].copy_from_slice(euler_parameter_rates(&p, &w_bar).as_slice());
        qdot[qo + 7..qo + 7 + m].copy_from_slice(&v[vo + 6..vo + 6 + m]);
    }
}

/// Rescales every body's Euler parameters in the positions `q` to unit norm, `p ← p / |p|`, telling
/// `moved(k, δ)` the change `δ` of each position `q[k]` it rescales; returns the largest `|pᵀp − 1|` it
/// found.
pub(crate) fn normalize_euler_parameters(model: &Model, q: &mut [f64], mut moved: impl FnMut(usize, f64)) -> f64 {
    let mut worst = 0.0_f64;
    for b in 0..model.bodies.len() {
        let qo = model.layout.q_offset[b];
        let norm_squared: f64 = (3..7).map(|k| q[qo + k].powi(2)).sum();
        worst = worst.max((norm_squared - 1.0).abs());
        let norm = norm_squared.sqrt();
        for k in qo + 3..qo + 7 {
            let unit = q[k] / norm;
            moved(k, unit - q[k]);
            q[k] = unit;
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::euler_parameters::rotation_matrix;
    use crate::math::{skew, Mat3};

    fn turned() -> Vec4 {
        let p = Vec4::new(0.8, 0.3, -0.4, 0.2);
        p / p.norm()
    }

    /// `Aᵀ Ȧ = ω̄̃` (Haug 1989): the rate `ṗ` turns the frame at `ω̄` in body axes. `Ȧ` by
    /// central differences of `A(p + s ṗ)`.
    #[test]
    fn euler_parameter_rates_turn_the_frame_at_the_body_frame_angular_velocity() {
        let (p, w_bar) = (turned(), Vec3::new(1.3, -0.7, 2.1));
        let p_rate = euler_parameter_rates(&p, &w_bar);
        let s = 1e-6;
        let a_rate: Mat3 = (rotation_matrix(&(p + s * p_rate)) - rotation_matrix(&(p - s * p_rate))) / (2.0 * s);
        let spin = rotation_matrix(&p).transpose() * a_rate;
        assert!((spin - skew(&w_bar)).norm() < 1e-8, "{spin} against {}", skew(&w_bar));
        assert!(p.dot(&p_rate).abs() < 1e-15, "the rate keeps |p| = 1");
    }

    #[test]
    fn position_rates_are_the_velocities_and_the_euler_parameter_rates() {
        let model = crate::analysis::test_models::double_pendulum_with_spring();
        let l = &model.layout;
        let mut q = vec![0.0; l.nq];
        for b in 0..model.bodies.len() {
            q[l.q_offset[b] + 3..l.q_offset[b] + 7].copy_from_slice(turned().as_slice());
        }
        let v: Vec<f64> = (0..l.nv).map(|k| 0.1 + 0.37 * k as f64).collect();
        let mut qdot = vec![f64::NAN; l.nq];
        position_rates(&model, &q, &v, &mut qdot);
        for b in 0..model.bodies.len() {
            let (qo, vo) = (l.q_offset[b], l.v_offset[b]);
            assert_eq!(qdot[qo..qo + 3], v[vo..vo + 3]);
            let p_rate = euler_parameter_rates(&turned(), &Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]));
            assert_eq!(qdot[qo + 3..qo + 7], *p_rate.as_slice());
        }
    }

    #[test]
    fn normalized_euler_parameters_are_unit_along_the_same_rotation() {
        let model = crate::analysis::test_models::double_pendulum_with_spring();
        let l = &model.layout;
        let mut q: Vec<f64> = (0..l.nq).map(|k| 0.2 + 0.1 * k as f64).collect();
        let before = q.clone();
        let mut change = vec![0.0; l.nq];
        let worst = normalize_euler_parameters(&model, &mut q, |k, d| change[k] += d);
        let mut expected_worst = 0.0_f64;
        for b in 0..model.bodies.len() {
            let r = l.q_offset[b] + 3..l.q_offset[b] + 7;
            let (old, new) = (Vec4::from_column_slice(&before[r.clone()]), Vec4::from_column_slice(&q[r.clone()]));
            expected_worst = expected_worst.max((old.norm_squared() - 1.0).abs());
            assert!((new.norm() - 1.0).abs() < 1e-15);
            assert!((rotation_matrix(&new) - rotation_matrix(&(old / old.norm()))).norm() < 1e-15, "same rotation");
            for k in r {
                assert!((before[k] + change[k] - q[k]).abs() < 1e-15, "the changes told are those made");
            }
        }
        assert!((worst - expected_worst).abs() <= 1e-14 * expected_worst, "{worst} against {expected_worst}");
        for b in 0..model.bodies.len() {
            let (qo, m) = (l.q_offset[b], l.modes[b]);
            assert_eq!(q[qo..qo + 3], before[qo..qo + 3], "origins untouched");
            assert_eq!(q[qo + 7..qo + 7 + m], before[qo + 7..qo + 7 + m], "modal coordinates untouched");
        }
    }
}
