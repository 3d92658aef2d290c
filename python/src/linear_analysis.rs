//! `Model.linearize` and `Model.eigen`: the library's `linear_model` (the operating point, the
//! linearization and its reduction to independent coordinates), `state_space` and `eigen_analysis`,
//! as `flexmb linearize` and `flexmb eigen` call them, with the matrices and shapes as numpy arrays.

use faer::Mat;
use flexmb::analysis::{eigen_analysis, linear_model, state_space, LinearModel, OperatingPointChoice};
use numpy::{Complex64, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::model_error;
use crate::model::Model;

/// The operating point of `at` (`"initial"` or `"equilibrium"`) or `t` (a simulated time).
fn choice(at: Option<&str>, t: Option<f64>) -> PyResult<OperatingPointChoice> {
    match (at, t) {
        (Some(_), Some(_)) => Err(model_error("give either at or t, not both")),
        (None, Some(t)) => Ok(OperatingPointChoice::Time(t)),
        (None | Some("initial"), None) => Ok(OperatingPointChoice::Initial),
        (Some("equilibrium"), None) => Ok(OperatingPointChoice::Equilibrium),
        (Some(other), None) => Err(model_error(format!("at: expected 'initial' or 'equilibrium', got '{other}'"))),
    }
}

fn linearized(py: Python<'_>, model: &Model, at: Option<&str>, t: Option<f64>) -> PyResult<LinearModel> {
    let choice = choice(at, t)?;
    let loaded = &model.loaded;
    let settings = loaded.simulation.settings(&loaded.model, loaded.simulation.assembly());
    py.detach(|| linear_model(&loaded.model, choice, &settings)).map_err(|e| model_error(format!("{}: {e}", model.file)))
}

fn array<'py>(py: Python<'py>, m: &Mat<f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let values: Vec<f64> = (0..m.nrows()).flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)])).collect();
    PyArray1::from_vec(py, values).reshape([m.nrows(), m.ncols()])
}

/// `Model.linearize`: a dict of `M`, `C`, `K`, `basis`, `coordinates`, `velocity_names`, `t`, and
/// with inputs or outputs `state_space` (`A`, `B`, `C`, `D`, `states`, `inputs`, `outputs`).
pub fn linearize<'py>(
    py: Python<'py>,
    model: &Model,
    at: Option<&str>,
    t: Option<f64>,
    inputs: Vec<String>,
    outputs: Vec<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut linear = linearized(py, model, at, t)?;
    let engine = &model.loaded.model;
    let dict = PyDict::new(py);
    dict.set_item("M", array(py, &linear.reduced.mass)?)?;
    dict.set_item("C", array(py, &linear.reduced.damping)?)?;
    dict.set_item("K", array(py, &linear.reduced.stiffness)?)?;
    dict.set_item("basis", array(py, &linear.reduced.independent.basis)?)?;
    dict.set_item("coordinates", linear.reduced.independent.names.clone())?;
    dict.set_item("velocity_names", engine.velocity_names())?;
    dict.set_item("t", linear.point.state.t)?;
    if !(inputs.is_empty() && outputs.is_empty()) {
        let LinearModel { point, reduced, .. } = &mut linear;
        let space = state_space(engine, &mut point.data, &point.state, &point.accelerations, reduced, &inputs, &outputs)
            .map_err(|e| model_error(format!("{}: {e}", model.file)))?;
        let s = PyDict::new(py);
        s.set_item("A", array(py, &space.a)?)?;
        s.set_item("B", array(py, &space.b)?)?;
        s.set_item("C", array(py, &space.c)?)?;
        s.set_item("D", array(py, &space.d)?)?;
        s.set_item("states", space.states)?;
        s.set_item("inputs", space.inputs)?;
        s.set_item("outputs", space.outputs)?;
        dict.set_item("state_space", s)?;
    }
    Ok(dict)
}

/// `Model.eigen`: a dict of `frequencies` (Hz, undamped), `damped_frequencies`, `damping_ratios`,
/// `eigenvalues` (complex), `whirl`, `rigid_body`, `shapes` (complex, modes × velocity coordinates),
/// `velocity_names`, `coordinates`, `t`.
pub fn eigen<'py>(py: Python<'py>, model: &Model, at: Option<&str>, t: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
    let linear = linearized(py, model, at, t)?;
    let engine = &model.loaded.model;
    let modes = eigen_analysis(engine, &linear.point.state, &linear.reduced).map_err(|e| model_error(format!("{}: {e}", model.file)))?;
    let m = &modes.modes;
    let nv = engine.layout().nv;
    let dict = PyDict::new(py);
    dict.set_item("frequencies", PyArray1::from_vec(py, m.iter().map(|x| x.frequency).collect()))?;
    dict.set_item("damped_frequencies", PyArray1::from_vec(py, m.iter().map(|x| x.damped_frequency).collect()))?;
    dict.set_item("damping_ratios", PyArray1::from_vec(py, m.iter().map(|x| x.damping_ratio).collect()))?;
    dict.set_item("eigenvalues", PyArray1::from_vec(py, m.iter().map(|x| Complex64::new(x.eigenvalue.0, x.eigenvalue.1)).collect()))?;
    dict.set_item("whirl", m.iter().map(|x| x.whirl.label()).collect::<Vec<_>>())?;
    dict.set_item("rigid_body", m.iter().map(|x| x.rigid_body).collect::<Vec<_>>())?;
    let shapes: Vec<Complex64> = m.iter().flat_map(|x| x.shape_re.iter().zip(&x.shape_im).map(|(a, b)| Complex64::new(*a, *b))).collect();
    dict.set_item("shapes", PyArray1::from_vec(py, shapes).reshape([m.len(), nv])?)?;
    dict.set_item("velocity_names", engine.velocity_names())?;
    dict.set_item("coordinates", linear.reduced.independent.names.clone())?;
    dict.set_item("t", linear.point.state.t)?;
    Ok(dict)
}
