#![warn(missing_docs)]

//! flexmb's files: what a program or a binding calls to load a mechanism, run it and keep its results.
//!
//! - [`model_file`]: model files (TOML, `docs/model-file.md`) with parameter overrides, built into a
//!   [`flexmb::Model`] plus its `[simulation]` settings ([`load_model`], [`load_model_with`]);
//! - [`fe_model_file`]: FE model files (`docs/fe-model-file.md`) for the preprocessor, and
//!   [`flexible_body`], the reduced flexible body turned into the engine's modal body;
//! - [`results`]: a run recorded to a result CSV and a JSON summary ([`record_model_run`]), with the
//!   stress hot spots of its flexible bodies ([`body_stress`]), and
//!   [`result_table`], a result CSV read back into named columns; [`restart`]: a run's checkpoint saved
//!   and resumed;
//! - [`vtk`]: ParaView files of a run and of mode shapes; [`shape`]: what they draw for rigid bodies;
//! - [`study_file`]: study files (a model in several variants, each with several integrators);
//! - [`output_limits`]: how many rows and frames a run may write; [`integrator_choice`]: integrators by
//!   name.
//!
//! The `flexmb` program is a thin layer over these calls: `flexmb run` is [`load_model`], the engine's
//! assembly check, [`record_model_run`], and printing.
//!
//! How a binding loads, runs and reads a model: the shipped pendulum with its rod 2 m long instead of
//! 1 m, run for one second into a table in memory, its swing angle read back by column name.
//!
//! ```
//! use flexmb::analysis::{OutputTable, Simulation};
//! use flexmb_files::{load_model_with, LoadOptions};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/pendulum.toml");
//! let mut options = LoadOptions::default();
//! options.overrides.parameters.push(("L".into(), 2.0));
//! let loaded = load_model_with(std::path::Path::new(path), &options)?;
//! let mut settings = loaded.simulation.settings(&loaded.model, loaded.simulation.assembly());
//! settings.t_end = 1.0;
//! let mut simulation = Simulation::new(loaded.model.clone(), settings)?;
//! let mut table = OutputTable::new(&loaded.model);
//! simulation.run(&mut table, &|| None)?;
//! let angle = table.column("pivot_angle").ok_or("no column pivot_angle")?;
//! assert_eq!(angle.len(), 101); // t = 0, 0.01, …, 1 s
//! assert!((angle[0] - std::f64::consts::FRAC_PI_3).abs() < 1e-9, "released 60° out");
//! assert!(angle[100] < angle[0], "swinging back");
//! # Ok(())
//! # }
//! ```

pub mod body_stress;
pub mod exported_matrices;
pub mod fe_model_file;
pub mod flexible_body;
pub mod integrator_choice;
pub mod matrix_market;
pub mod model_file;
pub mod output_limits;
pub mod restart;
pub mod result_table;
pub mod results;
pub mod shape;
pub mod study_file;
pub mod vtk;

pub use model_file::{load_model, load_model_with, parse_model, LoadOptions, LoadedModel, ModelFileError, SimulationDefaults};
pub use restart::{read_checkpoint, resume_simulation, save_checkpoint, Restart};
pub use result_table::ResultTable;
pub use results::{record_model_run, RecordedRun, ResultFileError, RunOutputs};
