//! The motions of a flexible body that carry no mass
//! ([`ModalBody::massless_motions`](crate::body::ModalBody::massless_motions): a straight beam
//! without rotary inertia spinning about its own axis) must be held, by the joints or by a gauge. The
//! accelerations solve `[M Bᵀ; B 0] [v̇; λ] = [Q − h; γ]` (Haug 1989, eq. 11.1.19), which is regular when
//! `M` is positive semi-definite and `B n ≠ 0` for every `n` with `M n = 0` (the null spaces of `M` and
//! `B` meet only at zero); the BDF's and the generalized-α method's iteration matrices have the same
//! structure, and no solve of the engine inverts `M` alone.
//!
//! **The gauge.** A spin that no joint holds (the beam on a ball joint, or free) moves no mass point:
//! the points lie on its axis, and once the beam bends, the same spin of the frame with the opposite
//! turn of the deflection in the modes leaves every point where it was. It is a gauge freedom of the
//! floating frame, not a motion of the body, and it is fixed by the condition that the frame does not
//! spin about that axis, `ω̄ · e = 0` in the body frame (e the axis). The condition is imposed through
//! the mass matrix: `c e eᵀ` is added to the body's angular-velocity block of the matrix of the
//! acceleration solve and of the Newton iterations, and `c e (e · ω̄̇)` to the inertia forces (no
//! velocity terms; the kinetic energy and the momenta leave it out), with `c` the body's largest
//! moment of inertia about its frame origin, so the block keeps the body's own scale. Along a gauge
//! direction `g` (`M g = 0`, no force does work along it, `B g = 0`), the equations of motion read
//! `c (e · g)(e · ω̄̇) = 0`: the spin's acceleration is zero and nothing else changes — the condition's
//! reaction is zero, as that of a constraint row `ω̄ · e = 0` would be. A row would have done the same,
//! but the engine's constraints are positions `Φ(q) = 0` with their velocity form (the stabilized
//! index-2 form keeps both, and the assembly, the redundancy analysis and every integrator rely on
//! it), and `ω̄ · e = 0` has no position form; the gauge inertia keeps the coordinates and the
//! integrators as they are. A spin given at the start (`ω̄ · e ≠ 0`) is kept constant, and still moves
//! no mass point. The gauge is set when the model is built, for the massless motions that the joints
//! do not hold at its initial configuration; a spin that a joint holds keeps no gauge (it would add
//! `c` times the spin's acceleration to the joint's reaction when the joint turns the beam about its
//! axis).
//!
//! The massless motions are found at `a = 0`; the assembly checks that the constraints in force at the
//! assembled configuration, with the gauge, hold every one; a motion that neither holds (one that does
//! not turn the frame, which no gauge of its spin can hold) is an error naming the body and the motion.

use nalgebra::{DMatrix, DVector, SymmetricEigen, Vector4};

use super::{AssemblyError, State};
use crate::body::MasslessMotion;
use crate::data::Data;
use crate::math::{rotation_matrix, Mat3, Vec3};
use crate::model::Model;
use crate::stage::{jacobian_entries, run_kinematic_stages};

/// `|B n|` below this share of the largest entry of `B` on the body's columns: `B` does not hold `n`.
const NOT_HELD: f64 = 1e-8;

/// Below this norm of its angular-velocity part (the motion of unit norm), a massless motion does not
/// turn the frame and no gauge of the spin holds it.
const NO_SPIN: f64 = 1e-6;

