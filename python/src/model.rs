//! `flexmb.load` and `flexmb.Model`: a model file loaded with parameter overrides, checked, and the
//! starting point of runs and simulations.

use std::collections::HashMap;
use std::path::PathBuf;

use flexmb::analysis::check_model;
use flexmb_files::model_file::{basis_name, LoadOptions, ModelOverrides};
use flexmb_files::{load_model_with, LoadedModel};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::model_error;
use crate::results::Results;
use crate::run::simulate;
use crate::settings::RunArguments;
use crate::simulation::Simulation;

/// A mechanism loaded from a model file: its bodies, joints, force elements and outputs, with the file's
/// `[simulation]` values as the defaults of its runs.
#[pyclass(frozen, module = "flexmb._native")]
pub struct Model {
    pub(crate) loaded: LoadedModel,
    /// The model file as given, as messages name it.
    pub(crate) file: String,
}

/// Loads the model file at `path`, with `parameters` (name → value) replacing the values of its
/// `[parameters]` table and `modes` (flexible body → mode set) the mode sets of its flexible bodies, as a
/// study's variants do. Raises `ModelError` with the command line's message.
#[pyfunction]
#[pyo3(signature = (path, parameters = None, modes = None))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    parameters: Option<HashMap<String, f64>>,
    modes: Option<HashMap<String, String>>,
) -> PyResult<Model> {
    let options = load_options(parameters, modes);
    let file = path.display().to_string();
    let loaded = py.detach(|| load_model_with(&path, &options)).map_err(model_error)?;
    Ok(Model { loaded, file })
}

/// The load options of `parameters` and `modes` (in name order, so that a load does not depend on a
/// dict's order).
pub(crate) fn load_options(parameters: Option<HashMap<String, f64>>, modes: Option<HashMap<String, String>>) -> LoadOptions {
    let mut parameters: Vec<(String, f64)> = parameters.unwrap_or_default().into_iter().collect();
    parameters.sort_by(|a, b| a.0.cmp(&b.0));
    let mut modes: Vec<(String, String)> = modes.unwrap_or_default().into_iter().collect();
    modes.sort();
    LoadOptions { overrides: ModelOverrides { modes, parameters, ..Default::default() }, ..Default::default() }
}

#[pymethods]
impl Model {
    /// The model's name.
    #[getter]
    fn name(&self) -> &str {
        self.loaded.model.name()
    }

    /// The model file, as given to `load`.
    #[getter]
    fn file(&self) -> &str {
        &self.file
    }

    /// The values of the file's `[parameters]` (name → value), overrides applied.
    #[getter]
    fn parameters(&self) -> std::collections::BTreeMap<String, f64> {
        self.loaded.parameters.clone()
    }

    /// The names of the output columns of a run, `t` first, as in the result CSV of `flexmb run`.
    #[getter]
    fn columns(&self) -> Vec<String> {
        std::iter::once("t".to_string())
            .chain(flexmb::analysis::output_columns(&self.loaded.model).into_iter().map(|c| c.name))
            .collect()
    }

