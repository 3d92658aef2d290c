//! `flexmb.Simulation`: a simulation held between calls, advanced to a time on request, its state read,
//! saved as a checkpoint and resumed (the library's `Simulation` and restart files).

use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};

use flexmb::analysis::{OutputTable, Simulation as Engine};
use flexmb_files::{resume_simulation, save_checkpoint};
use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyRuntimeError};
use pyo3::prelude::*;

use crate::errors::{model_error, SimulationError};
use crate::interrupt::SignalWatch;
use crate::model::Model;
use crate::results::Results;
use crate::run::finish;
use crate::settings::RunArguments;

/// A simulation that steps on request: `advance_to(t)` takes steps until the time reaches `t` (the last
/// step may end after it: steps are not shortened, so that pausing leaves the steps of one run), the
/// outputs passed collected in `results`; its state is read between calls, and `save(path)` writes a
/// checkpoint that `Simulation.resume` continues.
#[pyclass(frozen, module = "flexmb._native")]
pub struct Simulation {
    file: String,
    stepping: Mutex<Stepping>,
}

/// The engine's simulation and the outputs it reported since it was started or resumed.
struct Stepping {
    engine: Engine,
    table: OutputTable,
}

impl Simulation {
    /// A simulation of `model` with `settings`, assembled now.
    pub fn start(py: Python<'_>, model: &Model, settings: flexmb::analysis::SimulationSettings) -> PyResult<Self> {
        let engine = Arc::clone(&model.loaded.model);
        let engine = py.detach(|| Engine::new(engine, settings)).map_err(|e| crate::callable_law::start_error(py, &model.file, e))?;
        Ok(Self::holding(model, engine))
    }

    fn holding(model: &Model, engine: Engine) -> Self {
        let table = OutputTable::new(&model.loaded.model);
        Self { file: model.file.clone(), stepping: Mutex::new(Stepping { engine, table }) }
    }

    fn stepping(&self) -> PyResult<MutexGuard<'_, Stepping>> {
        self.stepping.lock().map_err(|_| PyRuntimeError::new_err("the simulation was poisoned by a panic in another thread"))
    }
}

#[pymethods]
impl Simulation {
    /// Continues the simulation saved by `save(path)` (of the same model file and integrator) to
    /// `t_end`, which may be later than the checkpoint's time; the other arguments as `Model.simulate`.
    /// Its `results` hold the rows after the checkpoint's time. Raises `ModelError` for a file that is
    /// not a checkpoint of this model and method.
    #[staticmethod]
    #[pyo3(signature = (model, path, t_end = None, integrator = None, rtol = None, atol = None, output_step = None, spectral_radius = None))]
    #[allow(clippy::too_many_arguments)]
    fn resume(
        py: Python<'_>,
        model: &Model,
        path: PathBuf,
        t_end: Option<f64>,
        integrator: Option<String>,
        rtol: Option<f64>,
        atol: Option<f64>,
        output_step: Option<f64>,
        spectral_radius: Option<f64>,
    ) -> PyResult<Self> {
        let arguments = RunArguments { t_end, output_step, rtol, atol, integrator, spectral_radius };
        let settings = arguments.settings(&model.loaded, &model.file)?;
        let engine = &model.loaded.model;
        let (engine, _) = py.detach(|| resume_simulation(engine, &settings, &path)).map_err(model_error)?;
        Ok(Self::holding(model, engine))
    }

    /// Steps until the time reaches `t` (or the end time), without the GIL; returns the time reached.
    /// Ctrl-C stops it after the current step and raises `KeyboardInterrupt` (the simulation stays
    /// usable); a failure raises `SimulationError` and ends the simulation.
    fn advance_to(&self, py: Python<'_>, t: f64) -> PyResult<f64> {
        let mut guard = self.stepping()?;
        let Stepping { engine, table } = &mut *guard;
        let (run, raised) = py.detach(|| {
            let watch = SignalWatch::new();
            let run = engine.advance_to_interruptible(t, table, &|| watch.interrupted());
            (run, watch.into_raised())
        });
        if run.is_err() || raised.is_some() {
            finish(py, &self.file, engine, table, run, raised)?;
        }
        Ok(engine.time())
    }

    /// Steps to the end time (`advance_to` the end) and returns the `results`.
    fn run(&self, py: Python<'_>) -> PyResult<Results> {
        self.advance_to(py, f64::INFINITY)?;
        self.results()
    }

    /// The time of the last accepted step (s).
    #[getter]
    fn time(&self) -> PyResult<f64> {
        Ok(self.stepping()?.engine.time())
    }

    /// The end time (s).
    #[getter]
    fn t_end(&self) -> PyResult<f64> {
        Ok(self.stepping()?.engine.settings().t_end)
    }

    /// Whether the end time is reached and its outputs reported.
    #[getter]
    fn finished(&self) -> PyResult<bool> {
        Ok(self.stepping()?.engine.is_finished())
    }

    /// The positions `q` at the last accepted step (per body: origin R, Euler parameters p, modal
    /// coordinates a), as a numpy array.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(py, self.stepping()?.engine.positions()))
    }

    /// The velocities `v` at the last accepted step (per body: Ṙ, body-frame angular velocity ω̄, modal
    /// rates ȧ), as a numpy array.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(py, self.stepping()?.engine.velocities()))
    }

    /// The outputs reported since the simulation was started (or resumed), with the summary so far.
    #[getter]
    fn results(&self) -> PyResult<Results> {
        let stepping = self.stepping()?;
        let e = &stepping.engine;
        Ok(Results::of_run(e.model(), &self.file, e.settings(), e.report(), &stepping.table, None))
    }

    /// Writes the simulation's complete state (positions, velocities, the integrator's history and step
    /// size, the counters so far) to `path` as the JSON checkpoint of `flexmb run --save-state`.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        let mut stepping = self.stepping()?;
        let checkpoint = stepping.engine.checkpoint().map_err(|e| SimulationError::new_err(format!("{}: {e}", self.file)))?;
        save_checkpoint(&path, &checkpoint).map_err(|e| PyOSError::new_err(e.0))
    }

    /// Replaces the positions and/or velocities (numpy arrays of the lengths of `positions` and
    /// `velocities`; `None` keeps them) at the current time. The positions are moved onto the
    /// constraints by the assembly's Newton iteration, the velocities projected onto the velocity
    /// constraints (both the least change), and the integrator restarts there (order 1, a new first
    /// step). Returns what the projection changed: `assembly_iterations`, `position_change`,
    /// `velocity_change` (largest changes), `position_residual`, `velocity_residual`, `energy_change`.
    /// Raises `ValueError` for a wrong length or a value that is not finite.
    #[pyo3(signature = (positions = None, velocities = None))]
    fn set_state<'py>(
        &self,
        py: Python<'py>,
        positions: Option<Vec<f64>>,
        velocities: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        crate::state_setting::set_state(py, &mut self.stepping()?.engine, positions, velocities)
    }

    /// The names of the coordinates: `{"positions": [...], "velocities": [...]}`, one per entry of
    /// `positions` and `velocities` (`<body>.R.x`, `<body>.p.0`, `<body>.a.1`; `<body>.Rdot.x`,
    /// `<body>.omega.x` in body axes, `<body>.adot.1`).
    #[getter]
    fn coordinate_names<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        crate::state_setting::coordinate_names(py, &self.stepping()?.engine)
    }

    fn __repr__(&self) -> PyResult<String> {
        let stepping = self.stepping()?;
        Ok(format!("<flexmb.Simulation of {} at t = {} s>", self.file, stepping.engine.time()))
    }
}
