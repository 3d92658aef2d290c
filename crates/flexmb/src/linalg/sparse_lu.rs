//! A square sparse matrix with a fixed pattern and its LU factorization (`faer`, partial pivoting,
//! COLAMD ordering). The pattern is analysed once and all workspaces are allocated up front, so that
//! factor and solve do not allocate inside a time step.
//!
//! Two kinds, by what a factorization may depend on:
//! - [`SparseLu::new`]: every factorization chooses its pivots afresh, so its factors are a function of
//!   the values alone (the accelerations' KKT matrix, the normal equations, the linearization). Small
//!   matrices (up to [`DENSE_LIMIT`]) are factored dense.
//! - [`SparseLu::with_kept_pivots`]: the integrators' iteration matrices, factored at nearly every step
//!   with nearly the same numbers. The row pivots of a factorization with pivoting are kept and the
//!   later factorizations only recompute the numbers ([`LuFactors::refactor`]) while each kept pivot is
//!   at least [`PIVOT_THRESHOLD`](super::lu_refactorization::PIVOT_THRESHOLD) of its column's largest
//!   candidate; else the matrix is factored afresh with pivoting. The factors then depend on the pivot
//!   sequence kept, which [`kept_pivots`](SparseLu::kept_pivots) gives and
//!   [`keep_pivots`](SparseLu::keep_pivots) loads again (an integrator's checkpoint). Matrices up to
//!   [`KEPT_PIVOTS_DENSE_LIMIT`] are factored dense, afresh each time.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::simplicial::{factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch, SimplicialLu};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::perm::PermRef;
use faer::{Conj, MatMut, Par};

use super::dense_lu::DenseLu;
use super::lu_refactorization::{InvalidPivots, LuFactors};

/// Largest dimension of a matrix factored afresh ([`SparseLu::new`]) that is factored dense: about
/// where the two cost the same. The Adams method on the chain of spherical rods (its accelerations'
/// KKT matrix, 9 unknowns per rod; rtol = atol = 3e-9, 0.1 s, valgrind lackey, instructions of the run
/// less those of its start): at 72 unknowns (8 rods) dense 37.3 M, sparse 45.1 M; at 144 (16 rods)
/// dense 130.3 M, sparse 85.2 M. The crossover lies between; the limit was 200 before.
pub const DENSE_LIMIT: usize = 96;

/// Largest dimension of a matrix with kept pivots ([`SparseLu::with_kept_pivots`]) that is factored
/// dense, afresh each time. Measured on the chain of spherical rods (BDF, rtol = atol = 3e-10, 0.1 s,
/// valgrind lackey, instructions of the run less those of its start): at 80 unknowns (4 rods) the
/// refactorization costs 49.2 M against the dense LU's 42.1 M, at 160 (8 rods) 126.8 M against
/// 146.7 M, so the crossover lies between. The limit is lower, so that the cost per step grows
/// linearly from the chain of 4 rods on (×2.1 to 8 rods, against the dense LU's ×2.9); below it the
/// dense LU's cost is a few thousand multiply–adds, and the physics watchdog's spin-up beam (34
/// unknowns), whose failure mode depends on round-off, keeps its factorization.
pub const KEPT_PIVOTS_DENSE_LIMIT: usize = 40;

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
    factorization: Factorization,
    factored: bool,
}

/// How a [`SparseLu`] factors its values.
enum Factorization {
    /// Dense LU with partial pivoting, afresh each time.
    Dense(DenseLu),
    /// faer's sparse LU with partial pivoting, afresh each time.
    Fresh(Box<FreshFactors>),
    /// Refactorization with kept pivots, which a factorization with partial pivoting chooses when a
    /// kept pivot fails.
    KeptPivots(Box<KeptPivots>),
}

/// faer's numeric LU and its workspaces.
struct FreshFactors {
    numeric: NumericLu<usize, f64>,
    factor_buffer: MemBuffer,
    solve_buffer: MemBuffer,
}

