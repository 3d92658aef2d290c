//! The shipped models (`models/`) the benchmarks run, read from the checkout the program was built
//! from.

use std::path::{Path, PathBuf};

use flexmb::Model;
use flexmb_files::model_file::{load_model_with, LoadOptions};
use flexmb_files::SimulationDefaults;

/// The path of a shipped model, `path` relative to `models/`.
pub fn shipped(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models").join(path)
}

/// The shipped model at `path` (relative to `models/`) with `options`, and its file's `[simulation]`.
pub fn load_shipped(path: &str, options: &LoadOptions) -> Result<(Model, SimulationDefaults), String> {
    let path = shipped(path);
    let loaded = load_model_with(&path, options).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok((std::sync::Arc::unwrap_or_clone(loaded.model), loaded.simulation))
}
