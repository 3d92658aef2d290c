//! The weighted norms of the integrators' error estimates and Newton increments: each component `x`
//! of a quantity whose value is `y` weighed by its error weight `atol + rtol |y|`, and the root mean
//! square of the weighted components, so that a norm of 1 is "at the tolerance" whatever the size of
//! the system (Hairer, Nørsett and Wanner, *Solving Ordinary Differential Equations I*, II.4).
//!
//! Positions are weighed in the coordinates `q = [R, p, a]` even when an increment is given in the
//! velocity coordinates `[Ṙ, ω̄, ȧ]` (the generalized-α method's steps, the Adams method's projections):
//! it is first mapped by `δq = T(q) δv`, so that every method measures a rotation alike.

use crate::model::Layout;
use crate::stage::euler_parameter_rates;
use crate::math::{Vec3, Vec4};

/// The error weight `atol + rtol |y|` of a component whose value is `y`.
#[inline]
pub(crate) fn error_weight(atol: f64, rtol: f64, y: f64) -> f64 {
    atol + rtol * y.abs()
}

/// `√(s / n)`: the root mean square of `n` weighted components whose squares sum to `s` (`√s` for
/// `n = 0`).
#[inline]
pub(crate) fn root_mean_square(sum_of_squares: f64, n: usize) -> f64 {
    (sum_of_squares / n.max(1) as f64).sqrt()
}

/// The weighted RMS norm `√(Σ (xᵢ / wᵢ)² / n)` of the components `(xᵢ, wᵢ)`, `wᵢ` their error weights.
pub(crate) fn weighted_rms_norm(components: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    let (sum, n) = components.into_iter().fold((0.0, 0), |(sum, n), (x, w)| (sum + (x / w).powi(2), n + 1));
    root_mean_square(sum, n)
}

/// `Σ (δqᵢ / (atol + rtol |qᵢ|))²` over the position coordinates at `q`, for a position increment `d`
/// given in velocity coordinates: `δR = d_R`, `δp = ½ Gᵀ(p) d_ω̄`, `δa = d_a`.
pub(crate) fn position_sum_of_squares(layout: &Layout, q: &[f64], d: &[f64], atol: f64, rtol: f64) -> f64 {
    let w = |x: f64, q: f64| x / error_weight(atol, rtol, q);
    let mut sum = 0.0;
    for b in 0..layout.n_bodies() {
        let (qo, vo, m) = (layout.q_offset[b], layout.v_offset[b], layout.modes[b]);
        for k in 0..3 {
            sum += w(d[vo + k], q[qo + k]).powi(2);
        }
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        let dp = euler_parameter_rates(&p, &Vec3::new(d[vo + 3], d[vo + 4], d[vo + 5]));
        for k in 0..4 {
            sum += w(dp[k], p[k]).powi(2);
        }
        for k in 0..m {
            sum += w(d[vo + 6 + k], q[qo + 7 + k]).powi(2);
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every component exactly at its tolerance has norm 1 whatever the size of the system; the norm is
    /// homogeneous in the components.
    #[test]
    fn components_at_their_tolerance_have_norm_one() {
        let (atol, rtol) = (1e-6, 1e-3);
        for n in [1, 7, 100] {
            let y: Vec<f64> = (0..n).map(|k| (k as f64 - 3.0) * 2.5).collect();
            let at_tolerance = y.iter().map(|&y| (error_weight(atol, rtol, y), error_weight(atol, rtol, y)));
            assert!((weighted_rms_norm(at_tolerance) - 1.0).abs() < 1e-15);
            let scaled = y.iter().map(|&y| (-3.0 * error_weight(atol, rtol, y), error_weight(atol, rtol, y)));
            assert!((weighted_rms_norm(scaled) - 3.0).abs() < 1e-14);
        }
        assert_eq!(weighted_rms_norm(std::iter::empty()), 0.0);
    }

    /// A velocity-space increment weighs what it moves the positions by: a turn `δθ̄` of a body moves its
    /// Euler parameters by `½ Gᵀ δθ̄`, whose length is `|δθ̄|/2`; the increment of a translation is itself.
    #[test]
    fn a_position_increment_is_weighed_in_the_positions_it_moves() {
        let model = crate::analysis::test_models::double_pendulum_with_spring();
        let l = &model.layout;
        let mut q = vec![0.0; l.nq];
        for b in 0..l.n_bodies() {
            let p = Vec4::new(0.8, 0.3, -0.4, 0.2);
            q[l.q_offset[b] + 3..l.q_offset[b] + 7].copy_from_slice((p / p.norm()).as_slice());
        }
        // Absolute weights only: the sum is then the squared length of δq.
        let (atol, rtol) = (1e-3, 0.0);
        let mut d = vec![0.0; l.nv];
        d[l.v_offset[1] + 3..l.v_offset[1] + 6].copy_from_slice(&[0.3e-3, -0.4e-3, 1.2e-3]);
        let turn = Vec3::new(0.3e-3, -0.4e-3, 1.2e-3).norm();
        let sum = position_sum_of_squares(l, &q, &d, atol, rtol);
        assert!((sum - (0.5 * turn / atol).powi(2)).abs() < 1e-12, "{sum}");
        d.fill(0.0);
        d[l.v_offset[0]] = 2e-3;
        assert!((position_sum_of_squares(l, &q, &d, atol, rtol) - 4.0).abs() < 1e-12);
    }
}
