//! The package's exceptions: a model that cannot be loaded, checked or set up raises `ModelError`
//! (a `ValueError`), a simulation that fails on the way raises `SimulationError` (a `RuntimeError`);
//! both carry the message the command line prints (file, key path, line).

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::PyErr;

create_exception!(
    flexmb,
    ModelError,
    PyValueError,
    "A model file that cannot be read, parsed, validated, built or assembled, or run settings that \
     cannot be used; the message is the command line's (file, key path, line)."
);

create_exception!(
    flexmb,
    SimulationError,
    PyRuntimeError,
    "A simulation that failed after it started; the message is the command line's, and the attribute \
     `results` holds the output rows computed before the failure."
);

/// A `ModelError` with `message`.
pub fn model_error(message: impl std::fmt::Display) -> PyErr {
    ModelError::new_err(message.to_string())
}
