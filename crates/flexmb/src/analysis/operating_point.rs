//! The state at which a mechanism is linearized (`flexmb linearize`, `flexmb eigen`, the Python
//! package's `Model.linearize` and `Model.eigen`): the initial state, the state a simulation reaches at
//! a time, or the static equilibrium.

use std::sync::Arc;

use super::{assemble, static_equilibrium, EquilibriumError, EquilibriumSettings, Start, linearize_at, reduce_to_independent, velocity_analysis, Linearization, ReducedLinearization, AccelerationSolver, Accelerations, AssemblyError, Simulation, SimulationFailure, SimulationSettings, State};
use crate::data::Data;
use crate::model::Model;

/// Where to linearize.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OperatingPointChoice {
    /// The assembled, velocity-analysed initial state, the model's initial velocities included (a
    /// spinning top's spin), with its accelerations and multipliers.
    Initial,
    /// The state a simulation with the given settings' integrator and tolerances reaches at this
    /// time (s).
    Time(f64),
    /// The static equilibrium with the loads and drivers held at their initial values.
    Equilibrium,
}

/// A state to linearize at, with what the linearization needs beside it.
#[derive(Clone, Debug)]
pub struct LinearizationPoint {
    /// Evaluation data at the state (parameters, joint-angle continuation).
    pub data: Data,
    /// Time, positions, velocities, constraint rows in force.
    pub state: State,
    /// Accelerations and multipliers at the state.
    pub accelerations: Accelerations,
}

/// Why no operating point could be found.
#[derive(Debug, thiserror::Error)]
pub enum OperatingPointError {
    /// The initial state could not be assembled.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// The accelerations of the state could not be solved (a singular mass or constraint matrix).
    #[error("the accelerations at the operating point could not be solved: {0}")]
    Accelerations(String),
    /// The simulation to the requested time failed.
    #[error("the simulation to the operating point failed: {0}")]
    Simulation(#[from] SimulationFailure),
    /// The static equilibrium could not be found.
    #[error("the static equilibrium (the operating point) could not be found: {0}")]
    Equilibrium(#[from] EquilibriumError),
    /// The choice is not available.
    #[error("{0}")]
    Unavailable(String),
}

/// The operating point of `choice`. `settings` supplies the assembly settings, and for
/// [`OperatingPointChoice::Time`] the integrator and tolerances (its end time is replaced by the
/// requested time).
pub fn operating_point(model: &Arc<Model>, choice: OperatingPointChoice, settings: &SimulationSettings) -> Result<LinearizationPoint, OperatingPointError> {
    match choice {
        OperatingPointChoice::Initial => initial_point(model, settings),
        OperatingPointChoice::Time(0.0) => initial_point(model, settings),
        OperatingPointChoice::Time(t) => {
            if !(t > 0.0 && t.is_finite()) {
                return Err(OperatingPointError::Unavailable(format!("the operating point's time must be positive, got {t}")));
            }
            let mut settings = *settings;
            settings.t_end = t;
            settings.output_step = settings.output_step.min(t);
            let mut simulation = Simulation::new(Arc::clone(model), settings).map_err(|e| e.cause)?;
            simulation.run(&mut |_: &super::OutputFrame| {}, &|| None)?;
            let (data, state, accelerations) = simulation.operating_point()?;
            Ok(LinearizationPoint { data, state, accelerations })
        }
        OperatingPointChoice::Equilibrium => equilibrium_point(model, settings),
    }
}

/// The static equilibrium at the start time with the settings of `settings.start` if it asks for an
/// equilibrium start (else the defaults, on the settings' assembly), velocities zero.
fn equilibrium_point(model: &Model, settings: &SimulationSettings) -> Result<LinearizationPoint, OperatingPointError> {
    let equilibrium_settings = match settings.start {
        Start::Equilibrium(s) => s,
        Start::Assembly => EquilibriumSettings { assembly: settings.assembly, ..Default::default() },
    };
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let t = state.t;
    static_equilibrium(model, &mut data, &mut state, t, &equilibrium_settings)?;
    let accelerations = AccelerationSolver::new(model)
        .solve_at(model, &mut data, state.t, &state.q, &state.v, &state.active)
        .map_err(|e| OperatingPointError::Accelerations(format!("{e:?}")))?
        .clone();
    Ok(LinearizationPoint { data, state, accelerations })
}

fn initial_point(model: &Model, settings: &SimulationSettings) -> Result<LinearizationPoint, OperatingPointError> {
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    assemble(model, &mut data, &mut state, settings.assembly)?;
    velocity_analysis(model, &mut data, &mut state)?;
    let accelerations = AccelerationSolver::new(model)
        .solve_at(model, &mut data, state.t, &state.q, &state.v, &state.active)
        .map_err(|e| OperatingPointError::Accelerations(format!("{e:?}")))?
        .clone();
    Ok(LinearizationPoint { data, state, accelerations })
}

/// The equations of motion linearized at an operating point, whole and in independent coordinates.
#[derive(Clone, Debug)]
pub struct LinearModel {
    /// Where they were linearized.
    pub point: LinearizationPoint,
    /// `M, C, K, B, K_B` in velocity coordinates.
    pub full: Linearization,
    /// `M_z, C_z, K_z` in independent coordinates, with the basis.
    pub reduced: ReducedLinearization,
}

/// Linearizes `model` at the operating point of `choice` ([`operating_point`]) and reduces the
/// equations to independent coordinates ([`reduce_to_independent`]): what `flexmb linearize`,
/// `flexmb eigen` and the Python package's `Model.linearize` and `Model.eigen` compute first.
pub fn linear_model(model: &Arc<Model>, choice: OperatingPointChoice, settings: &SimulationSettings) -> Result<LinearModel, OperatingPointError> {
    let mut point = operating_point(model, choice, settings)?;
    let full = linearize_at(model, &mut point.data, &point.state, &point.accelerations);
    let reduced = reduce_to_independent(model, &mut point.data, &point.state, &point.accelerations, &full);
    Ok(LinearModel { point, full, reduced })
}
