//! The `flexmb` program's commands over the library crates: runs with progress and printed reports,
//! checks, mode analysis, comparisons and studies, plots and spectra of results, benchmarks. File
//! formats (model files, FE model files, flexible-body files, results) are in `flexmb_files`.

pub mod bench;
pub mod check;
pub mod compare;
pub mod equilibrium;
pub mod interrupt;
pub mod limits;
pub mod modes;
pub mod parameters;
pub mod plot;
pub mod run;
pub mod spectrum;
pub mod study;

