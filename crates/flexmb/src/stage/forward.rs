//! The forward pipeline, the engine's table of contents: position → velocity (kinematics, constraint
//! equations) → forces (measures, applied forces, inertia forces). The accelerations and multipliers that
//! make these consistent are solved by [`AccelerationSolver`](crate::analysis::AccelerationSolver), the
//! dynamics end of the pipeline; the integrators, the analyses and the linearization evaluate the
//! stages through here.
//!
//! ```
//! use flexmb::analysis::{assemble, linearize, AccelerationSolver, State};
//! use flexmb::stage::forward;
//! use flexmb::Data;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! # let model = flexmb::analysis::test_models::double_pendulum_with_spring();
//! // `model`: any `Model`, here a double pendulum with a spring-damper.
//! let mut data = Data::new(&model);
//! let mut state = State::initial(&model);
//! assemble(&model, &mut data, &mut state, Default::default())?;
//! // The dynamics end: [M Bᵀ; B 0] [v̇; λ] = [Q − h; γ] at the state.
//! let acc = AccelerationSolver::new(&model).solve(&model, &mut data, state.t, &state.q, &state.v, &state.active)?.clone();
//! // The constraint Jacobian B, from the linearization at the state.
//! let b = linearize(&model, &mut data, &state, &acc)?.constraint_jacobian;
//! // Every stage at (t, q, v, v̇): the equations of motion M v̇ + h − Q + Bᵀλ = 0 hold.
//! forward(&model, &mut data, state.t, &state.q, &state.v, &acc.vdot)?;
//! for k in 0..model.layout().nv {
//!     let constraint_force: f64 = (0..model.layout().nc).map(|r| b[(r, k)] * acc.lambda[r]).sum();
//!     let g = data.inertia_forces()[k] - data.applied_forces()[k] + constraint_force;
//!     assert!(g.abs() < 1e-9 * (1.0 + data.applied_forces()[k].abs()));
//! }
//! # Ok(())
//! # }
//! ```

use super::{applied_forces, constraint_equations, inertia_forces, kinematics, measures};
use crate::data::Data;
use crate::model::{Model, SizeCheck, SizeMismatch};

/// Evaluates every stage at `(t, q, v)` with accelerations `vdot` into `data`: the
/// [`kinematic_stages`] then the [`force_stages`]. Vectors or a `data` not of `model`'s sizes are an
/// error, before anything is evaluated.
pub fn forward(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64], vdot: &[f64]) -> Result<(), SizeMismatch> {
    check_state(model, data, q, v)?.velocities("accelerations v̇", vdot)?;
    run_forward(model, data, t, q, v, vdot);
    Ok(())
}

/// Position and velocity: the kinematics of every body and marker at `(q, v)`, then the value,
/// derivatives and acceleration bias of every constraint row at `t` (using `data`'s joint-angle
/// references). Enough for the constraint residuals, the constraint Jacobian and the mass matrix.
pub fn kinematic_stages(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64]) -> Result<(), SizeMismatch> {
    check_state(model, data, q, v)?;
    run_kinematic_stages(model, data, t, q, v);
    Ok(())
}

/// Forces, after the [`kinematic_stages`]: the measures, the generalized applied forces `Q(q, v, t)`
/// ([`Data::applied_forces`]) and the inertia forces `M v̇ + h(q, v)` ([`Data::inertia_forces`]).
pub fn force_stages(model: &Model, data: &mut Data, t: f64, vdot: &[f64]) -> Result<(), SizeMismatch> {
    SizeCheck::new(model).data(data)?.velocities("accelerations v̇", vdot)?;
    run_force_stages(model, data, t, vdot);
    Ok(())
}

/// `data`, `q` and `v` of `model`'s sizes.
fn check_state<'m>(model: &'m Model, data: &Data, q: &[f64], v: &[f64]) -> Result<SizeCheck<'m>, SizeMismatch> {
    SizeCheck::new(model).data(data)?.positions(q)?.velocities("velocities v", v)
}

/// [`forward`] on arguments of the model's sizes (the engine's own calls).
pub(crate) fn run_forward(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64], vdot: &[f64]) {
    run_kinematic_stages(model, data, t, q, v);
    run_force_stages(model, data, t, vdot);
}

/// [`kinematic_stages`] on arguments of the model's sizes.
pub(crate) fn run_kinematic_stages(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64]) {
    kinematics(model, data, q, v);
    constraint_equations(model, data, t);
}

/// [`force_stages`] on arguments of the model's sizes.
pub(crate) fn run_force_stages(model: &Model, data: &mut Data, t: f64, vdot: &[f64]) {
    measures(model, data);
    applied_forces(model, data, t);
    inertia_forces(model, data, vdot);
}
