//! Positions updated in velocity space: each body's position lives on the group `R³ × S³ × Rᵐ`, and a
//! step moves it by an increment `d` in the velocity coordinates `[Ṙ (global), ω̄ (body), ȧ]`
//! (Brüls and Cardona 2010, with unit quaternions for the rotations):
//!
//! ```text
//! R ← R + d_R,      p ← p ⊗ exp(½ d_ω̄),      a ← a + d_a
//! ```
//! so that `A(p) ← A(p) exp(d̃_ω̄)`: the body frame turned by the body-frame rotation vector `d_ω̄`. The
//! result is exactly unit (it is renormalized against round-off).

use crate::math::{skew, Mat3, Vec3, Vec4};
use crate::model::Layout;

/// Hamilton product `p ⊗ r`, so that `A(p ⊗ r) = A(p) A(r)`.
#[inline]
pub(crate) fn quaternion_product(p: &Vec4, r: &Vec4) -> Vec4 {
    let (p0, pv) = (p[0], Vec3::new(p[1], p[2], p[3]));
    let (r0, rv) = (r[0], Vec3::new(r[1], r[2], r[3]));
    let v = p0 * rv + r0 * pv + pv.cross(&rv);
    Vec4::new(p0 * r0 - pv.dot(&rv), v.x, v.y, v.z)
}

/// `exp(½ θ̄)`: the unit quaternion of the rotation by the vector `θ̄` (angle `|θ̄|` about `θ̄`).
#[inline]
pub(crate) fn rotation_quaternion(theta: &Vec3) -> Vec4 {
    let angle = theta.norm();
    let (s, c) = (0.5 * angle).sin_cos();
    // sin(|θ|/2)/|θ| → ½ as |θ| → 0 (the next term, −|θ|²/48, is below round-off there).
    let k = if angle < 1e-8 { 0.5 } else { s / angle };
    Vec4::new(c, k * theta.x, k * theta.y, k * theta.z)
}

/// `out = q ∘ exp(d)`: every body moved by the velocity-space increment `d` (length `nv`).
pub(crate) fn retract(layout: &Layout, q: &[f64], d: &[f64], out: &mut [f64]) {
    for b in 0..layout.n_bodies() {
        let (qo, vo, m) = (layout.q_offset[b], layout.v_offset[b], layout.modes[b]);
        for k in 0..3 {
            out[qo + k] = q[qo + k] + d[vo + k];
        }
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        let turn = rotation_quaternion(&Vec3::new(d[vo + 3], d[vo + 4], d[vo + 5]));
        let p_new = quaternion_product(&p, &turn);
        let p_new = p_new / p_new.norm();
        out[qo + 3..qo + 7].copy_from_slice(p_new.as_slice());
        for k in 0..m {
            out[qo + 7 + k] = q[qo + 7 + k] + d[vo + 6 + k];
        }
    }
}

/// The tangent of the exponential map in the body frame, `J_r(u)`:
/// `exp((u + δ)~) = exp(ũ) exp((J_r(u) δ)~) + O(|δ|²)`, `J_r = I − (1 − cos θ)/θ² ũ + (θ − sin θ)/θ³ ũ²`
/// with `θ = |u|`. A body-frame perturbation of the step increment `d` turns the body by `J_r(d) δ`.
pub(crate) fn right_jacobian(u: &Vec3) -> Mat3 {
    let a = u.norm();
    let (c1, c2) = if a < 1e-4 {
        (0.5 - a * a / 24.0, 1.0 / 6.0 - a * a / 120.0)
    } else {
        ((1.0 - a.cos()) / (a * a), (a - a.sin()) / (a * a * a))
    };
    let ut = skew(u);
    Mat3::identity() - c1 * ut + c2 * ut * ut
}

