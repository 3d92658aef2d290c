//! LU factors on a kept pivot sequence, refactored with new numbers: the left-looking refactorization
//! of KLU (Davis and Palamadai Natarajan 2010, `klu_refactor`), which reuses the row pivots of a
//! factorization with partial pivoting and the patterns of `L` and `U` they imply, and so skips the
//! depth-first searches, the pivot search and the storage growth of a factorization with pivoting.
//!
//! With `P A Q = L U` (`P` the row pivots, `Q` the fill-reducing column order, `L` unit lower and `U`
//! upper triangular), column `j` of the factors is the sparse triangular solve
//! `L(0..j, 0..j) x = (P A Q)(0..j, j)` over the reach of `A Q`'s column `j` in the graph of `L`'s
//! earlier columns (Gilbert and Peierls 1988); then `U(0..j, j) = x(0..j)`, `U(j, j) = x_j` and
//! `L(j+1.., j) = x(j+1..) / x_j`. The patterns are found once per pivot sequence
//! ([`load`](LuFactors::load)) from the pattern of `A` and the pivots alone, and every column's
//! updates are taken in increasing pivot order (a topological order of the reach, since `L(:, k)` has
//! rows below `k` only). So the factors are a function of the pivot sequence and the current values,
//! whatever the pivoting factorization's own order of operations was: loading the same pivots again
//! (from a checkpoint) gives the same factors to the last bit.
//!
//! A kept pivot stays while it is at least [`PIVOT_THRESHOLD`] times the largest candidate of its
//! column (threshold partial pivoting; KLU's and UMFPACK's default tolerance is 0.1): the growth of the
//! factors per column is then bounded by `1 / PIVOT_THRESHOLD` instead of 1. 0.5 rather than 0.1: with
//! 0.1 the BDF at rtol = atol = 1e-12 stopped 1 ms before the double four-bar's singular position
//! (step size too small at t = 0.7117 s, tests/singular_passage.rs), which it passes with 0.5.
//! Otherwise [`refactor`](LuFactors::refactor) reports it and the caller factors afresh with pivoting.

use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

/// The smallest ratio of a kept pivot to the largest candidate of its column (in magnitude) for the
/// pivot to stay.
pub const PIVOT_THRESHOLD: f64 = 0.5;

/// Why a refactorization with the kept pivots was not completed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefactorFailure {
    /// The kept pivot of a column is below [`PIVOT_THRESHOLD`] times its column's largest candidate,
    /// or is zero or not finite.
    PivotTooSmall {
        /// The step (column of `P A Q`) whose pivot failed.
        step: usize,
    },
}

/// The smallest over the largest magnitude of `pivots` (1 if there are none, 0 if one is zero or not
/// finite): a cheap measure of how near singular a factored matrix is.
pub fn pivot_ratio(pivots: impl Iterator<Item = f64>) -> f64 {
    let (mut smallest, mut largest) = (f64::INFINITY, 0.0_f64);
    for pivot in pivots {
        if pivot == 0.0 || !pivot.is_finite() {
            return 0.0;
        }
        smallest = smallest.min(pivot.abs());
        largest = largest.max(pivot.abs());
    }
    if largest == 0.0 {
        1.0
    } else {
        smallest / largest
    }
}

/// A pivot sequence that cannot be loaded: not a permutation of the matrix's rows, or one whose
/// pattern leaves a structurally zero pivot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InvalidPivots;

/// `P A Q = L U` stored by columns in the permuted numbering: the strictly lower part of `L` (its unit
/// diagonal implied), the strictly upper part of `U` with its rows increasing, and `U`'s diagonal.
#[derive(Debug, Default)]
pub struct LuFactors {
    /// Whether a pivot sequence is held (set by `load`, cleared by a failed refactorization).
    loaded: bool,
    n: usize,
    /// Position in the pivot order of each row of `A` (`P`).
    row_position: Vec<usize>,
    /// Column of `A` taken at each step (`Q`).
    column_order: Vec<usize>,
    l_start: Vec<usize>,
    l_rows: Vec<usize>,
    l_values: Vec<f64>,
    u_start: Vec<usize>,
    u_rows: Vec<usize>,
    u_values: Vec<f64>,
    u_diagonal: Vec<f64>,
    /// The dense column being eliminated (all zeros between calls).
    work: Vec<f64>,
    /// The last column of each column's supernode: the columns `k..=last` of `L` in which `L(:, m)` is
    /// `{m + 1} ∪ L(:, m + 1)`, so that they share the rows below the block.
    supernode_last: Vec<usize>,
    /// The shared rows of a run of a supernode's columns, gathered dense, and the run's multipliers.
    shared: Vec<f64>,
    run: Vec<f64>,
    /// Scratch of the symbolic analysis: the step that last marked each position, the reach, a stack.
    marked: Vec<usize>,
    reach: Vec<usize>,
    stack: Vec<usize>,
}

