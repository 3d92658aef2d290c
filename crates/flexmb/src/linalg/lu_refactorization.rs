//! LU factors on a fixed pattern and pivot sequence, refactored with new numbers: the left-looking
//! refactorization of KLU (Davis and Palamadai Natarajan 2010, `klu_refactor`), which reuses the row
//! pivots and the structure of `L` and `U` found by a factorization with partial pivoting (faer's
//! Gilbert–Peierls LU) and so skips its depth-first searches, its pivot search and its storage growth.
//!
//! With `P A Q = L U` (`P` the row pivots, `Q` the fill-reducing column order, `L` unit lower and `U`
//! upper triangular), column `j` of the factors is the sparse triangular solve
//! `L(0..j, 0..j) x = (P A Q)(0..j, j)` over the pattern of `U(:, j)`, taken in the topological order
//! the pivoting factorization found (its depth-first search); then `U(j, j) = x_j` and
//! `L(:, j) = x · (1 / x_j)` below the diagonal. The reach of every column is that of the pivoting
//! factorization, so no entry falls outside the stored pattern, and the operations are those of the
//! pivoting factorization in the same order: with the same pivots, the factors are the same to the last
//! bit. A kept pivot is used only while it is the one partial pivoting would choose: the first largest
//! candidate of its column, in the order of the pivoting factorization's depth-first search, which is
//! replayed once when the factors are loaded;
//! otherwise [`refactor`](LuFactors::refactor) reports it and the caller factors afresh with pivoting.
//! So the factors never depend on the values factored before: a run resumed from a checkpoint, or a
//! matrix factored by a fresh solver, gives the same numbers to the last bit.

use faer::sparse::linalg::lu::simplicial::SimplicialLu;
use faer::sparse::SparseColMatRef;

/// Why a refactorization with the kept pivots was not completed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefactorFailure {
    /// The kept pivot of a column is no longer strictly the largest candidate of its column (or is zero
    /// or not finite): partial pivoting would choose another.
    PivotTooSmall,
}

/// `P A Q = L U` stored by columns in the permuted numbering: the strictly lower part of `L` (its unit
/// diagonal implied), the strictly upper part of `U` with its rows in the order of elimination, and
/// `U`'s diagonal.
#[derive(Debug, Default)]
pub struct LuFactors {
    /// Whether factors are held (set by `load`, cleared by a failed refactorization).
    loaded: bool,
    n: usize,
    /// Position in the pivot order of each row of `A`.
    row_position: Vec<usize>,
    /// Column of `A` taken at each step (the fill-reducing order `Q`).
    column_order: Vec<usize>,
    l_start: Vec<usize>,
    l_rows: Vec<usize>,
    l_values: Vec<f64>,
    u_start: Vec<usize>,
    u_rows: Vec<usize>,
    u_values: Vec<f64>,
    u_diagonal: Vec<f64>,
    /// For each column, how many entries of `L(:, j)` came before the pivot among the candidates of
    /// partial pivoting (the order of its depth-first search): those must stay strictly smaller than
    /// the pivot, the others no larger, for partial pivoting to choose it again.
    pivot_rank: Vec<usize>,
    /// The dense column being eliminated (all zeros between calls).
    work: Vec<f64>,
    /// Scratch of the replayed depth-first search: marks, the output (and head) list, the stack.
    marked: Vec<usize>,
    reach_list: Vec<usize>,
    dfs_stack: Vec<usize>,
}

impl LuFactors {
    /// Whether factors (a pattern and pivots) are held.
    pub fn is_loaded(&self) -> bool {
        self.loaded
    }

    /// Entries stored in `L` and `U` together, their diagonals included.
    #[cfg(test)]
    pub fn factor_entries(&self) -> usize {
        self.l_rows.len() + self.u_rows.len() + 2 * self.n
    }

