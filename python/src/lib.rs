//! The native module of the `flexmb` Python package: thin wrappers over the library calls the
//! `flexmb` program makes (`flexmb_files::load_model_with`, `flexmb::analysis::check_model`,
//! `flexmb::analysis::Simulation`, the restart files), with numpy arrays for results.

mod callable_law;
mod errors;
mod interrupt;
mod equilibrium;
mod linear_analysis;
mod model;
mod model_text;
mod modes;
mod results;
mod run;
mod settings;
mod simulation;
mod state_setting;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(model::load, m)?)?;
    m.add_class::<model::Model>()?;
    m.add_class::<results::Results>()?;
    m.add_class::<simulation::Simulation>()?;
    // Models from text (flexmb.ModelBuilder) and the preprocessor (flexmb.modes).
    m.add_function(wrap_pyfunction!(model_text::loads, m)?)?;
    m.add_function(wrap_pyfunction!(modes::modes, m)?)?;
    m.add_class::<modes::FlexibleBody>()?;
    m.add("ModelError", py.get_type::<errors::ModelError>())?;
    m.add("SimulationError", py.get_type::<errors::SimulationError>())?;
    Ok(())
}
