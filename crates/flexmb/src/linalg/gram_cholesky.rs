//! The Gram matrix `B Bᵀ` of a sparse `B` and its Cholesky factor, both by `faer`: the product's pattern
//! (sparse–sparse product) and the factor's symbolic analysis (AMD ordering, simplicial) are made once
//! for `B`'s pattern; each factorization then only forms the product's numbers and factors them, in
//! workspace allocated up front. `B Bᵀ` couples two rows only where they share a column, so for the
//! constraint Jacobian of a mechanism (a row touches the one or two bodies its joint connects) its
//! entries and its factor's grow with the joints, not with their square: the conditioning of a chain of
//! any length is measured at a cost linear in it.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering};
use faer::sparse::linalg::matmul::{sparse_sparse_matmul_numeric, sparse_sparse_matmul_numeric_scratch, sparse_sparse_matmul_symbolic, SparseMatMulInfo};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatMut, SparseColMatRef, SymbolicSparseColMat};
use faer::{Accum, Conj, MatMut, Par, Side};

/// `B` (`nrows × ncols`, a fixed pattern) and the Cholesky factor of `B Bᵀ`.
pub(crate) struct GramCholesky {
    /// `Bᵀ` by columns (`B` by rows, each row's columns ascending) and its values.
    by_rows: SymbolicSparseColMat<usize>,
    by_rows_values: Vec<f64>,
    /// `B` by columns, and the position there of each entry of `by_rows`.
    by_columns: SymbolicSparseColMat<usize>,
    by_columns_values: Vec<f64>,
    to_by_columns: Vec<usize>,
    /// `B Bᵀ`: its pattern, the product's plan, its values and the positions of its diagonal (none for
    /// a row without entries).
    gram: SymbolicSparseColMat<usize>,
    product: SparseMatMulInfo,
    gram_values: Vec<f64>,
    diagonal: Vec<Option<usize>>,
    /// The factor's symbolic analysis and values, valid after a successful [`factor`](Self::factor).
    symbolic: SymbolicCholesky<usize>,
    factor_values: Vec<f64>,
    factored: bool,
    /// Workspace of the product, the factorization and the solves.
    buffer: MemBuffer,
}

impl std::fmt::Debug for GramCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GramCholesky").field("nrows", &self.nrows()).field("gram_nnz", &self.gram_values.len()).finish()
    }
}

