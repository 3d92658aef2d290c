//! The forward pipeline in one call, the engine's table of contents: position → velocity (kinematics,
//! constraint equations) → forces (measures, applied forces) → inertia. The accelerations and multipliers
//! that make these consistent are solved by [`AccelerationSolver`](crate::analysis::AccelerationSolver);
//! the integrators' residuals and the linearization evaluate the stages through here.

use super::{applied_forces, constraint_equations, inertia_forces, kinematics, measures};
use crate::data::Data;
use crate::model::Model;

/// Evaluates every stage at `(t, q, v)` with accelerations `vdot` into `data`: marker and body
/// kinematics, constraint values and derivatives, measures, generalized applied forces `Q` and inertia
/// forces `M v̇ + h(q, v)`.
pub(crate) fn forward(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64], vdot: &[f64]) {
    kinematics(model, data, q, v);
    constraint_equations(model, data, t);
    measures(model, data);
    applied_forces(model, data, t);
    inertia_forces(model, data, vdot);
}
