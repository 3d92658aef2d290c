//! flexmb command-line layer: model files, FE model files, simulation runs, mode analysis, results
//! (CSV, JSON, VTK), benchmarks.

pub mod bench;
pub mod check;
pub mod compare;
pub mod fe_model_file;
pub mod flexible_body;
pub mod integrator_choice;
pub mod interrupt;
pub mod limits;
pub mod model_file;
pub mod modes;
pub mod output_limits;
pub mod plot;
pub mod results;
pub mod run;
pub mod shape;
pub mod spectrum;
pub mod study;
pub mod vtk;

pub use model_file::{load_model, parse_model, LoadedModel, ModelFileError, SimulationDefaults};
