//! Constraint stage: every joint row's `Φ`, `Φ_t`, Jacobian coefficients and acceleration bias, and the
//! products with the velocity Jacobian `B = Φ_q T` (columns `[Ṙ, ω̄, ȧ]` of each body; the modal
//! columns of a marker at a node of a flexible body are `Ψᵀ Aᵀ c_r + Θᵀ Jᵀ Aᵀ c_θ`).

use crate::data::Data;
use crate::joint::EquationTerms;
use crate::math::Vec6;
use crate::model::{BodyId, Model};
use crate::stage::{modal_row, MarkerState};

/// Fills `data.equations` at time `t` (after the kinematics stage).
pub(crate) fn constraint_equations(model: &Model, data: &mut Data, t: f64) {
    for (j, joint) in model.joints.iter().enumerate() {
        let law = joint.kind.time_function().map_or([0.0; 3], |f| f.eval(t));
        let mi = &data.markers[joint.marker_i.0];
        let mj = &data.markers[joint.marker_j.0];
        for row in model.layout.joint_rows[j].clone() {
            let eq = model.layout.equations[row].1;
            data.equations[row] = eq.evaluate(mi, mj, law, data.angle_reference[j]);
        }
    }
}

/// Row `B_k,b` of the velocity Jacobian for the body of marker `m`: `J_rᵀ c_r + J_θᵀ c_θ`.
#[inline]
fn body_row(m: &MarkerState, d_point: &crate::math::Vec3, d_rot: &crate::math::Vec3) -> Vec6 {
    m.jac_point.transpose() * d_point + m.jac_rotation.transpose() * d_rot
}

/// The two sides of a constraint row: (body, row of `B` for that body).
#[inline]
pub(crate) fn row_sides(model: &Model, data: &Data, row: usize) -> [Option<(BodyId, Vec6)>; 2] {
    let (j, _) = model.layout.equations[row];
    let joint = &model.joints[j.0];
    let terms: &EquationTerms = &data.equations[row];
    let mi = &data.markers[joint.marker_i.0];
    let mj = &data.markers[joint.marker_j.0];
    [
        mi.body.map(|b| (b, body_row(mi, &terms.d_point_i, &terms.d_rot_i))),
        mj.body.map(|b| (b, body_row(mj, &terms.d_point_j, &terms.d_rot_j))),
    ]
}

/// Calls `f(v_column, value)` for the modal entries of constraint row `row` (markers at nodes).
#[inline]
fn modal_entries(model: &Model, data: &Data, row: usize, mut f: impl FnMut(usize, f64)) {
    let (j, _) = model.layout.equations[row];
    let joint = &model.joints[j.0];
    let terms = &data.equations[row];
    for (marker, d_point, d_rot) in [
        (joint.marker_i, &terms.d_point_i, &terms.d_rot_i),
        (joint.marker_j, &terms.d_point_j, &terms.d_rot_j),
    ] {
        let m = &data.markers[marker.0];
        if let (Some(_), Some(b)) = (m.node, m.body) {
            let o = model.layout.v_offset[b.0] + 6;
            modal_row(model, m, d_point, d_rot, |k, x| f(o + k, x));
        }
    }
}

/// `out += Bᵀ w` for a vector `w` over constraint rows.
pub(crate) fn add_jacobian_transpose(model: &Model, data: &Data, w: &[f64], out: &mut [f64]) {
    for (row, &wk) in w.iter().enumerate() {
        if wk == 0.0 {
            continue;
        }
        for (b, r) in row_sides(model, data, row).into_iter().flatten() {
            let o = model.layout.v_offset[b.0];
            for k in 0..6 {
                out[o + k] += wk * r[k];
            }
        }
        modal_entries(model, data, row, |c, x| out[c] += wk * x);
    }
}

/// Calls `f(row, v_column, value)` for every entry of `B`. Callers add the values rather than set them,
/// so that the function stays correct should two sides of a row ever share a body.
pub(crate) fn jacobian_entries(model: &Model, data: &Data, mut f: impl FnMut(usize, usize, f64)) {
    for row in 0..model.layout.nc {
        for (b, r) in row_sides(model, data, row).into_iter().flatten() {
            let o = model.layout.v_offset[b.0];
            for k in 0..6 {
                f(row, o + k, r[k]);
            }
        }
        modal_entries(model, data, row, |c, x| f(row, c, x));
    }
}
