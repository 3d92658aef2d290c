//! Setting a simulation's state between steps: new positions and/or velocities, made consistent with
//! the constraints (the positions by the assembly's Newton iteration, the velocities by the velocity
//! analysis's projection), and the integrator restarted there as after a discontinuity (order 1, a new
//! first step, no history).

use std::sync::Arc;

use super::{start_integrator, Simulation, SimulationFailure};
use crate::analysis::assembly::project_positions;
use crate::analysis::velocity::project_velocities;
use crate::analysis::State;
use crate::data::Data;
use crate::model::Model;
use crate::stage::{energy, run_kinematic_stages};

/// What [`Simulation::set_state`] changed to make the state given consistent with the constraints.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct StateProjection {
    /// Newton iterations of the assembly on the positions given (0 without positions, or when they
    /// satisfied the constraints already).
    pub assembly_iterations: usize,
    /// Largest change the assembly made to a position coordinate given (0 without positions).
    pub position_change: f64,
    /// Largest change the projection made to a velocity given (or to the current velocities, when
    /// only positions are given).
    pub velocity_change: f64,
    /// Largest constraint residual `|Φ|` after the projection.
    pub position_residual: f64,
    /// Largest velocity-constraint residual `|B v − ν|` after the projection.
    pub velocity_residual: f64,
    /// Total energy after minus before (J): what the change of state added, kept out of the energy
    /// balance of the report.
    pub energy_change: f64,
}

impl Simulation {
    /// Replaces the positions `q` and/or the velocities `v` at the current time (`None` keeps the
    /// current ones), between steps. Positions are moved onto the constraints in force by the
    /// assembly's Newton iteration (the minimum-norm correction), velocities projected onto the velocity
    /// constraints at those positions (the minimum-norm correction, every component weighted alike);
    /// then the accelerations are solved and the integrator restarted there, at order 1 with a new
    /// initial step, as after a discontinuity. The counters go on; the energy the change adds is
    /// added to the report's initial energy, so that its balance measures the integration only.
    ///
    /// Fails, leaving the simulation as it was, for a wrong length or a value that is not finite
    /// ([`SimulationFailure::Invalid`] naming the expected length) or a state that cannot be made
    /// consistent (the assembly's failure).
    pub fn set_state(&mut self, positions: Option<&[f64]>, velocities: Option<&[f64]>) -> Result<StateProjection, SimulationFailure> {
        self.usable()?;
        let model = Arc::clone(&self.model);
        let l = &model.layout;
        check_given("positions", l.nq, "per body: origin R, Euler parameters p, modal coordinates a", positions)?;
        check_given("velocities", l.nv, "per body: origin velocity, body-frame angular velocity, modal rates", velocities)?;
        let t = self.integrator.t();
        let (q, v) = self.integrator.state();
        let mut state = State { t, q: positions.unwrap_or(q).to_vec(), v: velocities.unwrap_or(v).to_vec(), active: self.active.clone() };
        let mut data = Data::new(&model);
        data.parameters.copy_from_slice(&self.parameters);
        let energy_before = total_energy(&model, &mut data, t, q, v);
        let (q_given, v_given) = (state.q.clone(), state.v.clone());
        let assembly_iterations = match positions {
            Some(_) => project_positions(&model, &mut data, &mut state, self.settings.assembly)?,
            None => 0,
        };
        let velocity_residual = project_velocities(&model, &mut data, &mut state, &vec![1.0; l.nv])?;
        let acc = self
            .accelerations
            .solve_at(&model, &mut data, t, &state.q, &state.v, &state.active)
            .map_err(|_| super::accelerations_failure(&model, &data, t))?
            .clone();
        let energy_after = total_energy(&model, &mut data, t, &state.q, &state.v);
        let (position_residual, _) = super::constraint_residuals(&model, &data, &state.active);
        let integrator = start_integrator(&model, &self.settings, &state, &acc)?;
        self.restarted_stats = self.report.stats;
        self.integrator = integrator;
        // The shadow of the divergence check no longer neighbours the state set.
        self.divergence = None;
        // The global error estimate's shadow started from the run's start, not from the state set.
        self.global_error = None;
        for (p, value) in self.parameters.clone().into_iter().enumerate() {
            self.write_parameter(p, value);
        }
        let energy_change = energy_after - energy_before;
        if self.report.output_frames > 0 {
            self.report.energy_initial += energy_change;
        }
        let largest_change = |given: &[f64], now: &[f64]| given.iter().zip(now).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        Ok(StateProjection {
            assembly_iterations,
            position_change: if positions.is_some() { largest_change(&q_given, &state.q) } else { 0.0 },
            velocity_change: largest_change(&v_given, &state.v),
            position_residual,
            velocity_residual,
            energy_change,
        })
    }
}

/// `values`, if given, has `expected` finite entries; else an error naming the expected length and
/// the layout `what_per_body`.
fn check_given(what: &str, expected: usize, what_per_body: &str, values: Option<&[f64]>) -> Result<(), SimulationFailure> {
    let Some(values) = values else { return Ok(()) };
    if values.len() != expected {
        return Err(SimulationFailure::Invalid(format!(
            "the {what} must have {expected} entries ({what_per_body}), got {}",
            values.len()
        )));
    }
    if let Some(k) = values.iter().position(|x| !x.is_finite()) {
        return Err(SimulationFailure::Invalid(format!("the {what} must be finite, entry {k} is {}", values[k])));
    }
    Ok(())
}

fn total_energy(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64]) -> f64 {
    run_kinematic_stages(model, data, t, q, v);
    energy(model, data, q, v).total()
}
