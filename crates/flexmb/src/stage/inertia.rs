//! Inertia stage: `M(q) v̇ + h(q, v)` per body, in velocities `[Ṙ (global), ω̄ (body), ȧ]`
//! (formulation.md §4). A rigid body:
//!
//! ```text
//! m R̈ − A S̄̃ ω̄̇ + A ω̄̃ ω̄̃ S̄        (translation, global)
//! S̄̃ Aᵀ R̈ + J̄ ω̄̇ + ω̄̃ J̄ ω̄          (rotation, body frame)
//! ```
//! with `S̄ = m c̄` the first moment and `J̄` the inertia about the body-frame origin. A flexible body
//! adds the modal rows and couplings, all from the invariants at the current `a` (no term dropped):
//!
//! ```text
//! m R̈ − A S̃ ω̄̇ + A C2 ä + A (ω̄̃ ω̄̃ S + 2 ω̄̃ C2 ȧ)
//! S̃ Aᵀ R̈ + J̄ ω̄̇ + Cₚ ä + ω̄̃ J̄ ω̄ − 2 Σⱼ ȧⱼ (C4(j) + Eⱼᵀ) ω̄ + ω̄̃ (Σ Jᵢ Θᵢ) ȧ
//! C2ᵀ Aᵀ R̈ + Cₚᵀ ω̄̇ + M_aa ä + [ω̄ᵀ (C4(j)ᵀ + Eⱼ) ω̄]ⱼ + [2 Σₖ ȧₖ ω̄ᵀ C7(k)[:, j]]ⱼ
//! ```
//! with `S = C1 + C2 a`, `Eⱼ = Σₖ aₖ C5(j,k)`, `Cₚ = C6 + Σₖ C7(k) aₖ + Σ Jᵢ Θᵢ`, `M_aa = C9 + Σ Θᵢᵀ Jᵢ Θᵢ`
//! (the last terms are the nodes' own rotary inertia, zero unless the FE model lumps it).

use super::geometric_stiffening::{add_geometric_stiffening, geometric_stiffening_entries};
use crate::data::Data;
use crate::math::{skew, Mat3, Vec3};
use crate::model::Model;

/// Calls `f(r, c, value)` for every entry of body `b`'s mass matrix at its current state (`r`, `c`
/// local to the body's velocity coordinates, `0..6 + m`).
pub(crate) fn body_mass_entries(model: &Model, data: &Data, b: usize, mut f: impl FnMut(usize, usize, f64)) {
    let body = &model.bodies[b];
    let a = data.bodies[b].rotation;
    let (first_moment, inertia) = match &model.modal[b] {
        Some(_) => (data.modal[b].first_moment, data.modal[b].inertia),
        None => (body.first_moment(), body.inertia_about_origin()),
    };
    let coupling = -a * skew(&first_moment); // rows: translation, cols: ω̄
    for r in 0..3 {
        f(r, r, body.mass);
        for c in 0..3 {
            f(r, 3 + c, coupling[(r, c)]);
            f(3 + c, r, coupling[(r, c)]);
            f(3 + r, 3 + c, inertia[(r, c)]);
        }
    }
    let Some(modal) = &model.modal[b] else { return };
    let state = &data.modal[b];
    let inv = &modal.invariants;
    let m = modal.modes();
    for j in 0..m {
        let a_c2: Vec3 = a * Vec3::new(inv.c2[(0, j)], inv.c2[(1, j)], inv.c2[(2, j)]);
        for r in 0..3 {
            f(r, 6 + j, a_c2[r]);
            f(6 + j, r, a_c2[r]);
            f(3 + r, 6 + j, state.coupling[(r, j)]);
            f(6 + j, 3 + r, state.coupling[(r, j)]);
        }
        for k in 0..m {
            f(6 + j, 6 + k, inv.c9[(j, k)] + inv.rotary_modal_mass[(j, k)]);
        }
    }
}

/// Calls `f(r, c, value)` for every entry of `∂(inertia forces)/∂v̇` of body `b`: its mass matrix
/// ([`body_mass_entries`]), the gauge inertia of a massless spin no joint holds (the module
/// `analysis::massless_motions`) and, for a body with geometric stiffening, the derivative of `K_G a`
/// in the accelerations. The matrix of the acceleration solve, the Newton iterations and the
/// linearization; the kinetic energy and the momenta use the mass matrix alone.
pub(crate) fn inertia_jacobian_entries(model: &Model, data: &Data, b: usize, mut f: impl FnMut(usize, usize, f64)) {
    body_mass_entries(model, data, b, &mut f);
    let gauge = &model.massless_gauges[b];
    if gauge.amax() > 0.0 {
        for r in 0..3 {
            for c in 0..3 {
                f(3 + r, 3 + c, gauge[(r, c)]);
            }
        }
    }
    geometric_stiffening_entries(model, data, b, f);
}

