//! Dense path: the whole shift-invert operator, then a symmetric eigensolver.

use faer::{Mat, Side};

use super::shift_invert::ShiftInvert;
use crate::error::FemError;

/// Eigenvectors `z` of the `count` largest eigenvalues of the operator, largest first.
pub fn largest_eigenvectors(operator: &ShiftInvert, count: usize) -> Result<Mat<f64>, FemError> {
    let n = operator.dim();
    let b = operator.apply_to(Mat::<f64>::identity(n, n).as_ref());
    if !b.col_iter().all(|c| c.iter().all(|x| x.is_finite())) {
        return Err(FemError::NotFinite);
    }
    let symmetric = Mat::from_fn(n, n, |i, j| 0.5 * (b[(i, j)] + b[(j, i)]));
    let eigen = symmetric
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| FemError::LinearAlgebra(format!("dense eigensolver: {e:?}")))?;
    // Eigenvalues ascend: the largest are last.
    Ok(Mat::from_fn(n, count, |i, j| eigen.U()[(i, n - 1 - j)]))
}
