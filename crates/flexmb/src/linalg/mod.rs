//! Global (sparse) linear algebra on top of `faer` (LU of the iteration matrices, the Cholesky factor of
//! `B Bᵀ` for a sparse `B`, a rank-revealing QR by Givens rotations, the normal equations of minimum-norm
//! corrections), and the colouring and steps of finite-difference Jacobians.

mod colouring;
mod dense_lu;
mod finite_difference;
mod givens_qr;
mod gram_cholesky;
mod lu_refactorization;
mod normal_equations;
mod sparse_lu;
mod sparse_rows;
mod threshold_pivoting;

pub use colouring::greedy_colouring;
pub use finite_difference::{perturbation, RELATIVE_STEP};
pub use sparse_lu::SingularMatrix;
pub(crate) use sparse_lu::KEPT_PIVOTS_DENSE_LIMIT;
// The integrators' workspace: its callers build the pattern from a model's layout, so its checks are
// the engine's invariants, not a user's input.
pub(crate) use lu_refactorization::InvalidPivots;
pub(crate) use sparse_lu::SparseLu;
// The Adams method's partition: the dependent coordinates by sparse elimination with threshold full
// pivoting and Markowitz's choice.
pub(crate) use threshold_pivoting::{threshold_pivoting, PARTITION_THRESHOLD};
// The initial-condition analyses' sparse Jacobians, their rank and their minimum-norm corrections.
pub(crate) use givens_qr::dependent_rows;
// The conditioning of the constraint Jacobian in force (the singular-position guard).
pub(crate) use gram_cholesky::GramCholesky;
pub(crate) use normal_equations::{solve_normal_equations, NormalEquations};
pub(crate) use sparse_rows::SparseRows;
