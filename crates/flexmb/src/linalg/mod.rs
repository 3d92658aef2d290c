//! Global (sparse) linear algebra on top of `faer`, and the colouring and steps of finite-difference
//! Jacobians.

mod colouring;
mod dense_lu;
mod finite_difference;
mod sparse_lu;

pub use colouring::greedy_colouring;
pub use finite_difference::{perturbation, RELATIVE_STEP};
pub use sparse_lu::{SingularMatrix, SparseLu, DENSE_LIMIT};
