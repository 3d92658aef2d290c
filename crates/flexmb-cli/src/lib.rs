//! flexmb command-line layer: model files, simulation runs, results, benchmarks.

pub mod bench;
pub mod check;
pub mod fe_model_file;
pub mod model_file;
pub mod results;
pub mod run;

pub use model_file::{load_model, parse_model, LoadedModel, ModelFileError, SimulationDefaults};
