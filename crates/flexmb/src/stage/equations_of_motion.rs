//! The equations of motion in residual form, the function the linearization differentiates and the
//! generalized-α step solves: `g = [M v̇ + h(q, v) − Q(q, v, t) + Bᵀλ; B v + Φ_t]`, the
//! Lagrange-multiplier equations of motion (Haug 1989) with the constraints at velocity level. `Bᵀλ`
//! includes the geometric stiffening of the joints' reactions at interface nodes (`stage::geometric_stiffening`).

use super::geometric_stiffening::add_interface_reactions;
use super::{add_jacobian_transpose, run_forward};
use crate::data::Data;
use crate::model::Model;

/// `g = [M v̇ + h(q, v) − Q(q, v, t) + Bᵀλ; B v + Φ_t]` into `g` (length `nv + nc`; the rows of the
/// constraints switched off in `active` are zero), leaving every stage evaluated at `(t, q, v)` in
/// `data`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn equations_of_motion(
    model: &Model,
    data: &mut Data,
    active: &[bool],
    t: f64,
    q: &[f64],
    v: &[f64],
    vdot: &[f64],
    lambda: &[f64],
    g: &mut [f64],
) {
    let nv = model.layout.nv;
    run_forward(model, data, t, q, v, vdot);
    for k in 0..nv {
        g[k] = data.inertia[k] - data.applied[k];
    }
    add_jacobian_transpose(model, data, lambda, &mut g[..nv]);
    add_interface_reactions(model, data, lambda, &mut g[..nv]);
    for (row, terms) in data.equations.iter().enumerate() {
        let (j, _) = model.layout.equations[row];
        let joint = &model.joints[j.0];
        let (mi, mj) = (&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]);
        g[nv + row] = if active[row] { terms.rate(mi, mj) } else { 0.0 };
    }
}
