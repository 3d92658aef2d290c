//! `Simulation.set_state` and the names of the coordinates: the library's `Simulation::set_state`
//! (positions by the assembly's Newton iteration, velocities by the velocity projection, the integrator
//! restarted) with its report as a dict, and `Model::position_names` / `velocity_names`.

use flexmb::analysis::{Simulation as Engine, SimulationFailure};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Sets the positions and/or velocities of `engine` (sequences of floats of the layout's lengths) and
/// returns what the projection changed. A wrong length, a value that is not finite or a state that
/// cannot be made consistent raises `ValueError` (the simulation stays as it was).
pub fn set_state<'py>(
    py: Python<'py>,
    engine: &mut Engine,
    positions: Option<Vec<f64>>,
    velocities: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let projection = py
        .detach(|| engine.set_state(positions.as_deref(), velocities.as_deref()))
        .map_err(|e: SimulationFailure| PyValueError::new_err(format!("set_state: {e}")))?;
    let dict = PyDict::new(py);
    dict.set_item("assembly_iterations", projection.assembly_iterations)?;
    dict.set_item("position_change", projection.position_change)?;
    dict.set_item("velocity_change", projection.velocity_change)?;
    dict.set_item("position_residual", projection.position_residual)?;
    dict.set_item("velocity_residual", projection.velocity_residual)?;
    dict.set_item("energy_change", projection.energy_change)?;
    Ok(dict)
}

/// `{"positions": [...], "velocities": [...]}`: a name for each entry of `positions` and `velocities`.
pub fn coordinate_names<'py>(py: Python<'py>, engine: &Engine) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("positions", engine.model().position_names())?;
    dict.set_item("velocities", engine.model().velocity_names())?;
    Ok(dict)
}
