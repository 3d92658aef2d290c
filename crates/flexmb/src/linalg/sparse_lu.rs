//! A square sparse matrix with a fixed pattern and its LU factorization (`faer`, partial pivoting,
//! COLAMD ordering). The pattern is analysed once; the first factorization chooses the pivots and the
//! structure of the factors, and later ones only recompute the numbers with those pivots
//! ([`LuFactors::refactor`]) until a kept pivot becomes too small, when the matrix is factored afresh
//! with pivoting. All workspaces are allocated up front, so factor and solve do not allocate inside a
//! time step. Matrices of every size take this path: refactoring with kept pivots is cheaper than a
//! dense LU even at 20 unknowns (a rigid pendulum's BDF iteration matrix).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::simplicial::{
    factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch, SimplicialLu,
};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, SymbolicLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};

use super::lu_refactorization::LuFactors;

/// The factorization produced a zero or non-finite pivot.
#[derive(Clone, Copy, Debug, thiserror::Error, PartialEq, Eq)]
#[error("the matrix is singular to working precision")]
pub struct SingularMatrix;

/// Square sparse matrix (CSC, sorted rows) with reusable LU factors.
pub struct SparseLu {
    n: usize,
    pattern: SymbolicSparseColMat<usize>,
    /// Values in pattern order (`col_ptr`/`row_idx`); write them, then [`factor`](Self::factor).
    pub values: Vec<f64>,
    symbolic: SymbolicLu<usize>,
    /// The factors of the last factorization with pivoting, and its row pivots.
    pivoting: SimplicialLu<usize, f64>,
    row_order: Vec<usize>,
    row_position: Vec<usize>,
    factor_buffer: MemBuffer,
    /// The factors solved with: those of the pivoting factorization, refactored with new numbers.
    factors: LuFactors,
    /// Factorizations with pivoting (each followed by refactorizations with its pivots).
    pivoting_factorizations: usize,
    factored: bool,
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu").field("n", &self.n).field("nnz", &self.values.len()).finish()
    }
}