/// `J_r(u)⁻¹ = I + ½ ũ + (1/θ² − (1 + cos θ)/(2θ sin θ)) ũ²`: the rate of the exponential coordinates `u`
/// of `A(t) = A_n exp(ũ(t))` is `u̇ = J_r(u)⁻¹ ω̄` when the body angular velocity is `ω̄` (for `θ < π`).
pub(crate) fn right_jacobian_inverse(u: &Vec3) -> Mat3 {
    let a = u.norm();
    let c = if a < 1e-4 { 1.0 / 12.0 + a * a / 720.0 } else { 1.0 / (a * a) - (1.0 + a.cos()) / (2.0 * a * a.sin()) };
    let ut = skew(u);
    Mat3::identity() + 0.5 * ut + c * ut * ut
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::euler_parameters::rotation_matrix;
    use crate::test_support::{turn_body_frame, Lcg};

    #[test]
    fn retraction_turns_the_body_frame_and_stays_unit() {
        let mut rng = Lcg(7);
        let layout = Layout::new(&[0, 2], &[]);
        let mut q = vec![0.0; layout.nq];
        for b in 0..2 {
            let qo = layout.q_offset[b];
            q[qo..qo + 3].copy_from_slice(rng.vec3(1.0).as_slice());
            q[qo + 3..qo + 7].copy_from_slice(rng.rotation().0.as_slice());
        }
        let (qa, va) = (layout.q_offset[1] + 7, layout.v_offset[1] + 6);
        q[qa] = 0.3;
        q[qa + 1] = -0.2;
        let d: Vec<f64> = (0..layout.nv).map(|_| rng.range(-0.7, 0.7)).collect();
        let mut out = vec![0.0; layout.nq];
        retract(&layout, &q, &d, &mut out);
        for b in 0..2 {
            let (qo, vo) = (layout.q_offset[b], layout.v_offset[b]);
            let p = Vec4::from_column_slice(&q[qo + 3..qo + 7]);
            let pi_bar = Vec3::from_column_slice(&d[vo + 3..vo + 6]);
            let expected = turn_body_frame(&p, &pi_bar);
            let got = Vec4::from_column_slice(&out[qo + 3..qo + 7]);
            assert!((got - expected).norm() < 1e-15, "{got} vs {expected}");
            assert!((got.norm() - 1.0).abs() < 1e-15);
            // A ← A exp(π̄~), with exp by its series.
            let mut e = crate::math::Mat3::identity();
            let mut term = crate::math::Mat3::identity();
            for n in 1..30 {
                term = term * skew(&pi_bar) / n as f64;
                e += term;
            }
            let a_expected = rotation_matrix(&p) * e;
            assert!((rotation_matrix(&got) - a_expected).abs().max() < 1e-14);
            for k in 0..3 {
                assert_eq!(out[qo + k], q[qo + k] + d[vo + k]);
            }
        }
        assert_eq!(out[qa], 0.3 + d[va]);
        assert_eq!(out[qa + 1], -0.2 + d[va + 1]);
    }

    #[test]
    fn right_jacobian_and_its_inverse_match_finite_differences() {
        let mut rng = Lcg(11);
        for scale in [1e-6, 1e-3, 0.3, 2.5] {
            let u = rng.vec3(scale);
            let jr = right_jacobian(&u);
            assert!(
                (jr * right_jacobian_inverse(&u) - Mat3::identity()).abs().max() < 1e-12,
                "inverse at |u| {}",
                u.norm()
            );
            let p = rotation_quaternion(&u);
            let eps = 1e-7;
            for k in 0..3 {
                let mut du = Vec3::zeros();
                du[k] = eps;
                let (plus, minus) = (rotation_quaternion(&(u + du)), rotation_quaternion(&(u - du)));
                // Body-frame turn from exp(u) to exp(u ± δ): A(p)ᵀ A(p±), its skew part.
                let turn = |q: &Vec4| {
                    let r = rotation_matrix(&p).transpose() * rotation_matrix(q);
                    Vec3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]) * 0.5
                };
                let column = (turn(&plus) - turn(&minus)) / (2.0 * eps);
                let expected = jr.column(k);
                assert!((column - expected).norm() < 1e-7, "column {k} at |u| {}: {column} vs {expected}", u.norm());
            }
        }
    }
}
