//! `Model.simulate`: a run from the initial state to the end time into a table in memory, without the
//! GIL, stopped by Ctrl-C; its failure or interruption raised with the rows computed until then.

use std::sync::Arc;

use flexmb::analysis::{global_error_rerun, OutputTable, Simulation as Engine, SimulationFailure, SimulationSettings};
use pyo3::prelude::*;

use crate::errors::SimulationError;
use crate::interrupt::SignalWatch;
use crate::model::Model;
use crate::results::Results;

/// Runs `model` with `settings` to its end time; with global error control, again from the start while
/// [`global_error_rerun`] asks (the results are the last run's, its report naming the earlier ones).
pub fn simulate(py: Python<'_>, model: &Model, settings: &SimulationSettings) -> PyResult<Results> {
    let (mut settings, mut earlier) = (*settings, Vec::new());
    loop {
        let engine = Arc::clone(&model.loaded.model);
        let mut simulation = py.detach(|| Engine::new(engine, settings)).map_err(|e| crate::callable_law::start_error(py, &model.file, e))?;
        let mut table = OutputTable::new(&model.loaded.model);
        let (run, raised) = py.detach(|| {
            let watch = SignalWatch::new();
            let run = simulation.run(&mut table, &|| watch.interrupted());
            (run, watch.into_raised())
        });
        let rerun = match (&run, &raised) {
            (Ok(()), None) => global_error_rerun(&settings, simulation.report(), earlier.len()),
            _ => None,
        };
        match rerun {
            Some((finer, this)) => {
                settings = finer;
                earlier.push(this);
            }
            None => {
                simulation.record_earlier_runs(earlier);
                return finish(py, &model.file, &simulation, &table, run, raised);
            }
        }
    }
}

/// The results of a run (or of the steps a `Simulation` took) that returned `run` and was stopped by the
/// signal handler's exception `raised`, if one was: the results, or the exception with the results in
/// its attribute `results`.
pub fn finish(
    py: Python<'_>,
    file: &str,
    simulation: &Engine,
    table: &OutputTable,
    run: Result<(), SimulationFailure>,
    raised: Option<PyErr>,
) -> PyResult<Results> {
    let error = run.as_ref().err().map(ToString::to_string);
    let results = Results::of_run(simulation.model(), file, simulation.settings(), simulation.report(), table, error.as_deref());
    let failure = match (raised, error) {
        (Some(raised), _) => raised,
        (None, Some(error)) => SimulationError::new_err(format!("{file}: simulation failed: {error}")),
        (None, None) => return Ok(results),
    };
    crate::callable_law::chain_cause(py, &failure, run.as_ref().err());
    failure.value(py).setattr("results", Py::new(py, results)?)?;
    Err(failure)
}
