//! Python in the loop: a Python callable as the law of a force element or the motion of a driver
//! (`Model.with_law`), wrapped in the library's `UserFunction` / `UserMotion`.
//!
//! The run goes on without the GIL; each call of the law takes it back (`Python::attach`), hands over
//! the time and the measures (a numpy array, in the order the law named them) and reads a float (a
//! force law) or the three floats `(f, f', f'')` (a driver). An exception raised by the law is kept
//! (on the thread that runs the simulation: the engine evaluates its laws on that thread) and the law
//! fails with its text; the run stops with `SimulationError`, whose `__cause__` is that exception.

use std::cell::RefCell;
use std::sync::Arc;

use flexmb::analysis::SimulationFailure;
use flexmb::function::{UserFunction, UserMotion};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::errors::{model_error, SimulationError};
use crate::model::Model;

thread_local! {
    /// The exception of the first law that failed in the run on this thread, until the run's error
    /// is raised.
    static RAISED: RefCell<Option<PyErr>> = const { RefCell::new(None) };
}

/// Keeps `error` (unless one is kept already) and returns the law's failure message.
fn keep(py: Python<'_>, error: PyErr) -> String {
    let message = match error.value(py).get_type().qualname() {
        Ok(kind) => format!("{kind}: {}", error.value(py)),
        Err(_) => error.value(py).to_string(),
    };
    RAISED.with(|raised| {
        raised.borrow_mut().get_or_insert(error);
    });
    message
}

/// Forgets an exception kept from an earlier run.
pub fn forget_raised() {
    RAISED.with(|raised| raised.borrow_mut().take());
}

/// `error` with the exception the law raised as its `__cause__`, when `failure` is a law's failure.
pub fn chain_cause(py: Python<'_>, error: &PyErr, failure: Option<&SimulationFailure>) {
    let raised = RAISED.with(|raised| raised.borrow_mut().take());
    if let (Some(SimulationFailure::UserLaw { .. }), Some(cause)) = (failure, raised) {
        error.set_cause(py, Some(cause));
    }
}

/// The error of a simulation that could not start: `SimulationError` (with the law's exception as its
/// cause) when a law failed, else `ModelError`.
pub fn start_error(py: Python<'_>, file: &str, error: flexmb::analysis::SimulationError) -> PyErr {
    if matches!(error.cause, SimulationFailure::UserLaw { .. }) {
        let raised = SimulationError::new_err(format!("{file}: simulation failed: {error}"));
        chain_cause(py, &raised, Some(&error.cause));
        raised
    } else {
        forget_raised();
        model_error(format!("{file}: {error}"))
    }
}

/// A force law calling `law(t, measures)` with the measures as a numpy array.
fn force_law(law: Py<PyAny>) -> Arc<flexmb::function::ForceLaw> {
    Arc::new(move |t, measures: &[f64]| {
        Python::attach(|py| {
            let values = PyArray1::from_slice(py, measures);
            let value = law.call1(py, (t, values)).and_then(|v| v.extract::<f64>(py));
            value.map_err(|e| keep(py, e))
        })
    })
}

/// A driver's motion calling `law(t)` for `(f, f', f'')`.
fn motion_law(law: Py<PyAny>) -> Arc<flexmb::function::MotionLaw> {
    Arc::new(move |t| {
        Python::attach(|py| {
            let value = law.call1(py, (t,)).and_then(|v| {
                v.extract::<(f64, f64, f64)>(py).map_err(|_| {
                    pyo3::exceptions::PyTypeError::new_err(format!(
                        "a driver's law returns (f, f', f''): the motion and its first two time derivatives, got {}",
                        v.bind(py).repr().map(|r| r.to_string()).unwrap_or_default()
                    ))
                })
            });
            value.map(|(f, df, ddf)| [f, df, ddf]).map_err(|e| keep(py, e))
        })
    })
}

/// `Model.with_law`: a copy of `model` whose force element or driver `name` has `law`.
pub fn with_law(model: &Model, name: &str, law: Py<PyAny>, measures: &[String], component: Option<&str>) -> PyResult<Model> {
    let mut engine = (*model.loaded.model).clone();
    let fail = |e: &dyn std::fmt::Display| model_error(format!("{}: {e}", model.file));
    let is_force = engine.forces().iter().any(|f| f.name == name);
    if is_force {
        let names: Vec<&str> = measures.iter().map(String::as_str).collect();
        let ids = engine.measure_ids(&names).map_err(|e| fail(&e))?;
        let component = match component {
            None => None,
            Some("x") => Some(0),
            Some("y") => Some(1),
            Some("z") => Some(2),
            Some(other) => return Err(fail(&format!("component must be \"x\", \"y\" or \"z\", got {other:?}"))),
        };
        let law = UserFunction::new(name, ids, force_law(law)).map_err(|e| fail(&e))?;
        engine.set_force_law(name, component, law).map_err(|e| fail(&e))?;
    } else {
        if !measures.is_empty() || component.is_some() {
            let forces: Vec<&str> = engine.forces().iter().map(|f| f.name.as_str()).collect();
            return Err(fail(&format!(
                "'{name}' is not a force element (the model has {}): a driver's law reads no measures and has no component",
                forces.join(", ")
            )));
        }
        engine.set_driver_motion(name, UserMotion::new(name, motion_law(law))).map_err(|e| {
            let forces: Vec<&str> = engine.forces().iter().map(|f| f.name.as_str()).collect();
            fail(&format!("{e}; force elements: {}", forces.join(", ")))
        })?;
    }
    let mut loaded = model.loaded.clone();
    loaded.model = Arc::new(engine);
    Ok(Model { loaded, file: model.file.clone() })
}