impl LuFactors {
    /// Whether a pivot sequence (and so the factors' patterns) is held.
    pub fn is_loaded(&self) -> bool {
        self.loaded
    }

    /// The position in the pivot order of each row of `A`, if a pivot sequence is held.
    pub fn row_positions(&self) -> Option<&[usize]> {
        self.loaded.then_some(self.row_position.as_slice())
    }

    /// Forgets the pivot sequence: the next factorization chooses pivots afresh.
    pub fn unload(&mut self) {
        self.loaded = false;
    }

    /// Takes the pivot sequence `row_position` (the position of each row of `A`) for the column order
    /// `column_order` (the column of `A` at each step) and finds the patterns of `L` and `U` for the
    /// pattern of `a`. Reuses the storage of the previous factors, so it allocates only when the new
    /// ones are larger. The numbers are those of the next [`refactor`](Self::refactor).
    pub fn load(
        &mut self,
        a: SymbolicSparseColMatRef<'_, usize>,
        row_position: &[usize],
        column_order: &[usize],
    ) -> Result<(), InvalidPivots> {
        let n = a.ncols();
        self.loaded = false;
        if row_position.len() != n || column_order.len() != n || a.nrows() != n || !is_permutation(row_position, &mut self.marked) {
            return Err(InvalidPivots);
        }
        self.n = n;
        self.row_position.clear();
        self.row_position.extend_from_slice(row_position);
        self.column_order.clear();
        self.column_order.extend_from_slice(column_order);
        self.work.clear();
        self.work.resize(n, 0.0);
        self.u_diagonal.clear();
        self.u_diagonal.resize(n, 0.0);
        self.marked.clear();
        self.marked.resize(n, 0);
        // A reach holds each position once, and so does the search's stack.
        self.reach.clear();
        self.reach.reserve(n);
        self.stack.reserve(n);
        for v in [&mut self.l_start, &mut self.l_rows, &mut self.u_start, &mut self.u_rows] {
            v.clear();
        }
        self.l_start.push(0);
        self.u_start.push(0);
        for j in 0..n {
            self.find_reach(a.row_idx_of_col_raw(column_order[j]), j);
            if self.reach.binary_search(&j).is_err() {
                return Err(InvalidPivots);
            }
            self.u_rows.extend(self.reach.iter().copied().filter(|&k| k < j));
            self.l_rows.extend(self.reach.iter().copied().filter(|&k| k > j));
            self.u_start.push(self.u_rows.len());
            self.l_start.push(self.l_rows.len());
        }
        // A later pivot sequence may fill in more: the patterns are given twice the room of the first
        // (or of a larger one), and the values as much as the patterns, so that a new pivot sequence
        // inside a time step seldom allocates.
        for (rows, values) in [(&mut self.l_rows, &mut self.l_values), (&mut self.u_rows, &mut self.u_values)] {
            if rows.capacity() > values.capacity() || values.capacity() < rows.len() {
                rows.reserve(rows.len());
            }
            values.clear();
            values.reserve(rows.capacity());
            values.resize(rows.len(), 0.0);
        }
        self.find_supernodes();
        self.loaded = true;
        Ok(())
    }

    /// The supernodes of `L` ([`supernode_last`](Self::supernode_last)), from its pattern.
    fn find_supernodes(&mut self) {
        let n = self.n;
        let column = |k: usize| &self.l_rows[self.l_start[k]..self.l_start[k + 1]];
        self.supernode_last.clear();
        self.supernode_last.resize(n, 0);
        for k in (0..n).rev() {
            let continues = k + 1 < n && column(k).first() == Some(&(k + 1)) && column(k)[1..] == *column(k + 1);
            self.supernode_last[k] = if continues { self.supernode_last[k + 1] } else { k };
        }
        self.shared.clear();
        self.shared.resize(n, 0.0);
        self.run.clear();
        self.run.resize(n, 0.0);
    }

