//! `flexmb.modes` and `flexmb.FlexibleBody`: the preprocessor of `flexmb modes` — an FE model file
//! reduced to a mode set (`flexmb_files::fe_model_file::reduce_fe_model_file`, the call the program
//! makes) — with frequencies, mode shapes and mass properties as numpy arrays, and the flexible-body
//! file it writes.

use std::path::PathBuf;

use flexmb_fem::modes::{EigenSettings, EigenSolver};
use flexmb_fem::reduction::{Basis, FlexibleBody as ReducedBody, ModeKind, ModeSet};
use flexmb_fem::MassModel;
use flexmb_files::fe_model_file::{reduce_fe_model_file, ReduceFileError, ReducedFeModel, ReductionRequest};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use crate::errors::model_error;

/// A flexible body reduced from an FE model: its modes (labels, kinds, frequencies, shapes at the
/// nodes), its mass properties, and the flexible-body file a model's `[[flexible_body]]` reads
/// (`body_file`), written by `write`.
#[pyclass(frozen, module = "flexmb._native")]
pub struct FlexibleBody {
    body: ReducedBody,
    warnings: Vec<String>,
    seconds: f64,
}

/// Reduces the FE model file `fe_model` (TOML or an Abaqus/CalculiX `.inp` mesh) to the mode set
/// `modes` (e.g. `"4N5S"`: 4 vibration and 5 static correction modes), as `flexmb modes` does; each
/// argument left `None` takes the file's value (`[modes] set`, `[modes] basis` else `"orthonormal"`,
/// `[fe_model] mass` else consistent for beams and solids, lumped for shells). `basis` is `"raw"` or `"orthonormal"`, `mass` `"lumped"` or
/// `"consistent"`, `solver` `"auto"`, `"dense"` or `"lanczos"`; `stresses` stores each mode's stresses
/// (`flexmb modes --stresses`; `None`: the file's `[modes] stresses`). With `path`, also writes the
/// flexible-body file there. Returns a `FlexibleBody`; raises `ModelError` with the program's message.
#[pyfunction]
#[pyo3(signature = (fe_model, modes = None, basis = None, mass = None, solver = None, path = None, stresses = None))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments, one Rust argument each
pub fn modes(
    py: Python<'_>,
    fe_model: PathBuf,
    modes: Option<String>,
    basis: Option<String>,
    mass: Option<String>,
    solver: Option<String>,
    path: Option<PathBuf>,
    stresses: Option<bool>,
) -> PyResult<FlexibleBody> {
    let mode_set = match modes {
        Some(text) => Some(text.parse::<ModeSet>().map_err(|e| model_error(format!("modes: {e}")))?),
        None => None,
    };
    let basis = match basis.as_deref() {
        None => None,
        Some("raw") => Some(Basis::Raw),
        Some("orthonormal") => Some(Basis::Orthonormal),
        Some(other) => return Err(model_error(format!("basis: expected \"raw\" or \"orthonormal\", got {other:?}"))),
    };
    let mass = match mass.as_deref() {
        None => None,
        Some("lumped") => Some(MassModel::Lumped),
        Some("consistent") => Some(MassModel::Consistent),
        Some(other) => return Err(model_error(format!("mass: expected \"lumped\" or \"consistent\", got {other:?}"))),
    };
    let solver = match solver.as_deref() {
        None | Some("auto") => EigenSolver::Auto,
        Some("dense") => EigenSolver::Dense,
        Some("lanczos") => EigenSolver::Lanczos,
        Some(other) => return Err(model_error(format!("solver: expected \"auto\", \"dense\" or \"lanczos\", got {other:?}"))),
    };
    let memory_limit = flexmb::analysis::MemoryLimit::Available.bytes();
    let request = ReductionRequest { mode_set, basis, mass, eigen: EigenSettings { solver, memory_limit, ..Default::default() }, stresses };
    let reduced = py.detach(|| reduce_fe_model_file(&fe_model, &request)).map_err(|e| match e {
        ReduceFileError::NoModeSet { file } => {
            model_error(format!("{file}: no mode set: give modes= (e.g. \"6N\", \"5S\" or \"4N5S\") or `set` in the file's [modes] table"))
        }
        other => model_error(other),
    })?;
    let ReducedFeModel { loaded, reduction, seconds } = reduced;
    let warnings = loaded.warnings.iter().chain(&reduction.warnings).cloned().collect();
    let body = FlexibleBody { body: reduction.body, warnings, seconds };
    if let Some(path) = path {
        body.write(path)?;
    }
    Ok(body)
}

#[pymethods]
impl FlexibleBody {
    /// The body's name: the FE model's `[fe_model] name`, else its file name without extension.
    #[getter]
    fn name(&self) -> &str {
        &self.body.name
    }

    /// The mode set, e.g. `"4N5S"`.
    #[getter]
    fn mode_set(&self) -> &str {
        &self.body.mode_set
    }

