//! The product of a sparse symmetric matrix (the stiffness, the mass: both triangles stored) with a
//! block of dense vectors, in one pass over the sparse matrix.
//!
//! faer's sparse–dense product takes the dense columns one at a time and reads the whole sparse
//! matrix for each: with the 20 to 32 mode shapes of the `solid-reduction` benchmark, 20 to 32
//! passes over its stiffness of 220,515 equations. Here the vectors are laid out by rows
//! (a row of the block contiguous), and column `j` of the result is `Σ_i A_ij x_i`, the rows `x_i`
//! gathered along column `j` of `A` (`Aᵀ x`, which is `A x` for a symmetric `A`): the sparse matrix is
//! read once, and every nonzero updates all the vectors with one contiguous multiply–add.

use faer::sparse::SparseColMat;
use faer::{Mat, MatRef};

/// `A x` for a symmetric `A` (computed as `Aᵀ x`, the sparse matrix read once).
pub(crate) fn symmetric_times(a: &SparseColMat<usize, f64>, x: MatRef<'_, f64>) -> Mat<f64> {
    let (n, width) = (x.nrows(), x.ncols());
    assert_eq!(a.nrows(), n, "the vectors' length is the matrix's order");
    let mut rows = vec![0.0; n * width];
    for j in 0..width {
        for (i, v) in x.col(j).iter().enumerate() {
            rows[i * width + j] = *v;
        }
    }
    let mut product = Mat::zeros(a.ncols(), width);
    let mut sum = vec![0.0; width];
    for column in 0..a.ncols() {
        sum.fill(0.0);
        for (i, v) in a.row_idx_of_col(column).zip(a.val_of_col(column)) {
            sum.iter_mut().zip(&rows[i * width..(i + 1) * width]).for_each(|(s, x)| *s += v * x);
        }
        for (j, s) in sum.iter().enumerate() {
            product[(column, j)] = *s;
        }
    }
    product
}

/// `(A + Aᵀ) / 2`: a square matrix that is symmetric but for rounding (a projection `xᵀ A x`, a product of
/// factors), made exactly so before a symmetric eigen-decomposition or factorization reads one triangle.
pub(crate) fn symmetrized(a: &Mat<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// `xᵀ A x` for a symmetric `A` (the modal matrix of the modes `x`).
pub(crate) fn symmetric_projection(a: &SparseColMat<usize, f64>, x: MatRef<'_, f64>) -> Mat<f64> {
    x.transpose() * symmetric_times(a, x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    /// The one-pass product equals faer's, column by column, on a symmetric matrix with a
    /// repeated entry, an empty column and a full dense block.
    #[test]
    fn equals_the_column_by_column_product() {
        let n = 7;
        let mut triplets = Vec::new();
        for i in 0..n {
            if i == 3 {
                continue;
            }
            triplets.push(Triplet::new(i, i, 2.0 + i as f64));
            if i + 2 < n && i + 2 != 3 {
                triplets.push(Triplet::new(i, i + 2, -0.5 * i as f64 - 0.25));
                triplets.push(Triplet::new(i + 2, i, -0.5 * i as f64 - 0.25));
            }
        }
        triplets.push(Triplet::new(0, 0, 1.5));
        let a = SparseColMat::try_new_from_triplets(n, n, &triplets).unwrap();
        let x = Mat::from_fn(n, 5, |i, j| ((i * 7 + j * 3) % 11) as f64 - 4.5);
        let expected = &a * &x;
        let product = symmetric_times(&a, x.as_ref());
        for i in 0..n {
            for j in 0..5 {
                assert!((product[(i, j)] - expected[(i, j)]).abs() <= 1e-14 * expected[(i, j)].abs().max(1.0));
            }
        }
        let projection = symmetric_projection(&a, x.as_ref());
        let expected = x.transpose() * &expected;
        for i in 0..5 {
            for j in 0..5 {
                assert!((projection[(i, j)] - expected[(i, j)]).abs() <= 1e-12 * expected[(i, j)].abs().max(1.0));
            }
        }
    }
}
