//! `Model.equilibrium`: the library's `static_equilibrium` (as `flexmb equilibrium` calls it), with
//! the positions, multipliers, reactions and output values as numpy arrays and dicts.

use flexmb::analysis::{equilibrium_outputs, output_columns, static_equilibrium, EquilibriumSettings, Start, State};
use flexmb::Data;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::model_error;
use crate::model::Model;

/// `Model.equilibrium`: a dict of `positions`, `position_names`, `multipliers`, `reactions`, `outputs`,
/// `iterations`, `method`, `force_residual`, `constraint_residual`, `force_tolerance`, `history`,
/// `degrees_of_freedom`, `neutral_directions`, `unstable_directions`, `t`.
pub fn equilibrium<'py>(py: Python<'py>, model: &Model, t: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
    let loaded = &model.loaded;
    let engine = &loaded.model;
    let simulation = loaded.simulation.settings(engine, loaded.simulation.assembly());
    let settings = match simulation.start {
        Start::Equilibrium(s) => s,
        Start::Assembly => EquilibriumSettings { assembly: simulation.assembly, ..Default::default() },
    };
    let (state, report, outputs) = py
        .detach(|| {
            let mut data = Data::new(engine);
            let mut state = State::initial(engine);
            let t = t.unwrap_or(state.t);
            let report = static_equilibrium(engine, &mut data, &mut state, t, &settings).map_err(|e| e.to_string())?;
            let outputs = equilibrium_outputs(engine, &mut data, &state, &report.multipliers).map_err(|e| e.to_string())?;
            Ok((state, report, outputs))
        })
        .map_err(|e: String| model_error(format!("{}: {e}", model.file)))?;
    let dict = PyDict::new(py);
    dict.set_item("t", state.t)?;
    dict.set_item("positions", PyArray1::from_vec(py, state.q.clone()))?;
    dict.set_item("position_names", engine.position_names())?;
    dict.set_item("multipliers", PyArray1::from_vec(py, report.multipliers.clone()))?;
    let reactions = PyList::empty(py);
    for reaction in &report.reactions {
        for side in &reaction.sides {
            let row = PyDict::new(py);
            row.set_item("joint", &reaction.joint)?;
            row.set_item("body", &side.body)?;
            row.set_item("marker", &side.marker)?;
            row.set_item("point", PyArray1::from_slice(py, &side.point))?;
            row.set_item("force", PyArray1::from_slice(py, &side.force))?;
            row.set_item("torque", PyArray1::from_slice(py, &side.torque))?;
            reactions.append(row)?;
        }
    }
    dict.set_item("reactions", reactions)?;
    let values = PyDict::new(py);
    for (column, value) in output_columns(engine).iter().zip(&outputs) {
        values.set_item(&column.name, value)?;
    }
    dict.set_item("outputs", values)?;
    dict.set_item("iterations", report.iterations)?;
    dict.set_item("method", report.method.name())?;
    dict.set_item("force_residual", report.force_residual)?;
    dict.set_item("constraint_residual", report.constraint_residual)?;
    dict.set_item("force_tolerance", report.force_tolerance)?;
    let history: Vec<(&str, f64, f64)> = report.history.iter().map(|h| (h.method.name(), h.force_residual, h.constraint_residual)).collect();
    dict.set_item("history", history)?;
    dict.set_item("degrees_of_freedom", report.degrees_of_freedom)?;
    dict.set_item("neutral_directions", report.neutral_directions)?;
    dict.set_item("unstable_directions", report.unstable_directions)?;
    Ok(dict)
}