/// The state of a factorization with kept pivots.
struct KeptPivots {
    /// The last factorization with pivoting, its row order and each row's position in it.
    pivoting: SimplicialLu<usize, f64>,
    row_order: Vec<usize>,
    row_position: Vec<usize>,
    factor_buffer: MemBuffer,
    /// The factors solved with, on the kept pivots.
    factors: LuFactors,
    /// Factorizations with pivoting so far.
    pivoting_factorizations: usize,
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
        Self::build(n, entries, false)
    }

    /// Builds the pattern as [`new`](Self::new) does, for factorizations that keep the pivots of the
    /// last factorization with pivoting while they are large enough (see the module's documentation).
    ///
    /// # Panics
    /// As [`new`](Self::new).
    pub fn with_kept_pivots(n: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> Self {
        Self::build(n, entries, true)
    }

    fn build(n: usize, entries: impl IntoIterator<Item = (usize, usize)>, keep_pivots: bool) -> Self {
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
        let factorization = if n <= if keep_pivots { KEPT_PIVOTS_DENSE_LIMIT } else { DENSE_LIMIT } {
            Factorization::Dense(DenseLu::new(n))
        } else if keep_pivots {
            Factorization::KeptPivots(Box::new(KeptPivots {
                pivoting: SimplicialLu::new(),
                row_order: vec![0; n],
                row_position: vec![0; n],
                factor_buffer: MemBuffer::new(factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n)),
                factors: LuFactors::default(),
                pivoting_factorizations: 0,
            }))
        } else {
            Factorization::Fresh(Box::new(FreshFactors {
                numeric: NumericLu::new(),
                factor_buffer: MemBuffer::new(symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default())),
                solve_buffer: MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
            }))
        };
        Self { n, pattern, values: vec![0.0; nnz], symbolic, factorization, factored: false }
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

    /// The kept pivot sequence (the position of each row in the pivot order), if this matrix keeps
    /// pivots and holds some.
    pub fn kept_pivots(&self) -> Option<&[usize]> {
        match &self.factorization {
            Factorization::KeptPivots(kept) => kept.factors.row_positions(),
            _ => None,
        }
    }

    /// Keeps the pivot sequence `row_positions` (as [`kept_pivots`](Self::kept_pivots) gave it, for
    /// the same pattern), or none: the next [`factor`](Self::factor) refactors with those pivots, or
    /// chooses pivots afresh. A sequence for a matrix that keeps none, not a permutation of the rows,
    /// or leaving a structurally zero pivot is an error, and no pivots are kept.
    pub fn keep_pivots(&mut self, row_positions: Option<&[usize]>) -> Result<(), InvalidPivots> {
        self.factored = false;
        match (&mut self.factorization, row_positions) {
            (Factorization::KeptPivots(kept), Some(positions)) => {
                kept.factors.load(self.pattern.as_ref(), positions, self.symbolic.col_perm().arrays().0)
            }
            (Factorization::KeptPivots(kept), None) => {
                kept.factors.unload();
                Ok(())
            }
            (_, Some(_)) => Err(InvalidPivots),
            (_, None) => Ok(()),
        }
    }

    /// Factorizations with pivoting so far (of a matrix with kept pivots; every other factorization
    /// reused their pivots).
    #[cfg(test)]
    pub fn pivoting_factorizations(&self) -> usize {
        match &self.factorization {
            Factorization::KeptPivots(kept) => kept.pivoting_factorizations,
            _ => 0,
        }
    }

    /// The kept factors (of a matrix with kept pivots that holds some).
    #[cfg(test)]
    pub(crate) fn kept_factors(&self) -> Option<&LuFactors> {
        match &self.factorization {
            Factorization::KeptPivots(kept) if kept.factors.is_loaded() => Some(&kept.factors),
            _ => None,
        }
    }

    /// Factors the current values (with the kept pivots while they are large enough, for a matrix
    /// that keeps them). Does not allocate once the factors' storage has grown to size.
    pub fn factor(&mut self) -> Result<(), SingularMatrix> {
        self.factored = false;
        if !self.values.iter().all(|x| x.is_finite()) {
            return Err(SingularMatrix);
        }
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        match &mut self.factorization {
            Factorization::Dense(dense) => {
                let ptr = self.pattern.col_ptr();
                let rows = self.pattern.row_idx();
                let columns = (0..self.n).map(|c| (&self.values[ptr[c]..ptr[c + 1]], &rows[ptr[c]..ptr[c + 1]]));
                if !dense.factor(columns) {
                    return Err(SingularMatrix);
                }
            }
            Factorization::Fresh(fresh) => {
                let stack = MemStack::new(&mut fresh.factor_buffer);
                self.symbolic.factorize_numeric_lu(&mut fresh.numeric, a, Par::Seq, stack, Default::default()).map_err(|_| SingularMatrix)?;
            }
            Factorization::KeptPivots(kept) => {
                if !(kept.factors.is_loaded() && kept.factors.refactor(a).is_ok()) {
                    kept.factor_with_pivoting(a, self.symbolic.col_perm())?;
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    /// The smallest over the largest magnitude of the last successful factorization's pivots (of `U`'s
    /// diagonal), a cheap measure of how near singular the matrix is; `None` for a matrix factored
    /// afresh by `faer`'s sparse LU, whose numeric factors do not show `U`'s diagonal.
    pub fn pivot_ratio(&self) -> Option<f64> {
        match &self.factorization {
            Factorization::Dense(dense) => Some(dense.pivot_ratio()),
            Factorization::Fresh(_) => None,
            Factorization::KeptPivots(kept) => Some(kept.factors.pivot_ratio()),
        }
    }

    /// Solves `A x = b` in place (`rhs` holds `b` on entry and `x` on return).
    /// Returns an error if the factors give a non-finite solution (a numerically singular matrix).
    ///
    /// # Panics
    /// Before a successful [`factor`](Self::factor), or if `rhs` is not of length [`n`](Self::n).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        assert!(self.factored, "solve before factor");
        match &mut self.factorization {
            Factorization::Dense(dense) => dense.solve_in_place(rhs),
            Factorization::Fresh(fresh) => {
                // `numeric` was produced by `symbolic.factorize_numeric_lu`, the only precondition.
                let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &fresh.numeric);
                let stack = MemStack::new(&mut fresh.solve_buffer);
                let mat = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
                lu.solve_in_place_with_conj(Conj::No, mat, Par::Seq, stack);
            }
            Factorization::KeptPivots(kept) => kept.factors.solve_in_place(rhs),
        }
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

impl KeptPivots {
    /// Chooses the pivots of `a` by a factorization with partial pivoting and keeps them; the factors
    /// are then those of a refactorization on them, the same as a run that loads these pivots gets.
    fn factor_with_pivoting(&mut self, a: SparseColMatRef<'_, usize, f64>, column_order: PermRef<'_, usize>) -> Result<(), SingularMatrix> {
        self.factors.unload();
        let stack = MemStack::new(&mut self.factor_buffer);
        factorize_simplicial_numeric_lu(&mut self.row_order, &mut self.row_position, &mut self.pivoting, a, column_order, stack)
            .map_err(|_| SingularMatrix)?;
        self.pivoting_factorizations += 1;
        self.factors.load(a.symbolic(), &self.row_position, column_order.arrays().0).map_err(|_| SingularMatrix)?;
        self.factors.refactor(a).map_err(|_| SingularMatrix)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::InvalidPivots;

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
    fn the_dense_and_sparse_paths_solve_to_round_off() {
        for n in [DENSE_LIMIT / 2, DENSE_LIMIT + 50] {
            let (entries, values) = band_matrix(n);
            let mut a = SparseLu::new(n, entries.iter().copied());
            assert_eq!(matches!(a.factorization, Factorization::Dense(_)), n <= DENSE_LIMIT);
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

    #[test]
    fn a_singular_matrix_is_reported_on_both_paths() {
        for n in [10, DENSE_LIMIT + 10] {
            // The last row and column are empty but for a zero diagonal.
            let entries: Vec<(usize, usize)> = (0..n - 1).map(|i| (i, i)).collect();
            let mut a = SparseLu::new(n, entries.iter().copied());
            for (r, c) in &entries {
                a.add(*r, *c, 2.0);
            }
            // The dense path finds the zero pivot when it factors, the sparse one when it solves.
            let mut x = vec![1.0; n];
            let outcome = a.factor().and_then(|()| a.solve_in_place(&mut x));
            assert_eq!(outcome, Err(SingularMatrix), "n = {n}");
        }
    }

    /// Uniform numbers in [-1, 1) from a fixed seed (a 64-bit linear congruential generator, Knuth's
    /// MMIX constants), for reproducible random matrices.
    fn uniform(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// The band matrix of dimension `n` with kept pivots, its values in place.
    fn band_with_kept_pivots(n: usize) -> SparseLu {
        let (entries, values) = band_matrix(n);
        let mut a = SparseLu::with_kept_pivots(n, entries.iter().copied());
        for ((r, c), v) in entries.iter().zip(&values) {
            a.add(*r, *c, *v);
        }
        a
    }

    /// The largest residual `|A x − b|` of the solution of `A x = b`.
    fn residual_of_solution(a: &mut SparseLu, b: &[f64]) -> f64 {
        let mut x = b.to_vec();
        a.solve_in_place(&mut x).unwrap();
        let mut ax = vec![0.0; b.len()];
        a.multiply(&x, &mut ax);
        ax.iter().zip(b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max)
    }

    /// New values on the same pattern (each entry of the diagonally dominant band matrix scaled by a
    /// random factor in [0.8, 1.2]: its diagonal pivots stay the largest) are refactored on the kept
    /// pivots: 20 value sets, one factorization with pivoting in all, each solved to round-off.
    #[test]
    fn a_refactorization_on_kept_pivots_solves_to_round_off() {
        let n = 150;
        let mut a = band_with_kept_pivots(n);
        let start = a.values.clone();
        let b: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
        let mut seed = 7;
        for _ in 0..20 {
            for (v, v0) in a.values.iter_mut().zip(&start) {
                *v = v0 * (1.0 + 0.2 * uniform(&mut seed));
            }
            a.factor().unwrap();
            let residual = residual_of_solution(&mut a, &b);
            assert!(residual < 1e-13, "residual {residual:e}");
        }
        assert_eq!(a.pivoting_factorizations(), 1);
    }

    /// A block-tridiagonal matrix of dense 10 × 10 blocks (a chain's iteration matrix in miniature) has
    /// supernodes of several columns, which the refactorization takes a run at a time: 10 value sets on
    /// the kept pivots, each solved to round-off.
    #[test]
    fn a_refactorization_by_supernodes_solves_to_round_off() {
        let (blocks, size): (usize, usize) = (8, 10);
        let n = blocks * size;
        let entries: Vec<(usize, usize)> = (0..blocks)
            .flat_map(|b| (b.saturating_sub(1)..(b + 2).min(blocks)).map(move |c| (b, c)))
            .flat_map(|(b, c)| (0..size).flat_map(move |i| (0..size).map(move |j| (b * size + i, c * size + j))))
            .collect();
        let mut a = SparseLu::with_kept_pivots(n, entries.iter().copied());
        let mut seed = 11;
        let b: Vec<f64> = (0..n).map(|k| (k as f64 * 0.29).sin()).collect();
        for _ in 0..10 {
            a.clear();
            for &(r, c) in &entries {
                a.add(r, c, if r == c { 40.0 } else { uniform(&mut seed) });
            }
            a.factor().unwrap();
            let residual = residual_of_solution(&mut a, &b);
            assert!(residual < 1e-13, "residual {residual:e}");
        }
        assert!(a.kept_factors().unwrap().widest_supernode() >= size, "{}", a.kept_factors().unwrap().widest_supernode());
        assert_eq!(a.pivoting_factorizations(), 1);
    }

    /// The factors are a function of the kept pivot sequence and the values: a second matrix given the
    /// first's pivots (as a checkpoint gives them) factors the same later values to the same solution,
    /// to the last bit, without a factorization with pivoting.
    #[test]
    fn loading_the_kept_pivots_gives_the_same_factors_to_the_last_bit() {
        let n = 120;
        let mut a = band_with_kept_pivots(n);
        a.factor().unwrap();
        let mut resumed = band_with_kept_pivots(n);
        resumed.keep_pivots(a.kept_pivots()).unwrap();
        assert_eq!(resumed.kept_pivots(), a.kept_pivots());
        let b: Vec<f64> = (0..n).map(|k| (k as f64 * 0.61).cos()).collect();
        let mut seed = 3;
        for _ in 0..5 {
            for (v, w) in a.values.iter_mut().zip(&mut resumed.values) {
                *v *= 1.0 + 0.1 * uniform(&mut seed);
                *w = *v;
            }
            a.factor().unwrap();
            resumed.factor().unwrap();
            let (mut x, mut y) = (b.clone(), b.clone());
            a.solve_in_place(&mut x).unwrap();
            resumed.solve_in_place(&mut y).unwrap();
            assert_eq!(x, y);
        }
        assert_eq!(resumed.pivoting_factorizations(), 0);
    }

    /// A kept pivot below half its column's largest candidate is given up and the matrix factored
    /// afresh with pivoting; every solution is right. 21 blocks `[[v, 1], [1, v]]` (42 unknowns, above
    /// the dense limit) from `v = 2` pivot on the diagonal; `v = 0.5` keeps it (half the candidate),
    /// `v = 0.05` gives it up for the off-diagonal 1, which `v = 0.5` and 2 keep (half of 2) and
    /// `v = 20` gives up again.
    #[test]
    fn a_kept_pivot_below_the_threshold_is_chosen_afresh() {
        let blocks = 21;
        let entries: Vec<(usize, usize)> =
            (0..blocks).flat_map(|k| [(2 * k, 2 * k), (2 * k, 2 * k + 1), (2 * k + 1, 2 * k), (2 * k + 1, 2 * k + 1)]).collect();
        let mut a = SparseLu::with_kept_pivots(2 * blocks, entries.iter().copied());
        for &(r, c) in &entries {
            a.add(r, c, if r == c { 2.0 } else { 1.0 });
        }
        a.factor().unwrap();
        let diagonal: Vec<usize> = (0..2 * blocks).map(|k| a.slot(k, k).unwrap()).collect();
        for (v, pivoting) in [(0.5, 1), (0.05, 2), (0.5, 2), (2.0, 2), (20.0, 3)] {
            diagonal.iter().for_each(|&s| a.values[s] = v);
            a.factor().unwrap();
            let mut x = vec![1.0; 2 * blocks];
            a.solve_in_place(&mut x).unwrap();
            let exact = 1.0 / (v + 1.0);
            assert!(x.iter().all(|x| (x - exact).abs() < 1e-15), "{v}: {x:?}");
            assert_eq!(a.pivoting_factorizations(), pivoting, "{v}");
        }
    }

    /// Pivots that do not fit are refused: not a permutation, of another dimension, for a matrix that
    /// keeps none (factored afresh, or dense); no pivots at all are always accepted.
    #[test]
    fn pivots_that_do_not_fit_are_refused() {
        let mut a = band_with_kept_pivots(60);
        assert_eq!(a.keep_pivots(Some(&[0; 60])), Err(InvalidPivots));
        assert_eq!(a.keep_pivots(Some(&(0..59).collect::<Vec<_>>())), Err(InvalidPivots));
        assert_eq!(a.keep_pivots(None), Ok(()));
        a.factor().unwrap();
        let pivots = a.kept_pivots().unwrap().to_vec();
        let (entries, _) = band_matrix(60);
        let mut afresh = SparseLu::new(60, entries.iter().copied());
        assert_eq!(afresh.keep_pivots(Some(&pivots)), Err(InvalidPivots));
        let (entries, _) = band_matrix(30);
        let mut dense = SparseLu::with_kept_pivots(30, entries.iter().copied());
        assert_eq!(dense.keep_pivots(Some(&pivots[..30])), Err(InvalidPivots));
        assert_eq!(dense.kept_pivots(), None);
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