    /// `"raw"` (the modes as computed) or `"orthonormal"` (mass-orthonormalized).
    #[getter]
    fn basis(&self) -> &'static str {
        flexmb_files::model_file::basis_name(self.body.basis)
    }

    /// The FE model's mass: `"lumped"`, `"consistent"` or `"mixed"` (consistent beams or solids with
    /// lumped shells).
    #[getter]
    fn mass_model(&self) -> &'static str {
        self.body.mass.name()
    }

    /// The mode labels in basis order: `N1`, `N2`, … vibration modes, `S1`, … static correction modes,
    /// `O1`, … orthonormalized modes.
    #[getter]
    fn labels(&self) -> Vec<String> {
        self.body.modes.iter().map(|m| m.label.clone()).collect()
    }

    /// Each mode's kind: `"vibration"`, `"static"` or `"orthonormal"`.
    #[getter]
    fn kinds(&self) -> Vec<&'static str> {
        let kind = |k: ModeKind| match k {
            ModeKind::Vibration => "vibration",
            ModeKind::Static => "static",
            ModeKind::Orthonormal => "orthonormal",
        };
        self.body.modes.iter().map(|m| kind(m.kind)).collect()
    }

    /// The natural frequencies of the reduced body (Hz), ascending: the column `reduced f [Hz]` of
    /// `flexmb modes`.
    #[getter]
    fn frequencies<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.body.reduced_frequencies_hz)
    }

    /// The lowest natural frequencies of the supported FE model (Hz), ascending: the column
    /// `FE f [Hz]` of `flexmb modes`.
    #[getter]
    fn fe_frequencies<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.body.fe_frequencies_hz)
    }

    /// The FE model's node ids (labels), in the order of the rows of `node_positions` and `mode_shapes`.
    #[getter]
    fn node_ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        PyArray1::from_vec(py, self.body.nodes.iter().map(|n| n.label).collect())
    }

    /// The nodes' positions in the body frame (m): nodes × 3.
    #[getter]
    fn node_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let values: Vec<f64> = self.body.nodes.iter().flat_map(|n| [n.position.x, n.position.y, n.position.z]).collect();
        PyArray1::from_vec(py, values).reshape([self.body.nodes.len(), 3])
    }

    /// The mode shapes at the nodes: nodes × 6 × modes, the 6 being the translations x, y, z and the
    /// rotations about x, y, z of the node in the body frame for a unit modal coordinate.
    #[getter]
    fn mode_shapes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (nodes, modes) = (self.body.nodes.len(), self.body.shapes.len());
        let mut values = vec![0.0; nodes * 6 * modes];
        for (k, shape) in self.body.shapes.iter().enumerate() {
            for node in 0..nodes {
                for axis in 0..3 {
                    values[(node * 6 + axis) * modes + k] = shape.translation[node][axis];
                    values[(node * 6 + 3 + axis) * modes + k] = shape.rotation[node][axis];
                }
            }
        }
        Ok(PyArray1::from_vec(py, values).reshape([nodes, 6, modes])?.into_any())
    }

    /// The mass of the undeformed body (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.body.mass_properties.mass
    }

    /// The centre of mass of the undeformed body in the body frame (m): 3 values.
    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.body.mass_properties.center_of_mass.as_slice())
    }

    /// The inertia tensor about the centre of mass, body axes (kg m²): 3 × 3.
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let i = &self.body.mass_properties.inertia;
        let rows: Vec<f64> = (0..3).flat_map(|r| (0..3).map(move |c| i[(r, c)])).collect();
        PyArray1::from_vec(py, rows).reshape([3, 3])
    }

    /// The modal mass matrix `ΦᵀMΦ` (modes × modes).
    #[getter]
    fn modal_mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        square(py, &self.body.modal_mass)
    }

    /// The modal stiffness matrix `ΦᵀKΦ` (modes × modes).
    #[getter]
    fn modal_stiffness<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        square(py, &self.body.modal_stiffness)
    }

    /// The FE model's and the reduction's warnings (rigid modes found, loads balanced by inertia
    /// relief, a nearly dependent basis, …).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The wall time of the reduction (s).
    #[getter]
    fn seconds(&self) -> f64 {
        self.seconds
    }

    /// Writes the flexible-body file (JSON) to `path`, as `flexmb modes --out` does; a model file reads
    /// it with `body_file` in a `[[flexible_body]]` table. Raises `OSError` if it cannot be written.
    fn write(&self, path: PathBuf) -> PyResult<()> {
        self.body.write(&path).map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))
    }

    fn __repr__(&self) -> String {
        format!("<flexmb.FlexibleBody '{}' {} ({} basis), {} nodes>", self.body.name, self.body.mode_set, self.basis(), self.body.nodes.len())
    }
}

/// A square matrix as a 2-D numpy array, row by row.
fn square<'py>(py: Python<'py>, m: &nalgebra::DMatrix<f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = m.nrows();
    PyArray1::from_vec(py, m.transpose().as_slice().to_vec()).reshape([n, m.ncols()])
}
