//! Sparse path: faer's Krylov–Schur (thick-restart Lanczos for a symmetric operator) on the
//! shift-invert operator, whose largest eigenvalues are the lowest frequencies.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::matrix_free::eigen::{partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch, PartialEigenParams};
use faer::{Col, Mat, Par};

use super::shift_invert::ShiftInvert;
use crate::error::FemError;

/// How many eigenvectors the iteration computes for `count` wanted ones of an operator of dimension
/// `n`: a few more than asked, so that the last wanted one converges as well as the first and a
/// repeated frequency at the end of the range is not cut in half.
fn computed(count: usize, n: usize) -> usize {
    (count + (count / 2).max(4)).min(n)
}

/// The dimensions of the Krylov space between restarts: twice and four times the vectors computed,
/// and at least 32 and 64, the least faer uses.
fn krylov_dimensions(count: usize, n: usize) -> (usize, usize) {
    let wanted = computed(count, n);
    ((2 * wanted).max(32), (4 * wanted).max(64))
}

/// Whether the iteration applies to `count` eigenvectors of an operator of dimension `n`: its Krylov
/// space must be smaller than the operator (faer's iteration panics otherwise). A smaller problem is
/// one for the dense solver.
pub fn applies(count: usize, n: usize) -> bool {
    krylov_dimensions(count, n).1 < n
}

/// Eigenvectors `z` of the `count` largest eigenvalues of the operator, largest first. The
/// operator must be larger than the Krylov space ([`applies`]).
pub fn largest_eigenvectors(operator: &ShiftInvert, count: usize, tolerance: f64) -> Result<Mat<f64>, FemError> {
    let n = operator.dim();
    assert!(applies(count, n), "{count} eigenvectors of an operator of dimension {n}: solve it densely");
    let wanted = computed(count, n);
    let (min_dim, max_dim) = krylov_dimensions(count, n);
    let params = PartialEigenParams { min_dim, max_dim, max_restarts: 1000, ..Default::default() };
    let mut vectors = Mat::<f64>::zeros(n, wanted);
    let mut values = vec![0.0; wanted];
    // A start vector with every component nonzero and no structure (golden-ratio sequence).
    let start = operator.apply_to(Col::from_fn(n, |i| 0.5 + ((i as f64 + 1.0) * 0.618_033_988_749_895).fract()).as_mat());
    let start = start.col(0).to_owned();
    // A non-finite operator never converges: the iteration ran its thousand restarts on NaN (a plate
    // at z = −1e300, found by the fuzz test).
    if !start.iter().all(|x| x.is_finite()) {
        return Err(FemError::NotFinite);
    }
    let mut buffer = MemBuffer::new(partial_self_adjoint_eigen_scratch(operator, wanted, Par::Seq, params));
    let info = partial_self_adjoint_eigen(
        vectors.as_mut(),
        &mut values,
        operator,
        start.as_ref(),
        tolerance,
        Par::Seq,
        MemStack::new(&mut buffer),
        params,
    );
    if info.n_converged_eigen < count {
        return Err(FemError::EigenNotConverged { asked: count, converged: info.n_converged_eigen });
    }
    let mut order: Vec<usize> = (0..info.n_converged_eigen).collect();
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
    Ok(Mat::from_fn(n, count, |i, j| vectors[(i, order[j])]))
}
