//! The joints must hold every motion of a flexible body that carries no mass
//! ([`ModalBody::massless_motions`](crate::body::ModalBody::massless_motions): a straight beam
//! without rotary inertia spinning about its own axis). The accelerations solve
//! `[M Bᵀ; B 0] [v̇; λ] = [Q − h; γ]` (Haug 1989, eq. 11.1.19), which is regular when `M` is positive
//! semi-definite and `B n ≠ 0` for every `n` with `M n = 0` (the null spaces of `M` and `B` meet only
//! at zero); the BDF's and the generalized-α method's iteration matrices have the same structure, and
//! no solve of the engine inverts `M` alone. The massless motions are found at `a = 0` and held by the
//! constraints in force at the assembled configuration; one that nothing holds is an error naming the
//! body and the motion.

use nalgebra::{DMatrix, DVector, Vector4};

use super::{AssemblyError, State};
use crate::data::Data;
use crate::math::rotation_matrix;
use crate::model::Model;
use crate::stage::{jacobian_entries, run_kinematic_stages};

/// `|B n|` below this share of the largest entry of `B` on the body's columns: `B` does not hold `n`.
const NOT_HELD: f64 = 1e-8;

/// Checks, at the assembled `state`, that its constraint rows in force hold every massless motion of
/// every flexible body (the kinematic stages are run at the state once a body has such motions).
pub(crate) fn check_massless_motions_held(model: &Model, data: &mut Data, state: &State) -> Result<(), AssemblyError> {
    let (nc, q, active) = (model.layout.nc, &state.q, &state.active);
    let mut staged = false;
    for (b, modal) in model.modal.iter().enumerate() {
        let Some(modal) = modal else { continue };
        let motions = modal.massless_motions();
        if motions.is_empty() {
            continue;
        }
        if !staged {
            run_kinematic_stages(model, data, state.t, q, &state.v);
            staged = true;
        }
        let data = &*data;
        let span = model.layout.v_span(b);
        let qo = model.layout.q_offset[b];
        let a = rotation_matrix(&Vector4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]));
        // The body's columns of B, in force.
        let mut jacobian = DMatrix::<f64>::zeros(nc, span.len());
        jacobian_entries(model, data, |r, c, x| {
            if active[r] && span.contains(&c) {
                jacobian[(r, c - span.start)] += x;
            }
        });
        let largest = jacobian.amax();
        // The motions in the velocity coordinates: Ṙ is global, ω̄ and ȧ are in body axes.
        let columns: Vec<DVector<f64>> = motions
            .iter()
            .map(|m| {
                let mut v = m.velocity.clone();
                let global = a * v.fixed_rows::<3>(0);
                v.fixed_rows_mut::<3>(0).copy_from(&global);
                &jacobian * v
            })
            .collect();
        // Held together: B N has full column rank (each direction alone, and no combination, escapes).
        let held = DMatrix::from_columns(&columns);
        let smallest = if nc < motions.len() { 0.0 } else { held.singular_values().min() };
        // NaN holds nothing.
        let holds = |size: f64| size > NOT_HELD * largest;
        if !holds(smallest) {
            let unheld = columns.iter().position(|c| !holds(c.norm())).unwrap_or(0);
            return Err(AssemblyError::MasslessMotion {
                body: model.bodies[b].name.clone(),
                motion: motions[unheld].describe(),
            });
        }
    }
    Ok(())
}