    /// Takes the pattern, pivots and values of a pivoting factorization `P A Q = L U` (`lu` from faer's
    /// simplicial LU, whose row indices are already in the pivot order; `row_position[i]` the position
    /// of row `i` of `A`; `column_order[j]` the column of `A` at step `j`). Reuses the storage of the
    /// previous factors, so it allocates only when the new factors are larger.
    pub fn load(
        &mut self,
        a: SparseColMatRef<'_, usize, f64>,
        lu: &SimplicialLu<usize, f64>,
        row_position: &[usize],
        column_order: &[usize],
    ) {
        let n = lu.ncols();
        self.n = n;
        self.loaded = true;
        self.row_position.clear();
        self.row_position.extend_from_slice(row_position);
        self.column_order.clear();
        self.column_order.extend_from_slice(column_order);
        self.work.clear();
        self.work.resize(n, 0.0);
        self.u_diagonal.clear();
        self.u_diagonal.resize(n, 0.0);
        // L's unit diagonal is implied; U's is kept apart.
        off_diagonal(lu.l_factor_unsorted(), [&mut self.l_start, &mut self.l_rows], &mut self.l_values, |_, _| {});
        let diagonal = &mut self.u_diagonal;
        off_diagonal(lu.u_factor_unsorted(), [&mut self.u_start, &mut self.u_rows], &mut self.u_values, |j, x| diagonal[j] = x);
        self.find_pivot_ranks(a);
    }

    /// Replays the depth-first searches of the pivoting factorization (faer's `reach`, in the permuted
    /// numbering, where row `k` has an `L` column at step `j` if `k < j`) to find where each pivot stood
    /// among its column's candidates, `pivot_rank`.
    fn find_pivot_ranks(&mut self, a: SparseColMatRef<'_, usize, f64>) {
        let n = self.n;
        self.pivot_rank.clear();
        self.pivot_rank.resize(n, 0);
        self.marked.clear();
        self.marked.resize(n, 0);
        self.reach_list.clear();
        self.reach_list.resize(n, 0);
        self.dfs_stack.clear();
        self.dfs_stack.resize(n, 0);
        for j in 0..n {
            let mark = j + 1;
            let mut tail = n;
            for &r in a.row_idx_of_col_raw(self.column_order[j]) {
                let b = self.row_position[r];
                if self.marked[b] < mark {
                    tail = self.depth_first_search(b, j, mark, tail);
                }
            }
            let before = self.reach_list[tail..n].iter().take_while(|&&k| k != j).filter(|&&k| k > j).count();
            self.pivot_rank[j] = before;
        }
    }

