//! A sparse matrix stored by rows (`faer`'s compressed sparse rows, columns sorted within a row): the
//! constraint Jacobians of the initial-condition analyses, which hold a few entries per row (the velocity
//! coordinates of the one or two bodies a joint connects), so that their memory and work grow with
//! the bodies, not with their square. The products with `A` and `Aᵀ` are plain loops over the entries
//! (one vector each, as the analyses use them).

use faer::sparse::{SparseRowMat, Triplet};

/// An `nrows × ncols` sparse matrix by rows; each row's columns ascending and distinct.
#[derive(Clone, Debug)]
pub(crate) struct SparseRows(SparseRowMat<usize, f64>);

impl PartialEq for SparseRows {
    fn eq(&self, other: &Self) -> bool {
        self.same_pattern(other) && self.0.val() == other.0.val()
    }
}

impl SparseRows {
    /// The matrix of `(row, column, value)` entries, duplicates summed (as `jacobian_entries` adds
    /// the contributions of a row's two markers on the same body).
    ///
    /// # Panics
    /// If an entry is outside the matrix: the callers make the entries from a model's layout, so that is
    /// a bug of the engine, not a user's mistake.
    pub(crate) fn from_entries(nrows: usize, ncols: usize, entries: Vec<(usize, usize, f64)>) -> Self {
        let triplets: Vec<Triplet<usize, usize, f64>> = entries
            .into_iter()
            .map(|(r, c, x)| {
                assert!(r < nrows && c < ncols, "entry ({r}, {c}) outside a {nrows}×{ncols} matrix");
                Triplet::new(r, c, x)
            })
            .collect();
        Self(SparseRowMat::try_new_from_triplets(nrows, ncols, &triplets).expect("memory for a sparse matrix by rows"))
    }

    /// Number of rows.
    pub(crate) fn nrows(&self) -> usize {
        self.0.nrows()
    }

    /// Number of columns.
    pub(crate) fn ncols(&self) -> usize {
        self.0.ncols()
    }

    /// Number of stored entries.
    pub(crate) fn nnz(&self) -> usize {
        self.0.val().len()
    }

    /// Whether `other` has the same dimensions and entries (whatever their values).
    pub(crate) fn same_pattern(&self, other: &Self) -> bool {
        let (a, b) = (self.0.symbolic(), other.0.symbolic());
        a.nrows() == b.nrows() && a.ncols() == b.ncols() && a.row_ptr() == b.row_ptr() && a.col_idx() == b.col_idx()
    }

    /// The columns and values of row `r`.
    pub(crate) fn row(&self, r: usize) -> (&[usize], &[f64]) {
        let range = self.0.row_range(r);
        (&self.0.symbolic().col_idx()[range.clone()], &self.0.val()[range])
    }

    /// The Euclidean length of row `r`.
    #[cfg(test)]
    pub(crate) fn row_norm(&self, r: usize) -> f64 {
        self.row(r).1.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    /// `y = A x`.
    pub(crate) fn multiply(&self, x: &[f64], y: &mut [f64]) {
        for (r, y) in y.iter_mut().enumerate() {
            let (cols, values) = self.row(r);
            *y = cols.iter().zip(values).map(|(c, v)| v * x[*c]).sum();
        }
    }

    /// `y = Aᵀ z`.
    pub(crate) fn multiply_transposed(&self, z: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (r, z) in z.iter().enumerate() {
            let (cols, values) = self.row(r);
            cols.iter().zip(values).for_each(|(c, v)| y[*c] += v * z);
        }
    }

    /// `Aᵀ`, stored by rows: the entries of each column of `A`, in row order.
    pub(crate) fn transposed(&self) -> Self {
        Self(self.0.to_col_major().expect("memory for a sparse matrix by columns").into_transpose())
    }

    /// The rows of each column, in row order (the transposed pattern).
    pub(crate) fn column_rows(&self) -> Vec<Vec<usize>> {
        let t = self.transposed();
        (0..t.nrows()).map(|c| t.row(c).0.to_vec()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duplicates_are_summed_and_empty_rows_kept() {
        let a = SparseRows::from_entries(4, 3, vec![(2, 1, 1.0), (0, 2, 2.0), (2, 1, 0.5), (2, 0, -1.0), (0, 0, 3.0)]);
        assert_eq!(a.nrows(), 4);
        assert_eq!(a.nnz(), 4);
        assert_eq!(a.row(0), (&[0, 2][..], &[3.0, 2.0][..]));
        assert_eq!(a.row(1), (&[][..], &[][..]));
        assert_eq!(a.row(2), (&[0, 1][..], &[-1.0, 1.5][..]));
        assert_eq!(a.row(3).0.len(), 0);
        let mut y = [0.0; 4];
        a.multiply(&[1.0, 2.0, 3.0], &mut y);
        assert_eq!(y, [9.0, 0.0, 2.0, 0.0]);
        // zᵀ (A x) = (Aᵀ z)ᵀ x
        let z = [0.5, 7.0, -2.0, 1.0];
        let mut atz = [0.0; 3];
        a.multiply_transposed(&z, &mut atz);
        let lhs: f64 = z.iter().zip(&y).map(|(p, q)| p * q).sum();
        let rhs: f64 = atz.iter().zip([1.0, 2.0, 3.0]).map(|(p, q)| p * q).sum();
        assert_eq!(lhs, rhs);
        assert_eq!(a.column_rows(), vec![vec![0, 2], vec![2], vec![0]]);
        let t = a.transposed();
        assert_eq!((t.nrows(), t.ncols()), (3, 4));
        assert_eq!(t.row(0), (&[0, 2][..], &[3.0, -1.0][..]));
        assert_eq!(t.transposed(), a);
    }
}
