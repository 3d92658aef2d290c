//! The derivatives of the DAE residual ([`residual`](super::residual)) with respect to the multipliers
//! `λ` and `μ`, analytic: the residual is linear in them, so its derivatives are the constraint Jacobian
//! `B` (from the joints' primitives, [`jacobian_entries`]) placed where the multipliers act, independent
//! of the multipliers themselves.
//!
//! ```text
//! ∂(M v̇ + h − Q + Bᵀλ)/∂λ = Bᵀ (+ the joints' interface stiffening)  (dynamic rows)
//! ∂(q̇ − T(q) v − Φ̂_qᵀ μ)/∂μ_k = −[B_k,R; 2 Gᵀ(p) B_k,ω̄; B_k,a]   (kinematic rows: Ṙ, ṗ, ȧ)
//! ∂(q̇ − …)/∂μ_norm,b = −2 p_b                                    (normalization of body b)
//! ∂λ_k/∂λ_k = ∂μ_k/∂μ_k = 1                                       (rows switched off)
//! ```
//! The velocity and position constraint rows themselves do not depend on the multipliers.

use crate::data::Data;
use crate::math::euler_parameters::g_matrix;
use crate::math::Vec4;
use crate::model::Model;
use crate::stage::geometric_stiffening::interface_reaction_entries;
use crate::stage::{jacobian_entries, YLayout};

/// Calls `f(row, column, value)` (indices into `y = [q, v, λ, μ]` of `yl`) for every entry of the
/// residual's derivative with respect to `λ` and `μ`, at the state whose kinematic stages `data` holds
/// (positions `q`), with the constraint rows in force `active`. Each `(row, column)` may come more than
/// once: callers add the values.
pub(crate) fn multiplier_jacobian_entries(
    model: &Model,
    data: &Data,
    yl: &YLayout,
    q: &[f64],
    active: &[bool],
    mut f: impl FnMut(usize, usize, f64),
) {
    let l = &model.layout;
    for (row, &on) in active.iter().enumerate().take(l.nc) {
        if !on {
            f(yl.lambda.start + row, yl.lambda.start + row, 1.0);
            f(yl.mu.start + row, yl.mu.start + row, 1.0);
        }
    }
    jacobian_entries(model, data, |row, c, x| {
        let (lambda, mu) = (yl.lambda.start + row, yl.mu.start + row);
        f(yl.v.start + c, lambda, x);
        let b = l.v_offset.partition_point(|&o| o <= c) - 1;
        let (qo, local) = (yl.q.start + l.q_offset[b], c - l.v_offset[b]);
        match local {
            0..=2 => f(qo + local, mu, -x),
            3..=5 => {
                let g = g_matrix(&euler_parameters(q, l.q_offset[b]));
                for i in 0..4 {
                    f(qo + 3 + i, mu, -2.0 * g[(local - 3, i)] * x);
                }
            }
            _ => f(qo + local + 1, mu, -x),
        }
    });
    interface_reaction_entries(model, data, |row, c, x| f(yl.v.start + c, yl.lambda.start + row, x));
    for b in 0..model.bodies.len() {
        let p = euler_parameters(q, l.q_offset[b]);
        let column = yl.mu.start + l.nc + b;
        for i in 0..4 {
            f(yl.q.start + l.q_offset[b] + 3 + i, column, -2.0 * p[i]);
        }
    }
}

/// The Euler parameters of the body whose positions start at `offset`.
fn euler_parameters(q: &[f64], offset: usize) -> Vec4 {
    Vec4::new(q[offset + 3], q[offset + 4], q[offset + 5], q[offset + 6])
}
