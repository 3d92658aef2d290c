//! Drivers as inputs of the linear equations: a driver's constraint `Φ_d(q) − f(t) − u = 0` with a
//! small offset `u` added to its prescribed angle or displacement.
//!
//! The perturbed motion is `δx = N δz + P u`, with `P` the particular solution of the position
//! constraints `B δx_p = e_d` (one unit of the driver, the independent coordinates held; zero on them),
//! taken like `N` with the partition of the operating point. Its velocity is
//! `δv = N δż + (Ṅ + W N) δz + P u̇ + (Ṗ + W P) u`, and the projection `Nᵀ` of the linearized dynamics
//! (the multipliers drop out, `B N = 0`) gives
//!
//! ```text
//! M_z δz̈ + C_z δż + K_z δz + M_zu ü + C_zu u̇ + K_zu u = 0
//! M_zu = Nᵀ M P,   C_zu = Nᵀ [C P + M (2Ṗ + W P)],   K_zu = Nᵀ [K P + C (Ṗ + W P) + M (P̈ + W Ṗ + Ẇ P)]
//! ```
//!
//! so that a driven motion enters through its value (the springs and gravity it moves), its rate (the
//! dampers) and its acceleration (the inertia it carries): three inputs per driver, as a base excitation
//! is written in structural dynamics.

use faer::Mat;

use super::independent::reduce_with_particular;
use super::{Linearization, ReducedLinearization};
use crate::analysis::{Accelerations, State};
use crate::data::Data;
use crate::model::Model;

/// The terms of drivers' offsets in the reduced equations, one column per driver.
#[derive(Clone, Debug)]
pub struct DriverInputs {
    /// The drivers' names.
    pub names: Vec<String>,
    /// `M_zu = Nᵀ M P`, `n × drivers`: the term of the offsets' accelerations `ü`.
    pub mass: Mat<f64>,
    /// `C_zu`, `n × drivers`: the term of the offsets' rates `u̇`.
    pub damping: Mat<f64>,
    /// `K_zu`, `n × drivers`: the term of the offsets `u`.
    pub stiffness: Mat<f64>,
    /// `P`, `nv × drivers`: the motion of the mechanism (velocity coordinates, rotations in body axes)
    /// for a unit offset of each driver with the independent coordinates held.
    pub motion: Mat<f64>,
    /// `Ṗ + W P`, `nv × drivers`: the velocity a unit offset carries along the motion (zero at rest).
    pub motion_rate: Mat<f64>,
}

/// The terms of the offsets of the angle or displacement drivers `drivers` (joint names) in the
/// reduced equations of `lin` (taken at `state` with `acc`), in the independent coordinates the
/// reduction [`reduce_to_independent`](super::reduce_to_independent) chooses at that state. A name that
/// is not a driver of `model`, a driver switched off at the state, or one whose equation depends on the
/// others there (its offset cannot be prescribed) is an error that says so.
pub fn driver_inputs(model: &Model, data: &mut Data, state: &State, acc: &Accelerations, lin: &Linearization, drivers: &[String]) -> Result<(ReducedLinearization, DriverInputs), String> {
    let rows = drivers.iter().map(|name| driver_row(model, state, name)).collect::<Result<Vec<_>, _>>()?;
    let (reduced, particular) = reduce_with_particular(model, data, state, acc, lin, &rows).map_err(|row| {
        let name = &drivers[rows.iter().position(|r| *r == row).unwrap_or(0)];
        format!("driver '{name}': its equation depends on the other constraints at the operating point, so its offset cannot be an input")
    })?;
    let inputs = DriverInputs {
        names: drivers.to_vec(),
        mass: particular.mass,
        damping: particular.damping,
        stiffness: particular.stiffness,
        motion: particular.motion,
        motion_rate: particular.motion_rate,
    };
    Ok((reduced, inputs))
}

/// The constraint row of the driver `name`.
fn driver_row(model: &Model, state: &State, name: &str) -> Result<usize, String> {
    let Some(j) = model.joints.iter().position(|j| j.name == name && j.kind.is_driver()) else {
        let known: Vec<&str> = model.joints.iter().filter(|j| j.kind.is_driver()).map(|j| j.name.as_str()).collect();
        let list = if known.is_empty() { "it has none".to_string() } else { format!("it has {}", known.join(", ")) };
        return Err(format!("the model has no angle or displacement driver '{name}': {list}"));
    };
    let row = model.layout.joint_rows[j].start;
    if !state.active[row] {
        return Err(format!("driver '{name}' is switched off at the operating point"));
    }
    Ok(row)
}