    /// The positions reached from the rows `rows` of `A` at step `j` (the rows of the column's `L`
    /// solve: a position `k < j` reaches the rows of `L(:, k)`), sorted, into `reach`.
    fn find_reach(&mut self, rows: &[usize], j: usize) {
        let mark = j + 1;
        self.reach.clear();
        self.stack.clear();
        for &r in rows {
            let b = self.row_position[r];
            if self.marked[b] != mark {
                self.marked[b] = mark;
                self.stack.push(b);
            }
        }
        while let Some(k) = self.stack.pop() {
            self.reach.push(k);
            if k < j {
                for &i in &self.l_rows[self.l_start[k]..self.l_start[k + 1]] {
                    if self.marked[i] != mark {
                        self.marked[i] = mark;
                        self.stack.push(i);
                    }
                }
            }
        }
        self.reach.sort_unstable();
    }

    /// Entries stored in `L` and `U` together, their diagonals included.
    #[cfg(test)]
    pub fn factor_entries(&self) -> usize {
        self.l_rows.len() + self.u_rows.len() + 2 * self.n
    }

    /// The smallest over the largest magnitude of `U`'s diagonal (1 for an empty matrix); meaningful
    /// after a successful [`refactor`](Self::refactor).
    pub fn pivot_ratio(&self) -> f64 {
        pivot_ratio(self.u_diagonal[..self.n].iter().copied())
    }

    /// The most columns of one supernode of `L`.
    #[cfg(test)]
    pub fn widest_supernode(&self) -> usize {
        (0..self.n).map(|k| self.supernode_last[k] - k + 1).max().unwrap_or(0)
    }

    /// Multiply–adds of one refactorization: for each column `j`, the entries of `L(:, k)` for every
    /// `k` in `U(:, j)`'s pattern, and the divisions of `L(:, j)`.
    #[cfg(test)]
    pub fn refactor_operations(&self) -> usize {
        let l_len = |k: usize| self.l_start[k + 1] - self.l_start[k];
        (0..self.n).map(|j| self.u_rows[self.u_start[j]..self.u_start[j + 1]].iter().map(|&k| l_len(k)).sum::<usize>() + l_len(j)).sum()
    }

