//! The `flexmb` program's commands over the library crates: runs with progress and printed reports,
//! checks, mode analysis, linearization and eigen-analysis, comparisons and studies, plots and spectra of results, benchmarks. File
//! formats (model files, FE model files, flexible-body files, results) are in `flexmb_files`.

pub mod bench;
pub mod check;
pub mod compare;
pub mod equilibrium;
pub mod eigen;
pub mod interrupt;
pub mod limits;
pub mod linear_analysis;
pub mod modes;
pub mod parameters;
pub mod plot;
pub mod run;
pub mod spectrum;
pub mod study;
pub mod work_precision;

