//! Global (sparse) linear algebra on top of `faer`, and the colouring and steps of finite-difference
//! Jacobians.

mod colouring;
mod dense_lu;
mod finite_difference;
mod sparse_lu;

pub use colouring::greedy_colouring;
pub use finite_difference::{perturbation, RELATIVE_STEP};
pub use sparse_lu::SingularMatrix;
// The integrators' workspace: its callers build the pattern from a model's layout, so its checks are
// the engine's invariants, not a user's input.
pub(crate) use sparse_lu::SparseLu;
