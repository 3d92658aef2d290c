//! The residual `F(t, y, ẏ)` of the stabilized index-2 equations of motion (Gear–Gupta–Leimkuhler),
//! with `y = [q, v, λ, μ]`:
//!
//! ```text
//! F_q = q̇ − T(q) v − Φ̂_qᵀ μ           T(q) v = [Ṙ; ½ Gᵀ ω̄; ȧ]       (kinematic, 7 + m per body)
//! F_v = M(q) v̇ + h(q, v) − Q + Bᵀ λ                                  (dynamic, 6 + m per body)
//! F_λ = B v + Φ_t                                                     (velocity constraints)
//! F_μ = [Φ(q, t); pᵀp − 1]                                            (position constraints)
//! ```
//!
//! `B = Φ_q T` is the Jacobian in velocities `[Ṙ, ω̄]`, `Φ̂ = [Φ; pᵀp − 1]`, and `Φ̂_q` its Jacobian in
//! positions: `Φ_p = B_ω̄ 2G(p)`, `(pᵀp)_p = 2pᵀ`. At a solution `μ = 0`; its role is to let `q` satisfy the
//! position constraints and `pᵀp = 1` while `v` satisfies the velocity constraints, so neither drifts.

use std::ops::Range;

use crate::data::Data;
use crate::math::euler_parameters::g_matrix;
use crate::math::{Vec3, Vec4};
use crate::model::Model;
use crate::stage::geometric_stiffening::add_interface_reactions;
use crate::stage::{add_jacobian_transpose, euler_parameter_rates, run_forward};

/// Ranges of the blocks of `y = [q, v, λ, μ]` (and of the matching residual rows).
#[derive(Clone, Debug)]
pub(crate) struct YLayout {
    pub q: Range<usize>,
    pub v: Range<usize>,
    pub lambda: Range<usize>,
    pub mu: Range<usize>,
}

impl YLayout {
    pub fn new(model: &Model) -> Self {
        let l = &model.layout;
        let (nq, nv, nc) = (l.nq, l.nv, l.nc);
        let mu_len = l.n_position_constraints();
        Self { q: 0..nq, v: nq..nq + nv, lambda: nq + nv..nq + nv + nc, mu: nq + nv + nc..nq + nv + nc + mu_len }
    }
    pub fn len(&self) -> usize {
        self.mu.end
    }
    /// Rows with a derivative (`q`, `v`); the rest are algebraic.
    pub fn n_differential(&self) -> usize {
        self.v.end
    }
}

/// Evaluates all stages at `(t, y, ẏ)` and writes `F` into `res`.
/// `active[k] == false` switches constraint row `k` off: its rows become `λ_k = 0`, `μ_k = 0`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn residual(
    model: &Model,
    data: &mut Data,
    yl: &YLayout,
    active: &[bool],
    t: f64,
    y: &[f64],
    yp: &[f64],
    res: &mut [f64],
) {
    let (q, v) = (&y[yl.q.clone()], &y[yl.v.clone()]);
    let (lambda, mu) = (&y[yl.lambda.clone()], &y[yl.mu.clone()]);
    let nc = model.layout.nc;
    run_forward(model, data, t, q, v, &yp[yl.v.clone()]);

    // Dynamic rows.
    let mut bt = std::mem::take(&mut data.scratch_v);
    bt.fill(0.0);
    add_jacobian_transpose(model, data, lambda, &mut bt);
    add_interface_reactions(model, data, lambda, &mut bt);
    let res_v = &mut res[yl.v.clone()];
    for k in 0..res_v.len() {
        res_v[k] = data.inertia[k] - data.applied[k] + bt[k];
    }

    // Kinematic rows.
    bt.fill(0.0);
    add_jacobian_transpose(model, data, &mu[..nc], &mut bt);
    for b in 0..model.bodies.len() {
        let qo = model.layout.q_offset[b];
        let vo = model.layout.v_offset[b];
        let qp = &yp[yl.q.clone()];
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        let g = g_matrix(&p);
        let w_bar = Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
        let mu_r = Vec3::new(bt[vo], bt[vo + 1], bt[vo + 2]);
        let mu_w = Vec3::new(bt[vo + 3], bt[vo + 4], bt[vo + 5]);
        let mu_norm = mu[nc + b];
        let p_rate = euler_parameter_rates(&p, &w_bar) + 2.0 * g.transpose() * mu_w + 2.0 * mu_norm * p;
        for k in 0..3 {
            res[qo + k] = qp[qo + k] - v[vo + k] - mu_r[k];
        }
        for k in 0..4 {
            res[qo + 3 + k] = qp[qo + 3 + k] - p_rate[k];
        }
        // Modal coordinates: ȧ = v_a, with Φ_a = B_a (T is the identity there).
        for k in 0..model.layout.modes[b] {
            res[qo + 7 + k] = qp[qo + 7 + k] - v[vo + 6 + k] - bt[vo + 6 + k];
        }
    }

    data.scratch_v = bt;

    // Velocity and position constraints.
    for (row, terms) in data.equations.iter().enumerate() {
        let (j, _) = model.layout.equations[row];
        let joint = &model.joints[j.0];
        let (mi, mj) = (&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]);
        if active[row] {
            res[yl.lambda.start + row] = terms.rate(mi, mj);
            res[yl.mu.start + row] = terms.phi;
        } else {
            res[yl.lambda.start + row] = lambda[row];
            res[yl.mu.start + row] = mu[row];
        }
    }
    for b in 0..model.bodies.len() {
        let qo = model.layout.q_offset[b];
        let pp: f64 = (3..7).map(|k| q[qo + k] * q[qo + k]).sum();
        res[yl.mu.start + nc + b] = pp - 1.0;
    }
}
