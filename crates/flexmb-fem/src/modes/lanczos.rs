//! Sparse path: faer's Krylov–Schur (thick-restart Lanczos for a symmetric operator) on the
//! shift-invert operator, whose largest eigenvalues are the lowest frequencies.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::matrix_free::eigen::{partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch, PartialEigenParams};
use faer::{Col, Mat, Par};

use super::shift_invert::ShiftInvert;
use crate::error::FemError;

/// Eigenvectors `z` of the `count` largest eigenvalues of the operator, largest first.
pub fn largest_eigenvectors(operator: &ShiftInvert, count: usize, tolerance: f64) -> Result<Mat<f64>, FemError> {
    let n = operator.dim();
    // A few more than asked, so that the last wanted one converges as well as the first and a
    // repeated frequency at the end of the range is not cut in half.
    let wanted = (count + (count / 2).max(4)).min(n);
    let params = PartialEigenParams {
        min_dim: (2 * wanted).max(20).min(n),
        max_dim: (4 * wanted).max(40).min(n),
        max_restarts: 1000,
        ..Default::default()
    };
    let mut vectors = Mat::<f64>::zeros(n, wanted);
    let mut values = vec![0.0; wanted];
    // A start vector with every component nonzero and no structure (golden-ratio sequence).
    let start = operator.apply_to(Col::from_fn(n, |i| 0.5 + ((i as f64 + 1.0) * 0.618_033_988_749_895).fract()).as_mat());
    let start = start.col(0).to_owned();
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