/// Fills `data.inertia` with `M v̇ + h(q, v)` (after the kinematics stage), and the geometric
/// stiffening `K_G a` of flexible bodies that have it.
pub(crate) fn inertia_forces(model: &Model, data: &mut Data, vdot: &[f64]) {
    for (b, body) in model.bodies.iter().enumerate() {
        let o = model.layout.v_offset[b];
        let state = &data.bodies[b];
        let a = state.rotation;
        let w = state.omega_bar;
        let rdd = Vec3::new(vdot[o], vdot[o + 1], vdot[o + 2]);
        let wd = Vec3::new(vdot[o + 3], vdot[o + 4], vdot[o + 5]);
        let Some(modal) = &model.modal[b] else {
            let s = body.first_moment();
            let j = body.inertia_about_origin();
            let trans = body.mass * rdd - a * s.cross(&wd) + a * w.cross(&w.cross(&s));
            let rot = s.cross(&(a.transpose() * rdd)) + j * wd + w.cross(&(j * w));
            for k in 0..3 {
                data.inertia[o + k] = trans[k];
                data.inertia[o + 3 + k] = rot[k];
            }
            continue;
        };
        let ms = &data.modal[b];
        let inv = &modal.invariants;
        let m = modal.modes();
        let add = &vdot[o + 6..o + 6 + m];
        let (s, j) = (ms.first_moment, ms.inertia);
        let mut c2_add = Vec3::zeros();
        let mut c2_ad = Vec3::zeros();
        let mut cp_add = Vec3::zeros();
        let mut rotary_ad = Vec3::zeros();
        let mut gyro = Mat3::zeros();
        for k in 0..m {
            let c2k = Vec3::new(inv.c2[(0, k)], inv.c2[(1, k)], inv.c2[(2, k)]);
            c2_add += c2k * add[k];
            c2_ad += c2k * ms.a_dot[k];
            cp_add += Vec3::new(ms.coupling[(0, k)], ms.coupling[(1, k)], ms.coupling[(2, k)]) * add[k];
            rotary_ad += Vec3::new(inv.rotary_coupling[(0, k)], inv.rotary_coupling[(1, k)], inv.rotary_coupling[(2, k)])
                * ms.a_dot[k];
            gyro += (inv.c4[k] + ms.c5a[k].transpose()) * ms.a_dot[k];
        }
        let trans = body.mass * rdd - a * s.cross(&wd) + a * c2_add + a * (w.cross(&w.cross(&s)) + 2.0 * w.cross(&c2_ad));
        // The gauge of a massless spin (zero for most bodies) holds the frame's spin acceleration about it.
        let gauge = model.massless_gauges[b] * wd;
        let rot = s.cross(&(a.transpose() * rdd)) + j * wd + gauge + cp_add + w.cross(&(j * w)) - 2.0 * gyro * w + w.cross(&rotary_ad);
        for k in 0..3 {
            data.inertia[o + k] = trans[k];
            data.inertia[o + 3 + k] = rot[k];
        }
        let r_local = a.transpose() * rdd;
        for p in 0..m {
            let c2p = Vec3::new(inv.c2[(0, p)], inv.c2[(1, p)], inv.c2[(2, p)]);
            let cpp = Vec3::new(ms.coupling[(0, p)], ms.coupling[(1, p)], ms.coupling[(2, p)]);
            let mut row = c2p.dot(&r_local) + cpp.dot(&wd);
            for k in 0..m {
                row += (inv.c9[(p, k)] + inv.rotary_modal_mass[(p, k)]) * add[k];
                let c7kp = Vec3::new(inv.c7[k][(0, p)], inv.c7[k][(1, p)], inv.c7[k][(2, p)]);
                row += 2.0 * ms.a_dot[k] * w.dot(&c7kp);
            }
            row += w.dot(&((inv.c4[p].transpose() + ms.c5a[p]) * w));
            data.inertia[o + 6 + p] = row;
        }
        add_geometric_stiffening(model, data, b, vdot);
    }
}