impl SparseLu {
    /// Builds the pattern from `(row, col)` entries (duplicates allowed) plus the whole diagonal.
    ///
    /// # Panics
    /// If an entry is outside the `n × n` matrix. This type is the integrators' workspace: its callers
    /// build the pattern from a model's layout, so an entry outside it is a bug of the engine, not a
    /// user's mistake.
    pub fn new(n: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (r, c) in entries {
            assert!(r < n && c < n, "entry ({r}, {c}) outside a {n}×{n} matrix");
            cols[c].push(r);
        }
        for (c, col) in cols.iter_mut().enumerate() {
            col.push(c);
            col.sort_unstable();
            col.dedup();
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for col in &cols {
            row_idx.extend_from_slice(col);
            col_ptr.push(row_idx.len());
        }
        let nnz = row_idx.len();
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        // Simplicial (left-looking, Gilbert–Peierls) rather than supernodal: faer 0.24's supernodal
        // numeric factorization allocates four times per call, and a time step must not allocate. The
        // supernodal one was 1.3–1.7× faster on `flexmb bench`; see tests/no_allocation.rs.
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), params)
            .expect("symbolic LU analysis of a valid pattern");
        let factor_buffer = MemBuffer::new(factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n));
        Self {
            n,
            pattern,
            values: vec![0.0; nnz],
            symbolic,
            pivoting: SimplicialLu::new(),
            row_order: vec![0; n],
            row_position: vec![0; n],
            factor_buffer,
            factors: LuFactors::default(),
            pivoting_factorizations: 0,
            factored: false,
        }
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Index range in [`values`](Self::values) of column `c`, and the rows of those entries.
    ///
    /// # Panics
    /// If `c` is not below [`n`](Self::n).
    pub fn column(&self, c: usize) -> (std::ops::Range<usize>, &[usize]) {
        let ptr = self.pattern.col_ptr();
        let range = ptr[c]..ptr[c + 1];
        (range.clone(), &self.pattern.row_idx()[range])
    }

    /// The values of column `c` (mutable) with their rows.
    pub fn column_mut(&mut self, c: usize) -> (&mut [f64], &[usize]) {
        let ptr = self.pattern.col_ptr();
        let range = ptr[c]..ptr[c + 1];
        self.factored = false;
        (&mut self.values[range.clone()], &self.pattern.row_idx()[range])
    }

    /// Position of entry `(r, c)` in [`values`](Self::values), if it is in the pattern.
    pub fn slot(&self, r: usize, c: usize) -> Option<usize> {
        let (range, rows) = self.column(c);
        rows.binary_search(&r).ok().map(|k| range.start + k)
    }

    /// Adds `x` to entry `(r, c)`.
    ///
    /// # Panics
    /// If the entry is outside the pattern (a bug of the caller, as for [`new`](Self::new)).
    #[inline]
    pub fn add(&mut self, r: usize, c: usize, x: f64) {
        let s = self.slot(r, c).unwrap_or_else(|| panic!("entry ({r}, {c}) is not in the pattern"));
        self.values[s] += x;
    }

    /// Sets every value to zero.
    pub fn clear(&mut self) {
        self.values.fill(0.0);
        self.factored = false;
    }

    /// Factorizations with pivoting so far (the first, and one each time a kept pivot became too small);
    /// every other factorization reused their pivots.
    #[cfg(test)]
    pub fn pivoting_factorizations(&self) -> usize {
        self.pivoting_factorizations
    }

    /// Entries of the sparse factors `L` and `U` (diagonals included; zero before the first
    /// factorization).
    #[cfg(test)]
    pub fn factor_entries(&self) -> usize {
        if self.factors.is_loaded() {
            self.factors.factor_entries()
        } else {
            0
        }
    }

    /// Multiply–adds of one refactorization with the kept pivots (zero before the first factorization).
    #[cfg(test)]
    pub fn refactor_operations(&self) -> usize {
        if self.factors.is_loaded() {
            self.factors.refactor_operations()
        } else {
            0
        }
    }

    /// Factors the current values: with the pivots and patterns of the last factorization with
    /// pivoting if they are held and every kept pivot is large enough, else afresh with pivoting. Does
    /// not allocate once the factors' storage has grown to size.
    pub fn factor(&mut self) -> Result<(), SingularMatrix> {
        self.factored = false;
        if !self.values.iter().all(|x| x.is_finite()) {
            return Err(SingularMatrix);
        }
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        if self.factors.is_loaded() && self.factors.refactor(a).is_ok() {
            self.factored = true;
            return Ok(());
        }
        let stack = MemStack::new(&mut self.factor_buffer);
        let column_order = self.symbolic.col_perm();
        factorize_simplicial_numeric_lu(&mut self.row_order, &mut self.row_position, &mut self.pivoting, a, column_order, stack)
            .map_err(|_| SingularMatrix)?;
        self.pivoting_factorizations += 1;
        self.factors.load(a, &self.pivoting, &self.row_position, column_order.arrays().0);
        if !self.factors.pivots_are_regular() {
            return Err(SingularMatrix);
        }
        self.factored = true;
        Ok(())
    }

    /// Solves `A x = b` in place (`rhs` holds `b` on entry and `x` on return).
    /// Returns an error if the factors give a non-finite solution (a numerically singular matrix).
    ///
    /// # Panics
    /// Before a successful [`factor`](Self::factor), or if `rhs` is not of length [`n`](Self::n).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        assert!(self.factored, "solve before factor");
        self.factors.solve_in_place(rhs);
        if rhs.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(SingularMatrix)
        }
    }

    /// `y = A x` with the current values (for the tests' residual checks).
    #[cfg(test)]
    pub fn multiply(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for c in 0..self.n {
            let (range, rows) = self.column(c);
            for (v, r) in self.values[range].iter().zip(rows) {
                y[*r] += v * x[c];
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A diagonally dominant unsymmetric band matrix with a few far entries, of dimension `n`.
    fn band_matrix(n: usize) -> (Vec<(usize, usize)>, Vec<f64>) {
        let mut entries = Vec::new();
        let mut values = Vec::new();
        for i in 0..n {
            for (j, v) in [(i, 10.0 + i as f64 * 0.01), ((i + 1) % n, -1.0 - 0.001 * i as f64), ((i + 7) % n, 0.5), ((i * 13 + 5) % n, 0.25)] {
                entries.push((i, j));
                values.push(v);
            }
        }
        (entries, values)
    }

    #[test]
    fn small_and_larger_matrices_solve_to_round_off() {
        for n in [100, 250] {
            let (entries, values) = band_matrix(n);
            let mut a = SparseLu::new(n, entries.iter().copied());
            for ((r, c), v) in entries.iter().zip(&values) {
                a.add(*r, *c, *v);
            }
            a.factor().unwrap();
            let b: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
            let mut x = b.clone();
            a.solve_in_place(&mut x).unwrap();
            let mut ax = vec![0.0; n];
            a.multiply(&x, &mut ax);
            let residual = ax.iter().zip(&b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
            assert!(residual < 1e-13, "n = {n}: residual {residual:e}");
        }
    }

    /// Uniform numbers in [-1, 1) from a fixed seed (a 64-bit linear congruential generator, Knuth's
    /// MMIX constants), for reproducible random matrices.
    pub(crate) fn uniform(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// The largest difference of two solutions relative to the largest component of the second.
    pub(crate) fn relative_difference(x: &[f64], y: &[f64]) -> f64 {
        let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        x.iter().zip(y).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs())) / scale
    }

    /// Solves with `a`'s current values and with a fresh factorization (new pattern analysis, pivots
    /// chosen afresh) of the same values; returns the relative difference of the two solutions (zero:
    /// the kept pivots are used only where partial pivoting chooses them).
    pub(crate) fn against_fresh_factorization(a: &mut SparseLu, rhs: &[f64]) -> f64 {
        let n = a.n();
        let entries: Vec<(usize, usize)> = (0..n).flat_map(|c| a.column(c).1.iter().map(move |&r| (r, c)).collect::<Vec<_>>()).collect();
        let mut fresh = SparseLu::new(n, entries);
        fresh.values.copy_from_slice(&a.values);
        fresh.factor().unwrap();
        let mut x_fresh = rhs.to_vec();
        fresh.solve_in_place(&mut x_fresh).unwrap();
        assert_eq!(fresh.pivoting_factorizations(), 1);
        a.factor().unwrap();
        let mut x = rhs.to_vec();
        a.solve_in_place(&mut x).unwrap();
        relative_difference(&x, &x_fresh)
    }

    /// After the first factorization, new values on the same pattern (each entry scaled by a random
    /// factor in [0.8, 1.2]; the matrix stays diagonally dominant, so its pivots stay) are refactored
    /// with the kept pivots: 20 value sets, one factorization with pivoting in all, each solution equal
    /// to that of a fresh factorization to the last bit.
    #[test]
    fn a_refactorization_with_kept_pivots_equals_a_fresh_factorization() {
        let n = 150;
        let (entries, values) = band_matrix(n);
        let mut a = SparseLu::new(n, entries.iter().copied());
        for ((r, c), v) in entries.iter().zip(&values) {
            a.add(*r, *c, *v);
        }
        let start = a.values.clone();
        let rhs: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
        let mut seed = 7;
        for _ in 0..20 {
            for (v, v0) in a.values.iter_mut().zip(&start) {
                *v = v0 * (1.0 + 0.2 * uniform(&mut seed));
            }
            let difference = against_fresh_factorization(&mut a, &rhs);
            assert_eq!(difference, 0.0);
        }
        assert_eq!(a.pivoting_factorizations(), 1);
    }

    /// A kept pivot that is no longer the largest of its column is not used: the matrix is factored
    /// afresh with pivoting, and every solution is right. `[[v, 1], [1, v]]` from `v = 2` pivots on a
    /// diagonal entry (in either column order); at `v = 0.5` the off-diagonal one is larger and chosen,
    /// kept at `v = 0.05` and 0, and given up again at `v = 2` (kept at 20).
    #[test]
    fn a_pivot_that_is_no_longer_the_largest_is_chosen_afresh() {
        let entries = [(0, 0), (0, 1), (1, 0), (1, 1)];
        let mut a = SparseLu::new(2, entries);
        for ((r, c), v) in entries.iter().zip([2.0, 1.0, 1.0, 2.0]) {
            a.add(*r, *c, v);
        }
        a.factor().unwrap();
        let diagonal = [a.slot(0, 0).unwrap(), a.slot(1, 1).unwrap()];
        for (v, pivoting) in [(0.5, 2), (0.05, 2), (0.0, 2), (2.0, 3), (20.0, 3)] {
            diagonal.iter().for_each(|&s| a.values[s] = v);
            a.factor().unwrap();
            let mut x = [1.0, 1.0];
            a.solve_in_place(&mut x).unwrap();
            let exact = 1.0 / (v + 1.0);
            assert!(x.iter().all(|x| (x - exact).abs() < 1e-15), "{v}: {x:?}");
            assert_eq!(a.pivoting_factorizations(), pivoting, "{v}");
        }
    }

    #[test]
    fn a_singular_matrix_is_reported_at_every_size() {
        for n in [10, 210] {
            // The last row and column are empty but for a zero diagonal.
            let entries: Vec<(usize, usize)> = (0..n - 1).map(|i| (i, i)).collect();
            let mut a = SparseLu::new(n, entries.iter().copied());
            for (r, c) in &entries {
                a.add(*r, *c, 2.0);
            }
            // The zero pivot is found when the matrix is factored.
            let mut x = vec![1.0; n];
            let outcome = a.factor().and_then(|()| a.solve_in_place(&mut x));
            assert_eq!(outcome, Err(SingularMatrix), "n = {n}");
            assert_eq!(a.factor(), Err(SingularMatrix), "n = {n}");
        }
    }

    #[test]
    fn factor_and_solve_a_small_unsymmetric_system() {
        // [[4, 1, 0], [2, 5, 1], [0, 3, 6]] x = [1, 2, 3]
        let entries = [(0, 0), (0, 1), (1, 0), (1, 1), (1, 2), (2, 1), (2, 2)];
        let mut a = SparseLu::new(3, entries);
        for ((r, c), v) in entries.iter().zip([4.0, 1.0, 2.0, 5.0, 1.0, 3.0, 6.0]) {
            a.add(*r, *c, v);
        }
        a.factor().unwrap();
        let b = [1.0, 2.0, 3.0];
        let mut x = b;
        a.solve_in_place(&mut x).unwrap();
        let mut ax = [0.0; 3];
        a.multiply(&x, &mut ax);
        for k in 0..3 {
            assert!((ax[k] - b[k]).abs() < 1e-14);
        }
        // Refactor with new numbers on the same pattern.
        a.values.iter_mut().for_each(|v| *v *= 2.0);
        a.factor().unwrap();
        let mut x2 = b;
        a.solve_in_place(&mut x2).unwrap();
        for k in 0..3 {
            assert!((2.0 * x2[k] - x[k]).abs() < 1e-14);
        }
    }
}
