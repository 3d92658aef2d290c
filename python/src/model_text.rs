//! `flexmb.loads`: a model from the text of a model file in memory — what `flexmb.ModelBuilder.build`
//! hands over — through the loader of model files (`flexmb_files::model_file::parse_model_with`), so
//! its validation and messages are the file's.

use std::collections::HashMap;
use std::path::PathBuf;

use flexmb_files::model_file::parse_model_with;
use pyo3::prelude::*;

use crate::errors::model_error;
use crate::model::{load_options, Model};

/// Loads a model from `text`, the text of a model file: `source` names it in messages (the `file` of
/// `file:line: key: message`), relative `fe_model` and `body_file` paths start at `base_dir` (default
/// the current directory); `parameters` and `modes` as in `load`. Raises `ModelError`.
#[pyfunction]
#[pyo3(signature = (text, source = "<string>".to_string(), base_dir = None, parameters = None, modes = None))]
pub fn loads(
    py: Python<'_>,
    text: String,
    source: String,
    base_dir: Option<PathBuf>,
    parameters: Option<HashMap<String, f64>>,
    modes: Option<HashMap<String, String>>,
) -> PyResult<Model> {
    let options = load_options(parameters, modes);
    let base_dir = base_dir.unwrap_or_default();
    let loaded = py.detach(|| parse_model_with(&text, &source, &base_dir, &options)).map_err(model_error)?;
    Ok(Model { loaded, file: source })
}