    /// One depth-first search from `b` over the `L` columns of the rows pivoted before step `j`; its
    /// nodes in reverse post-order are put before `tail` in `reach_list`; returns the new tail.
    fn depth_first_search(&mut self, b: usize, j: usize, mark: usize, mut tail: usize) -> usize {
        let mut head = 1;
        self.reach_list[0] = b;
        'search: while head > 0 {
            let node = self.reach_list[head - 1];
            let range = if node < j { self.l_start[node]..self.l_start[node + 1] } else { 0..0 };
            if self.marked[node] < mark {
                self.marked[node] = mark;
                self.dfs_stack[head - 1] = range.start;
            }
            for ptr in self.dfs_stack[head - 1]..range.end {
                let i = self.l_rows[ptr];
                if self.marked[i] == mark {
                    continue;
                }
                self.dfs_stack[head - 1] = ptr;
                self.reach_list[head] = i;
                head += 1;
                continue 'search;
            }
            head -= 1;
            tail -= 1;
            self.reach_list[tail] = node;
        }
        tail
    }

    /// Multiply–adds of one refactorization: for each column `j`, the entries of `L(:, k)` for every
    /// `k` in `U(:, j)`'s pattern, and the divisions of `L(:, j)`.
    #[cfg(test)]
    pub fn refactor_operations(&self) -> usize {
        let l_len = |k: usize| self.l_start[k + 1] - self.l_start[k];
        (0..self.n).map(|j| self.u_rows[self.u_start[j]..self.u_start[j + 1]].iter().map(|&k| l_len(k)).sum::<usize>() + l_len(j)).sum()
    }

    /// Whether every pivot (diagonal of `U`) is non-zero and finite.
    pub fn pivots_are_regular(&self) -> bool {
        self.u_diagonal.iter().all(|d| *d != 0.0 && d.is_finite())
    }

    /// Refactors `a` (the pattern of the loaded factors' matrix, new values) with the kept pivots and
    /// patterns. Allocates nothing. On failure the factors are unusable until the next
    /// [`load`](Self::load) or successful refactorization.
    ///
    /// # Panics
    /// If no factors are loaded or `a` is not of their dimension (a bug of the caller).
    pub fn refactor(&mut self, a: SparseColMatRef<'_, usize, f64>) -> Result<(), RefactorFailure> {
        assert!(self.is_loaded() && a.ncols() == self.n && a.nrows() == self.n, "refactor without matching factors");
        for j in 0..self.n {
            let column = self.column_order[j];
            for (&r, &x) in a.row_idx_of_col_raw(column).iter().zip(a.val_of_col(column)) {
                self.work[self.row_position[r]] = x;
            }
            // x = L(0..j, 0..j)⁻¹ a_j over U(:, j)'s pattern, in the pivoting factorization's order.
            for p in self.u_start[j]..self.u_start[j + 1] {
                let k = self.u_rows[p];
                let xk = self.work[k];
                self.work[k] = 0.0;
                self.u_values[p] = xk;
                let column_of_l = self.l_start[k]..self.l_start[k + 1];
                for (&r, &l) in self.l_rows[column_of_l.clone()].iter().zip(&self.l_values[column_of_l]) {
                    self.work[r] -= l * xk;
                }
            }
            let pivot = self.work[j];
            self.work[j] = 0.0;
            self.u_diagonal[j] = pivot;
            // The kept pivot must be the one partial pivoting chooses: the first largest candidate.
            let reciprocal = pivot.recip();
            let magnitude = pivot.abs();
            let mut chosen = true;
            for (t, q) in (self.l_start[j]..self.l_start[j + 1]).enumerate() {
                let r = self.l_rows[q];
                let x = self.work[r];
                chosen &= if t < self.pivot_rank[j] { x.abs() < magnitude } else { x.abs() <= magnitude };
                self.l_values[q] = x * reciprocal;
                self.work[r] = 0.0;
            }
            if pivot == 0.0 || !pivot.is_finite() || !chosen {
                self.work.fill(0.0);
                self.loaded = false;
                return Err(RefactorFailure::PivotTooSmall);
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
        assert!(self.is_loaded() && rhs.len() == self.n, "solve without matching factors");
        let y = &mut self.work;
        for (i, b) in rhs.iter().enumerate() {
            y[self.row_position[i]] = *b;
        }
        for j in 0..self.n {
            let yj = y[j];
            if yj != 0.0 {
                let column = self.l_start[j]..self.l_start[j + 1];
                for (&r, &l) in self.l_rows[column.clone()].iter().zip(&self.l_values[column]) {
                    y[r] -= l * yj;
                }
            }
        }
        for j in (0..self.n).rev() {
            let yj = y[j] / self.u_diagonal[j];
            y[j] = yj;
            if yj != 0.0 {
                let column = self.u_start[j]..self.u_start[j + 1];
                for (&r, &u) in self.u_rows[column.clone()].iter().zip(&self.u_values[column]) {
                    y[r] -= u * yj;
                }
            }
        }
        for (j, &c) in self.column_order.iter().enumerate() {
            rhs[c] = y[j];
            y[j] = 0.0;
        }
    }
}

/// Copies the off-diagonal entries of the square `m` by columns, in their stored order, into `starts`
/// (column starts, `n + 1` of them), `rows` and `values`, handing each diagonal entry to `on_diagonal`.
fn off_diagonal(
    m: SparseColMatRef<'_, usize, f64>,
    [starts, rows]: [&mut Vec<usize>; 2],
    values: &mut Vec<f64>,
    mut on_diagonal: impl FnMut(usize, f64),
) {
    starts.clear();
    rows.clear();
    values.clear();
    starts.push(0);
    for j in 0..m.ncols() {
        for (&r, &x) in m.row_idx_of_col_raw(j).iter().zip(m.val_of_col(j)) {
            if r == j {
                on_diagonal(j, x);
            } else {
                rows.push(r);
                values.push(x);
            }
        }
        starts.push(rows.len());
    }
}