    /// The file's `[simulation]` values that a run uses unless told otherwise: `t_end`, `output_step`,
    /// `rtol`, `atol`.
    #[getter]
    fn defaults<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = &self.loaded.simulation;
        let dict = PyDict::new(py);
        dict.set_item("t_end", d.t_end)?;
        dict.set_item("output_step", d.output_step)?;
        dict.set_item("rtol", d.rtol)?;
        dict.set_item("atol", d.atol)?;
        Ok(dict)
    }

    /// Assembles the initial state and runs the velocity analysis, as `flexmb check` does; returns a
    /// dict: `degrees_of_freedom`, `redundant_constraints` (their descriptions), the `bodies`, `joints`
    /// and `force_elements` by name, `markers` and `constraint_equations` counted, the `assembly`
    /// (iterations, initial and final residual), `velocity_adjustments`, and `flexible_bodies` (name,
    /// mode set, basis, mode labels, frequencies in Hz, nodes). Raises `ModelError` when the model cannot
    /// be assembled.
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let model = &self.loaded.model;
        let settings = self.loaded.simulation.assembly();
        let report = py.detach(|| check_model(model, settings)).map_err(|e| model_error(format!("{}: {e}", self.file)))?;
        let names = |items: Vec<&str>| items.into_iter().map(str::to_string).collect::<Vec<_>>();
        let dict = PyDict::new(py);
        dict.set_item("model", model.name())?;
        dict.set_item("degrees_of_freedom", report.assembly.degrees_of_freedom)?;
        let redundant: Vec<&str> = report.assembly.redundant.iter().map(|r| r.description.as_str()).collect();
        dict.set_item("redundant_constraints", names(redundant))?;
        dict.set_item("bodies", names(model.bodies().iter().map(|b| b.name.as_str()).collect()))?;
        dict.set_item("joints", names(model.joints().iter().map(|j| j.name.as_str()).collect()))?;
        dict.set_item("force_elements", names(model.forces().iter().map(|f| f.name.as_str()).collect()))?;
        dict.set_item("markers", model.markers().len())?;
        dict.set_item("constraint_equations", model.layout().nc)?;
        let assembly = PyDict::new(py);
        assembly.set_item("iterations", report.assembly.iterations)?;
        assembly.set_item("initial_residual", report.assembly.initial_residual)?;
        assembly.set_item("residual", report.assembly.residual)?;
        dict.set_item("assembly", assembly)?;
        let adjusted: Vec<String> = report.velocity.adjusted.iter().map(ToString::to_string).collect();
        dict.set_item("velocity_adjustments", adjusted)?;
        let mut flexible = Vec::new();
        for info in &self.loaded.flexible_bodies {
            let body = PyDict::new(py);
            body.set_item("name", &info.name)?;
            body.set_item("mode_set", &info.mode_set)?;
            body.set_item("basis", basis_name(info.basis))?;
            body.set_item("modes", &info.mode_labels)?;
            body.set_item("frequencies_hz", &info.frequencies_hz)?;
            body.set_item("nodes", info.nodes)?;
            body.set_item("warnings", &info.warnings)?;
            flexible.push(body);
        }
        dict.set_item("flexible_bodies", flexible)?;
        Ok(dict)
    }

    /// The static equilibrium at time `t` (default: the start time) with gravity, springs, loads and
    /// drivers held there, as `flexmb equilibrium` finds it (Newton with a line search, damped dynamic
    /// relaxation as fallback). Returns a dict: `positions` (numpy, per body `R, p, a`) and
    /// `position_names`, `multipliers`, `reactions` (one dict per joint side: `joint`, `body`,
    /// `marker`, `point`, `force`, `torque`, global axes), `outputs` (column → value there),
    /// `iterations`, `method`, `force_residual`, `constraint_residual`, `force_tolerance`, `history`,
    /// `degrees_of_freedom`, `neutral_directions`, `unstable_directions`, `t`. A mechanism with no
    /// equilibrium raises `ModelError` naming the free motion.
    #[pyo3(signature = (t = None))]
    fn equilibrium<'py>(&self, py: Python<'py>, t: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        crate::equilibrium::equilibrium(py, self, t)
    }

    /// Linearizes the model at an operating point (`at="initial"`, the assembled initial state with its
    /// velocities; `at="equilibrium"`; or `t`, the state a simulation reaches at that time) and returns a
    /// dict: `M`, `C`, `K` (numpy, independent coordinates), `basis` (the velocity-space motion of each
    /// independent coordinate), `coordinates` (their names), `velocity_names`, `t`; with `inputs` (force
    /// elements: `NAME.x`/`.y`/`.z` of an applied force or torque, `NAME` of a spring-damper; drivers:
    /// `NAME`, `NAME.rate`, `NAME.acceleration` for the offset of an angle or displacement driver) or
    /// `outputs` (measures) also `state_space`: `A`, `B`, `C`, `D`, `states`, `inputs`, `outputs`. As
    /// `flexmb linearize`; raises `ModelError` with its message.
    #[pyo3(signature = (at = None, t = None, inputs = None, outputs = None))]
    fn linearize<'py>(
        &self,
        py: Python<'py>,
        at: Option<&str>,
        t: Option<f64>,
        inputs: Option<Vec<String>>,
        outputs: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        crate::linear_analysis::linearize(py, self, at, t, inputs.unwrap_or_default(), outputs.unwrap_or_default())
    }

    /// Eigen-analysis at an operating point (as `linearize`): a dict of `frequencies` (Hz, undamped
    /// natural), `damped_frequencies`, `damping_ratios`, `eigenvalues` (complex), `whirl` (`forward`,
    /// `backward`, `none`), `rigid_body`, `shapes` (complex numpy, modes × velocity coordinates),
    /// `velocity_names`, `coordinates`, `t`. As `flexmb eigen`; raises `ModelError` with its message.
    #[pyo3(signature = (at = None, t = None))]
    fn eigen<'py>(&self, py: Python<'py>, at: Option<&str>, t: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        crate::linear_analysis::eigen(py, self, at, t)
    }

    /// Simulates the model from its initial state to `t_end` and returns the outputs as `Results`.
    /// Each argument left `None` takes the model file's `[simulation]` value; `integrator` is `"bdf"`,
    /// `"adams"` or `"gen-alpha"` (with `spectral_radius`, default 0.8). The native work runs without the
    /// GIL; Ctrl-C stops it after the current step and raises `KeyboardInterrupt`, whose `results`
    /// attribute holds the rows computed until then. A failure raises `SimulationError` (the rows before
    /// it in its `results`).
    #[pyo3(signature = (t_end = None, integrator = None, rtol = None, atol = None, output_step = None, spectral_radius = None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate(
        &self,
        py: Python<'_>,
        t_end: Option<f64>,
        integrator: Option<String>,
        rtol: Option<f64>,
        atol: Option<f64>,
        output_step: Option<f64>,
        spectral_radius: Option<f64>,
    ) -> PyResult<Results> {
        let arguments = RunArguments { t_end, output_step, rtol, atol, integrator, spectral_radius };
        simulate(py, self, &arguments.settings(&self.loaded, &self.file)?)
    }

    /// A `Simulation` of the model that steps on request (`advance_to`), with the same arguments as
    /// `simulate`; assembles the initial state now (`ModelError` if it cannot).
    #[pyo3(signature = (t_end = None, integrator = None, rtol = None, atol = None, output_step = None, spectral_radius = None))]
    #[allow(clippy::too_many_arguments)]
    fn simulation(
        &self,
        py: Python<'_>,
        t_end: Option<f64>,
        integrator: Option<String>,
        rtol: Option<f64>,
        atol: Option<f64>,
        output_step: Option<f64>,
        spectral_radius: Option<f64>,
    ) -> PyResult<Simulation> {
        let arguments = RunArguments { t_end, output_step, rtol, atol, integrator, spectral_radius };
        Simulation::start(py, self, arguments.settings(&self.loaded, &self.file)?)
    }

    /// A copy of the model whose force element or driver `name` takes its law from the Python
    /// callable `law` (Python in the loop). A force element's law is `law(t, measures) -> float`,
    /// `measures` a numpy array of the values of the measures named in `measures`, in that order: the
    /// actuator of a spring-damper, or the `component` ("x", "y", "z") of an applied force or torque. A
    /// driver's law is `law(t) -> (f, f', f'')`, the motion with its first two time derivatives. An
    /// exception in the law stops the run with `SimulationError` (the exception its `__cause__`).
    #[pyo3(signature = (name, law, measures = Vec::new(), component = None))]
    fn with_law(&self, name: &str, law: Py<PyAny>, measures: Vec<String>, component: Option<String>) -> PyResult<Model> {
        crate::callable_law::with_law(self, name, law, &measures, component.as_deref())
    }

    /// The names of the laws given as Python callables (`with_law`), force elements then drivers.
    #[getter]
    fn laws(&self) -> Vec<String> {
        self.loaded.model.user_laws().into_iter().map(str::to_string).collect()
    }

    fn __repr__(&self) -> String {
        format!("<flexmb.Model '{}' from {}>", self.loaded.model.name(), self.file)
    }
}
