//! `Model.simulate`: a run from the initial state to the end time into a table in memory, without the
//! GIL, stopped by Ctrl-C; its failure or interruption raised with the rows computed until then.

use std::sync::Arc;

use flexmb::analysis::{run_under_global_error_control, OutputTable, Simulation as Engine, SimulationFailure, SimulationSettings};
use pyo3::prelude::*;

use crate::errors::SimulationError;
use crate::interrupt::SignalWatch;
use crate::model::Model;
use crate::results::Results;

/// Runs `model` with `settings` to its end time; with global error control, again from the start while it
/// asks ([`run_under_global_error_control`]; the results are the last run's, its report naming the earlier ones).
pub fn simulate(py: Python<'_>, model: &Model, settings: &SimulationSettings) -> PyResult<Results> {
    let (outcome, _, earlier) = run_under_global_error_control(settings, |settings| {
        let engine = Arc::clone(&model.loaded.model);
        let mut simulation = match py.detach(|| Engine::new(engine, *settings)) {
            Ok(simulation) => simulation,
            Err(e) => return (Err(e), None),
        };
        let mut table = OutputTable::new(&model.loaded.model);
        let (run, raised) = py.detach(|| {
            let watch = SignalWatch::new();
            let run = simulation.run(&mut table, &|| watch.interrupted());
            (run, watch.into_raised())
        });
        let completed = (run.is_ok() && raised.is_none()).then(|| simulation.report().clone());
        (Ok((simulation, table, run, raised)), completed)
    });
    let (mut simulation, table, run, raised) = outcome.map_err(|e| crate::callable_law::start_error(py, &model.file, e))?;
    simulation.record_earlier_runs(earlier);
    finish(py, &model.file, &simulation, &table, run, raised)
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