    /// Refactors `a` (the pattern the pivots were loaded for, new values) with the kept pivots.
    /// Allocates nothing. On failure the pivot sequence is forgotten.
    ///
    /// # Panics
    /// If no pivots are loaded or `a` is not of their dimension (a bug of the caller).
    pub fn refactor(&mut self, a: SparseColMatRef<'_, usize, f64>) -> Result<(), RefactorFailure> {
        assert!(self.loaded && a.ncols() == self.n && a.nrows() == self.n, "refactor without matching factors");
        // Slices bound once: a store into `work` through `self` would make the compiler load every field
        // of `self` again in the inner loop (it cannot tell the stored numbers from the vectors' lengths),
        // which doubled the instructions of a refactorization.
        let (l_start, l_rows, l_values) = (&self.l_start[..], &self.l_rows[..], &mut self.l_values[..]);
        let (u_start, u_rows, u_values) = (&self.u_start[..], &self.u_rows[..], &mut self.u_values[..]);
        let (work, row_position, u_diagonal) = (&mut self.work[..], &self.row_position[..], &mut self.u_diagonal[..]);
        let (supernode_last, shared, run) = (&self.supernode_last[..], &mut self.shared[..], &mut self.run[..]);
        for (j, &column) in self.column_order.iter().enumerate() {
            for (&r, &x) in a.row_idx_of_col_raw(column).iter().zip(a.val_of_col(column)) {
                work[row_position[r]] = x;
            }
            // x = L(0..j, 0..j)⁻¹ a_j over U(:, j)'s pattern, in increasing pivot order, a supernode's
            // run of columns at a time (each row takes the same updates in the same order).
            let pattern = &u_rows[u_start[j]..u_start[j + 1]];
            let u_column = &mut u_values[u_start[j]..u_start[j + 1]];
            let mut i = 0;
            while i < pattern.len() {
                let k = pattern[i];
                let last = supernode_last[k].min(j - 1);
                let width = last - k + 1;
                debug_assert!(pattern[i..i + width].iter().copied().eq(k..=last), "a supernode's run is in the reach");
                let run = &mut run[..width];
                for m in k..=last {
                    let xm = std::mem::replace(&mut work[m], 0.0);
                    u_column[i + m - k] = xm;
                    run[m - k] = xm;
                    // The rows m + 1..=last of the run.
                    let triangle = &l_values[l_start[m]..l_start[m] + (last - m)];
                    for (w, &l) in work[m + 1..=last].iter_mut().zip(triangle) {
                        *w -= l * xm;
                    }
                }
                update_shared_rows(work, shared, &l_rows[l_start[last]..l_start[last + 1]], run, |m| {
                    &l_values[l_start[k + m] + (last - k - m)..l_start[k + m + 1]]
                });
                i += width;
            }
            let pivot = std::mem::replace(&mut work[j], 0.0);
            u_diagonal[j] = pivot;
            let candidates = l_start[j]..l_start[j + 1];
            let largest = l_rows[candidates.clone()].iter().fold(0.0_f64, |m, &r| m.max(work[r].abs()));
            let kept = pivot != 0.0 && pivot.is_finite() && largest.is_finite() && pivot.abs() >= PIVOT_THRESHOLD * largest;
            if !kept {
                work.fill(0.0);
                self.loaded = false;
                return Err(RefactorFailure::PivotTooSmall { step: j });
            }
            let reciprocal = pivot.recip();
            for (&r, l) in l_rows[candidates.clone()].iter().zip(&mut l_values[candidates]) {
                *l = std::mem::replace(&mut work[r], 0.0) * reciprocal;
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place with the factors (`rhs` holds `b` on entry and `x` on return), using
    /// the work column as scratch. Allocates nothing.
    ///
    /// # Panics
    /// If no factors are loaded or `rhs` is not of their dimension.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        assert!(self.loaded && rhs.len() == self.n, "solve without matching factors");
        let y = &mut self.work[..];
        let (l_start, l_rows, l_values) = (&self.l_start[..], &self.l_rows[..], &self.l_values[..]);
        let (u_start, u_rows, u_values) = (&self.u_start[..], &self.u_rows[..], &self.u_values[..]);
        for (&b, &position) in rhs.iter().zip(&self.row_position) {
            y[position] = b;
        }
        for j in 0..self.n {
            let yj = y[j];
            if yj != 0.0 {
                let column = l_start[j]..l_start[j + 1];
                for (&r, &l) in l_rows[column.clone()].iter().zip(&l_values[column]) {
                    y[r] -= l * yj;
                }
            }
        }
        for (j, &diagonal) in self.u_diagonal.iter().enumerate().rev() {
            let yj = y[j] / diagonal;
            y[j] = yj;
            if yj != 0.0 {
                let column = u_start[j]..u_start[j + 1];
                for (&r, &u) in u_rows[column.clone()].iter().zip(&u_values[column]) {
                    y[r] -= u * yj;
                }
            }
        }
        for (j, &c) in self.column_order.iter().enumerate() {
            rhs[c] = std::mem::replace(&mut y[j], 0.0);
        }
    }
}

/// `work[rows] -= Σ_m column(m) · run[m]` for the rows `rows` that a run of a supernode's columns
/// shares, each row updated by the columns in order (`column(m)` holds column `m`'s values in those rows)
/// and a column with a zero multiplier skipped. A run of one column updates `work` in place; a longer one
/// on a dense copy of the rows (`shared`), so that its inner loops touch contiguous numbers only.
fn update_shared_rows<'a>(work: &mut [f64], shared: &mut [f64], rows: &[usize], run: &[f64], column: impl Fn(usize) -> &'a [f64]) {
    if let [x] = run {
        if *x != 0.0 {
            for (&r, &l) in rows.iter().zip(column(0)) {
                work[r] -= l * x;
            }
        }
        return;
    }
    let shared = &mut shared[..rows.len()];
    for (s, &r) in shared.iter_mut().zip(rows) {
        *s = work[r];
    }
    for (m, &x) in run.iter().enumerate() {
        if x != 0.0 {
            for (s, &l) in shared.iter_mut().zip(column(m)) {
                *s -= l * x;
            }
        }
    }
    for (&s, &r) in shared.iter().zip(rows) {
        work[r] = s;
    }
}

/// Whether `p` holds each of `0..p.len()` once (`seen` is scratch).
fn is_permutation(p: &[usize], seen: &mut Vec<usize>) -> bool {
    seen.clear();
    seen.resize(p.len(), 0);
    p.iter().all(|&k| k < p.len() && std::mem::replace(&mut seen[k], 1) == 0)
}
