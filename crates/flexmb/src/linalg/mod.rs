//! Global (sparse) linear algebra on top of `faer`.

mod sparse_lu;

pub use sparse_lu::{SingularMatrix, SparseLu};
