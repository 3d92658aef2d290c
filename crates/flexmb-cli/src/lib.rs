//! flexmb command-line layer: model files, simulation runs, results.

pub mod model_file;

pub use model_file::{load_model, parse_model, LoadedModel, ModelFileError, SimulationDefaults};
