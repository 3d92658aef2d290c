//! Global (sparse) linear algebra on top of `faer`.

mod dense_lu;
mod sparse_lu;

pub use sparse_lu::{SingularMatrix, SparseLu, DENSE_LIMIT};