impl GramCholesky {
    /// The analysis for `B` with `nrows` rows, `ncols` columns and entries at `(row, column)` of
    /// `entries` (duplicates allowed).
    ///
    /// # Panics
    /// If an entry is outside the matrix: the callers make the pattern from a model's layout, so that is
    /// a bug of the engine, not a user's mistake.
    pub(crate) fn new(nrows: usize, ncols: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let mut row_columns = vec![Vec::new(); nrows];
        for (r, c) in entries {
            assert!(r < nrows && c < ncols, "entry ({r}, {c}) outside a {nrows}×{ncols} matrix");
            row_columns[r].push(c);
        }
        let (mut ptr, mut idx) = (vec![0], Vec::new());
        for columns in &mut row_columns {
            columns.sort_unstable();
            columns.dedup();
            idx.extend_from_slice(columns);
            ptr.push(idx.len());
        }
        let nnz = idx.len();
        let by_rows = SymbolicSparseColMat::new_checked(ncols, nrows, ptr, None, idx);
        // B by columns: each column's rows ascending, as a row's entries are visited in row order.
        let mut column_ptr = vec![0; ncols + 1];
        by_rows.row_idx().iter().for_each(|&c| column_ptr[c + 1] += 1);
        (0..ncols).for_each(|c| column_ptr[c + 1] += column_ptr[c]);
        let mut next = column_ptr.clone();
        let (mut column_rows, mut to_by_columns) = (vec![0; nnz], vec![0; nnz]);
        for r in 0..nrows {
            for k in by_rows.col_range(r) {
                let c = by_rows.row_idx()[k];
                column_rows[next[c]] = r;
                to_by_columns[k] = next[c];
                next[c] += 1;
            }
        }
        let by_columns = SymbolicSparseColMat::new_checked(nrows, ncols, column_ptr, None, column_rows);
        let (gram, product) = sparse_sparse_matmul_symbolic(by_columns.as_ref(), by_rows.as_ref()).expect("memory for the pattern of B Bᵀ");
        let diagonal = (0..nrows)
            .map(|r| gram.col_range(r).find(|&k| gram.row_idx()[k] == r))
            .collect();
        let params = CholeskySymbolicParams { supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL, ..Default::default() };
        let symbolic = factorize_symbolic_cholesky(gram.as_ref(), Side::Upper, SymmetricOrdering::Amd, params).expect("memory for the Cholesky analysis of B Bᵀ");
        let scratch = StackReq::any_of(&[
            sparse_sparse_matmul_numeric_scratch::<usize, f64>(gram.as_ref(), Par::Seq),
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        let gram_nnz = gram.row_idx().len();
        let factor_len = symbolic.len_val();
        Self {
            by_rows,
            by_rows_values: vec![0.0; nnz],
            by_columns,
            by_columns_values: vec![0.0; nnz],
            to_by_columns,
            gram,
            product,
            gram_values: vec![0.0; gram_nnz],
            diagonal,
            symbolic,
            factor_values: vec![0.0; factor_len],
            factored: false,
            buffer: MemBuffer::new(scratch),
        }
    }

    /// Rows of `B`.
    pub(crate) fn nrows(&self) -> usize {
        self.diagonal.len()
    }

    /// Sets `B` to zero, before its entries are added again.
    pub(crate) fn clear(&mut self) {
        self.by_rows_values.fill(0.0);
        self.factored = false;
    }

    /// `B[row, column] += x`; `false` (and nothing added) if the entry is not in `B`'s pattern.
    pub(crate) fn add(&mut self, row: usize, column: usize, x: f64) -> bool {
        let range = self.by_rows.col_range(row);
        match self.by_rows.row_idx()[range.clone()].binary_search(&column) {
            Ok(k) => {
                self.by_rows_values[range.start + k] += x;
                true
            }
            Err(_) => false,
        }
    }

    /// Forms `B Bᵀ` from the entries added and factors it; returns its trace, or `None` when a pivot of
    /// the factor is at most `tiny` times the mean diagonal entry (`B Bᵀ` singular to that precision).
    pub(crate) fn factor(&mut self, tiny: f64) -> Option<f64> {
        self.factored = false;
        for (k, &x) in self.by_rows_values.iter().enumerate() {
            self.by_columns_values[self.to_by_columns[k]] = x;
        }
        let stack = MemStack::new(&mut self.buffer);
        sparse_sparse_matmul_numeric(
            SparseColMatMut::new(self.gram.as_ref(), &mut self.gram_values),
            Accum::Replace,
            SparseColMatRef::new(self.by_columns.as_ref(), &self.by_columns_values),
            SparseColMatRef::new(self.by_rows.as_ref(), &self.by_rows_values),
            1.0,
            &self.product,
            Par::Seq,
            stack,
        );
        let trace: f64 = self.diagonal.iter().flatten().map(|&k| self.gram_values[k]).sum();
        let n = self.nrows();
        if n == 0 || self.diagonal.contains(&None) || !trace.is_finite() || trace <= 0.0 {
            return None;
        }
        let stack = MemStack::new(&mut self.buffer);
        let result = self.symbolic.factorize_numeric_llt(
            &mut self.factor_values,
            SparseColMatRef::new(self.gram.as_ref(), &self.gram_values),
            Side::Upper,
            LltRegularization { dynamic_regularization_delta: 0.0, dynamic_regularization_epsilon: 0.0 },
            Par::Seq,
            stack,
            Default::default(),
        );
        if result.is_err() {
            return None;
        }
        // A pivot at most `tiny` of the mean diagonal entry: singular to that precision. The simplicial
        // factor stores each column's diagonal entry first.
        let SymbolicCholeskyRaw::Simplicial(simplicial) = self.symbolic.raw() else {
            unreachable!("the analysis is simplicial")
        };
        let threshold = tiny * trace / n as f64;
        let column_starts = &simplicial.col_ptr()[..n];
        if !column_starts.iter().all(|&k| self.factor_values[k] * self.factor_values[k] > threshold) {
            return None;
        }
        self.factored = true;
        Some(trace)
    }

    /// Solves `(B Bᵀ) y = y` in place with the factor of the last successful [`factor`](Self::factor).
    ///
    /// # Panics
    /// If there is no such factor, or `y` is not of `B`'s rows (bugs of the caller).
    pub(crate) fn solve_in_place(&mut self, y: &mut [f64]) {
        assert!(self.factored, "B Bᵀ solved with before it was factored");
        let n = self.nrows();
        let factor = LltRef::new(&self.symbolic, &self.factor_values);
        let stack = MemStack::new(&mut self.buffer);
        factor.solve_in_place_with_conj(Conj::No, MatMut::from_column_major_slice_mut(y, n, 1), Par::Seq, stack);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 × 6 `B` whose rows share columns pairwise (0 with 1 and 3, 2 with 3): `(B Bᵀ) y = r` solved to round-off
    /// against the product formed entry by entry, entries outside the pattern refused, and dependent
    /// rows found singular.
    #[test]
    fn the_gram_matrix_is_factored_and_solved_and_dependent_rows_are_singular() {
        let b = [
            [1.0, -2.0, 0.0, 0.0, 0.5, 0.0],
            [0.0, 3.0, 1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 4.0, 0.0, -1.0],
            [2.0, 0.0, 0.0, 0.0, 0.0, 1.5],
        ];
        let entries: Vec<(usize, usize)> = (0..4).flat_map(|r| (0..6).filter(move |&c| b[r][c] != 0.0).map(move |c| (r, c))).collect();
        let mut gram = GramCholesky::new(4, 6, entries.iter().copied().chain(entries.iter().copied()));
        gram.clear();
        for &(r, c) in &entries {
            // Each entry in two halves, as a joint's two markers on one body add theirs.
            assert!(gram.add(r, c, 0.25 * b[r][c]));
            assert!(gram.add(r, c, 0.75 * b[r][c]));
        }
        assert!(!gram.add(1, 5, 1.0), "an entry outside the pattern");
        let trace = gram.factor(1e-14).expect("independent rows");
        let full = |i: usize, j: usize| (0..6).map(|k| b[i][k] * b[j][k]).sum::<f64>();
        assert!((trace - (0..4).map(|i| full(i, i)).sum::<f64>()).abs() < 1e-13);
        let r = [0.3, -1.0, 2.0, 0.7];
        let mut y = r;
        gram.solve_in_place(&mut y);
        for i in 0..4 {
            let back: f64 = (0..4).map(|j| full(i, j) * y[j]).sum();
            assert!((back - r[i]).abs() < 1e-13, "row {i}: {back} against {}", r[i]);
        }
        // Two rows, one −2 times the other: singular.
        let mut dependent = GramCholesky::new(2, 3, [(0, 0), (0, 1), (1, 0), (1, 1)]);
        dependent.clear();
        [(0, 0, 1.0), (0, 1, 2.0), (1, 0, -2.0), (1, 1, -4.0)].into_iter().for_each(|(r, c, x)| assert!(dependent.add(r, c, x)));
        assert_eq!(dependent.factor(1e-14), None);
    }
}
