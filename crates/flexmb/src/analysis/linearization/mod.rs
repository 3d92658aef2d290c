//! The equations of motion linearized at any state: mass, damping and stiffness matrices and the
//! constraint Jacobian, for eigen-analysis, equilibrium and control design.
//!
//! With `g(q, v, v̇, λ) = M(q) v̇ + h(q, v) − Q(q, v, t) + B(q)ᵀλ` (the dynamic rows) and the velocity
//! constraints `B(q) v + Φ_t = 0`, a small motion `δq` (in velocity space: translations, rotation vector
//! in body axes, modal coordinates, as [`displaced_positions`] moves the positions), `δv`, `δv̇`, `δλ`
//! about a state satisfies
//!
//! ```text
//! M δv̇ + C δv + K δq + Bᵀ δλ = 0,        C = ∂g/∂v,   K = ∂g/∂q  (v̇, λ held)
//! ```
//!
//! `M` and `B` are exact; `K`, `C` and `K_B = ∂(B v + Φ_t)/∂q` come from finite differences with the
//! columns grouped by colouring, on a sparse pattern made once per model ([`SparseLinearization`], the
//! evaluation the generalized-α iteration matrix makes too). [`linearize`] returns them dense; an
//! eigen-analysis of a large model keeps them sparse.

mod driver_input;
mod independent;
mod sparse;

use faer::Mat;

pub use driver_input::{driver_inputs, DriverInputs};
pub use independent::{reduce_to_independent, IndependentCoordinates, ReducedLinearization};
pub use sparse::SparseLinearization;

use super::{Accelerations, State};
use crate::data::Data;
use crate::stage::retract;
use crate::model::{Model, SizeCheck, SizeMismatch};
use crate::stage::{inertia_jacobian_entries, jacobian_entries, run_kinematic_stages};

/// The equations of motion linearized at one state (matrices in velocity coordinates: `nv` columns).
#[derive(Clone, Debug)]
pub struct Linearization {
    /// `M = ∂g/∂v̇`, `nv × nv`: the mass matrix, and for a flexible body with geometric stiffening the
    /// (non-symmetric) acceleration columns of `K_G a`.
    pub mass: Mat<f64>,
    /// `C = ∂g/∂v`, `nv × nv`: viscous forces, gyroscopic and Coriolis terms.
    pub damping: Mat<f64>,
    /// `K = ∂g/∂q`, `nv × nv`: elastic forces, gravity through the rotations, the inertia and
    /// constraint forces of the state's `v̇` and `λ`.
    pub stiffness: Mat<f64>,
    /// `B = Φ_q T`, `nc × nv` (zero rows for the constraints switched off).
    pub constraint_jacobian: Mat<f64>,
    /// `K_B = ∂(B v + Φ_t)/∂q`, `nc × nv`.
    pub constraint_stiffness: Mat<f64>,
}

/// A state of motion at which the equations are linearized: time, positions and velocities, with the
/// accelerations and multipliers held while they are perturbed.
#[derive(Clone, Copy, Debug)]
pub struct OperatingPoint<'a> {
    /// Time (s).
    pub t: f64,
    /// Positions, per body `R, p, a`.
    pub q: &'a [f64],
    /// Velocities, per body `Ṙ, ω̄, ȧ`.
    pub v: &'a [f64],
    /// Accelerations `v̇`.
    pub vdot: &'a [f64],
    /// Multipliers `λ`, one per constraint row.
    pub lambda: &'a [f64],
}

impl<'a> OperatingPoint<'a> {
    /// The point of `state` with the accelerations and multipliers `acc`.
    pub fn new(state: &'a State, acc: &'a Accelerations) -> Self {
        Self { t: state.t, q: &state.q, v: &state.v, vdot: &acc.vdot, lambda: &acc.lambda }
    }
}

/// Linearizes the equations of motion at `state` with the accelerations and multipliers `acc` (those
/// of the state for a linearization about a motion; zero velocities and accelerations with the
/// equilibrium's multipliers for one about an equilibrium). `data` supplies the parameter values and
/// joint-angle references; its stages are left evaluated at the state. A `data`, state or `acc` not of
/// `model`'s sizes is an error.
pub fn linearize(model: &Model, data: &mut Data, state: &State, acc: &Accelerations) -> Result<Linearization, SizeMismatch> {
    SizeCheck::new(model).data(data)?.state(state)?.accelerations(acc)?;
    Ok(linearize_at(model, data, state, acc))
}

/// [`linearize`] on arguments of the model's sizes (the engine's own calls).
pub(crate) fn linearize_at(model: &Model, data: &mut Data, state: &State, acc: &Accelerations) -> Linearization {
    let State { t, q, v, active } = state;
    let l = &model.layout;
    let mut derivatives = SparseLinearization::new(model);
    derivatives.evaluate_at(model, data, active, &OperatingPoint::new(state, acc));
    let (stiffness, damping, constraint_stiffness) = derivatives.to_dense();
    run_kinematic_stages(model, data, *t, q, v);
    let mut mass = Mat::zeros(l.nv, l.nv);
    for b in 0..model.bodies.len() {
        let vo = l.v_offset[b];
        inertia_jacobian_entries(model, data, b, |r, c, m| mass[(vo + r, vo + c)] += m);
    }
    let mut constraint_jacobian = Mat::zeros(l.nc, l.nv);
    jacobian_entries(model, data, |row, col, x| {
        if active[row] {
            constraint_jacobian[(row, col)] += x;
        }
    });
    Linearization { mass, damping, stiffness, constraint_jacobian, constraint_stiffness }
}

/// The positions `q` moved by the velocity-space increment `d`: translations and modal coordinates
/// added, each body frame turned by the rotation vector `d_ω̄` about its own axes (`p ∘ exp(d_ω̄)`), the
/// displacement the columns of [`Linearization::stiffness`] are taken along. `q` and `d` not of `model`'s
/// sizes are an error.
pub fn displaced_positions(model: &Model, q: &[f64], d: &[f64]) -> Result<Vec<f64>, SizeMismatch> {
    SizeCheck::new(model).positions(q)?.velocities("the increment d", d)?;
    let mut out = vec![0.0; q.len()];
    retract(&model.layout, q, d, &mut out);
    Ok(out)
}