/// The gauge inertia of each body (body frame, zero where none): for a flexible body, `c Σ e eᵀ` over
/// an orthonormal basis `e` of the spin axes of its massless motions that the joints do not hold at the
/// model's initial configuration, `c` its largest moment of inertia about the frame origin (module
/// documentation).
pub(crate) fn massless_gauges(model: &Model) -> Vec<Mat3> {
    let mut gauges = vec![Mat3::zeros(); model.bodies.len()];
    let mut staged: Option<(Data, State)> = None;
    for (b, modal) in model.modal.iter().enumerate() {
        let Some(modal) = modal else { continue };
        let motions = modal.massless_motions();
        if motions.is_empty() {
            continue;
        }
        let (data, state) = staged.get_or_insert_with(|| {
            let state = State::initial(model);
            let mut data = Data::new(model);
            run_kinematic_stages(model, &mut data, state.t, &state.q, &state.v);
            (data, state)
        });
        let all = vec![true; model.layout.nc];
        let (held, largest) = held_columns(model, data, &state.q, &all, b, &motions);
        // The combinations of the motions that B does not hold: the eigenvectors of (B N)ᵀ(B N) with
        // eigenvalues below the threshold's square.
        let eigen = SymmetricEigen::new(held.transpose() * &held);
        let threshold = (NOT_HELD * largest).powi(2);
        let spins: Vec<Vec3> = (0..motions.len())
            // NaN holds nothing.
            .filter(|&k| eigen.eigenvalues[k].partial_cmp(&threshold) != Some(std::cmp::Ordering::Greater))
            .map(|k| {
                motions.iter().zip(eigen.eigenvectors.column(k).iter()).map(|(m, u)| *u * spin_part(m)).sum::<Vec3>()
            })
            .collect();
        if spins.is_empty() {
            continue;
        }
        // An orthonormal basis of their spin axes.
        let spans = SymmetricEigen::new(spins.iter().map(|w| w * w.transpose()).sum::<Mat3>());
        let axes = (0..3).filter(|&k| spans.eigenvalues[k] > NO_SPIN * NO_SPIN).map(|k| spans.eigenvectors.column(k).into_owned());
        let scale = modal.invariants.undeformed_inertia().symmetric_eigenvalues().max();
        gauges[b] = axes.map(|e| scale * e * e.transpose()).sum();
    }
    gauges
}

fn spin_part(motion: &MasslessMotion) -> Vec3 {
    Vec3::new(motion.velocity[3], motion.velocity[4], motion.velocity[5])
}

/// `B N`: the body's columns of the constraint Jacobian in the rows in force (`active`) times each
/// massless motion (its `Ṙ` turned to global axes), after the kinematic stages at `q`; and the largest
/// entry of those columns of `B`, the scale of the test.
fn held_columns(model: &Model, data: &Data, q: &[f64], active: &[bool], b: usize, motions: &[MasslessMotion]) -> (DMatrix<f64>, f64) {
    let nc = model.layout.nc;
    let span = model.layout.v_span(b);
    let qo = model.layout.q_offset[b];
    let a = rotation_matrix(&Vector4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]));
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
    let held = if columns.is_empty() { DMatrix::zeros(nc, 0) } else { DMatrix::from_columns(&columns) };
    (held, largest)
}

/// Checks, at the assembled `state`, that its constraint rows in force and the gauges hold every
/// massless motion of every flexible body (the kinematic stages are run at the state once a body has
/// such motions).
pub(crate) fn check_massless_motions_held(model: &Model, data: &mut Data, state: &State) -> Result<(), AssemblyError> {
    let mut staged = false;
    for (b, modal) in model.modal.iter().enumerate() {
        let Some(modal) = modal else { continue };
        let motions = modal.massless_motions();
        if motions.is_empty() {
            continue;
        }
        if !staged {
            run_kinematic_stages(model, data, state.t, &state.q, &state.v);
            staged = true;
        }
        let (held, largest) = held_columns(model, data, &state.q, &state.active, b, &motions);
        // The gauge's rows: the spin about each gauged axis, at the scale of B.
        let gauge = model.massless_gauges[b];
        let gauge_scale = gauge.amax();
        let largest = if largest > 0.0 { largest } else { 1.0 };
        let rows = held.nrows();
        let held = DMatrix::from_fn(rows + 3, motions.len(), |r, k| {
            if r < rows {
                held[(r, k)]
            } else if gauge_scale > 0.0 {
                largest * (gauge * spin_part(&motions[k]))[r - rows] / gauge_scale
            } else {
                0.0
            }
        });
        // Held together: the columns have full rank (each direction alone, and no combination, escapes).
        let smallest = if held.nrows() < held.ncols() { 0.0 } else { held.singular_values().min() };
        // NaN holds nothing.
        let holds = |size: f64| size > NOT_HELD * largest;
        if !holds(smallest) {
            let unheld = held.column_iter().position(|c| !holds(c.norm())).unwrap_or(0);
            return Err(AssemblyError::MasslessMotion {
                body: model.bodies[b].name.clone(),
                motion: motions[unheld].describe(),
            });
        }
    }
    Ok(())
}
