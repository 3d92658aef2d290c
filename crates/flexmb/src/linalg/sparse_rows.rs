//! A sparse matrix stored by rows (compressed sparse rows, columns sorted within a row): the constraint
//! Jacobians of the initial-condition analyses, which hold a few entries per row (the velocity
//! coordinates of the one or two bodies a joint connects), so that their memory and work grow with
//! the bodies, not with their square.

/// An `nrows × ncols` sparse matrix by rows; each row's columns ascending and distinct.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SparseRows {
    ncols: usize,
    /// Row `r`'s entries are `row_ptr[r]..row_ptr[r + 1]` of `cols` and `values`.
    row_ptr: Vec<usize>,
    cols: Vec<usize>,
    values: Vec<f64>,
}

impl SparseRows {
    /// The matrix of `(row, column, value)` entries, duplicates summed (as `jacobian_entries` adds
    /// the contributions of a row's two markers on the same body).
    ///
    /// # Panics
    /// If an entry is outside the matrix: the callers make the entries from a model's layout, so that is
    /// a bug of the engine, not a user's mistake.
    pub(crate) fn from_entries(nrows: usize, ncols: usize, mut entries: Vec<(usize, usize, f64)>) -> Self {
        entries.sort_unstable_by_key(|&(r, c, _)| (r, c));
        let mut row_ptr = Vec::with_capacity(nrows + 1);
        let mut cols = Vec::with_capacity(entries.len());
        let mut values: Vec<f64> = Vec::with_capacity(entries.len());
        row_ptr.push(0);
        let mut row = 0;
        for (r, c, x) in entries {
            assert!(r < nrows && c < ncols, "entry ({r}, {c}) outside a {nrows}×{ncols} matrix");
            while row < r {
                row_ptr.push(cols.len());
                row += 1;
            }
            if cols.len() > row_ptr[r] && cols.last() == Some(&c) {
                *values.last_mut().expect("a value beside each column") += x;
            } else {
                cols.push(c);
                values.push(x);
            }
        }
        while row < nrows {
            row_ptr.push(cols.len());
            row += 1;
        }
        Self { ncols, row_ptr, cols, values }
    }

    /// Number of rows.
    pub(crate) fn nrows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Number of columns.
    pub(crate) fn ncols(&self) -> usize {
        self.ncols
    }

    /// Number of stored entries.
    pub(crate) fn nnz(&self) -> usize {
        self.cols.len()
    }

    /// Whether `other` has the same dimensions and entries (whatever their values).
    pub(crate) fn same_pattern(&self, other: &Self) -> bool {
        self.ncols == other.ncols && self.row_ptr == other.row_ptr && self.cols == other.cols
    }

    /// The columns and values of row `r`.
    pub(crate) fn row(&self, r: usize) -> (&[usize], &[f64]) {
        let range = self.row_ptr[r]..self.row_ptr[r + 1];
        (&self.cols[range.clone()], &self.values[range])
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
        let entries = (0..self.nrows())
            .flat_map(|r| {
                let (cols, values) = self.row(r);
                cols.iter().zip(values).map(move |(c, x)| (*c, r, *x))
            })
            .collect();
        Self::from_entries(self.ncols, self.nrows(), entries)
    }

    /// The rows of each column, in row order (the transposed pattern).
    pub(crate) fn column_rows(&self) -> Vec<Vec<usize>> {
        let mut rows = vec![Vec::new(); self.ncols];
        for r in 0..self.nrows() {
            self.row(r).0.iter().for_each(|&c| rows[c].push(r));
        }
        rows
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
