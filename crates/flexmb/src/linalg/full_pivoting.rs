//! Which columns Gaussian elimination with full pivoting takes as pivots in a sparse `m × n` matrix
//! (`m ≤ n`), on its rows alone: at each step the entry of largest magnitude among the rows not yet
//! eliminated and the columns not yet chosen, its row swapped to the current position and eliminated
//! from the rows below. The pivot columns are the dependent coordinates of a coordinate partitioning
//! (Wehage and Haug 1982), the rest the independent ones.
//!
//! The choice is that of the dense elimination it replaced, to the last bit: the same arithmetic on
//! the entries (a row's update `a_i ← a_i − (a_ij / a_kj) a_k` over the pivot row's entries, nothing
//! else changes), and among entries of equal magnitude the same tie-break, the row at the smallest
//! position (the dense elimination's row exchanges tracked) and then the smallest column. The largest
//! entry is kept by a heap of candidates: every entry of a row is pushed when the row is updated or
//! moved, with the row's stamp, so that an entry of an older stamp, an eliminated row or a chosen
//! column is stale and skipped when it comes up. The work is that of the updates, the entries and the
//! fill, times the heap's logarithm: on a chain of bodies the rows merged by an elimination are a
//! body's neighbours, so the fill stays within the neighbouring bodies' coordinates whatever the order
//! (`O(m log m)` for the chain of 1,024 rods, against the dense `O(m² n)`).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// An entry as a pivot candidate: larger magnitude first, then the smaller row position, then the
/// smaller column (the dense scan's order).
#[derive(Clone, Copy, Debug)]
struct Candidate {
    magnitude: f64,
    position: usize,
    column: usize,
    row: usize,
    stamp: usize,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        self.magnitude
            .total_cmp(&other.magnitude)
            .then_with(|| other.position.cmp(&self.position))
            .then_with(|| other.column.cmp(&self.column))
    }
}

/// The rows during the elimination, and the candidates.
struct Elimination {
    /// Each row's entries in the columns not chosen, columns ascending.
    rows: Vec<Vec<(usize, f64)>>,
    /// The rows that hold (or held) an entry in each column.
    column_rows: Vec<Vec<usize>>,
    position: Vec<usize>,
    row_at: Vec<usize>,
    eliminated: Vec<bool>,
    chosen: Vec<bool>,
    stamp: Vec<usize>,
    heap: BinaryHeap<Candidate>,
}

impl Elimination {
    /// Pushes every entry of row `i` as a candidate with a new stamp (its older candidates go stale).
    fn push_row(&mut self, i: usize) {
        self.stamp[i] += 1;
        for &(column, value) in &self.rows[i] {
            // A zero or NaN never exceeds the dense scan's best, which starts at zero.
            if value.abs() > 0.0 && !self.chosen[column] {
                let candidate = Candidate { magnitude: value.abs(), position: self.position[i], column, row: i, stamp: self.stamp[i] };
                self.heap.push(candidate);
            }
        }
    }

    /// The largest valid candidate, if any is left.
    fn best(&mut self) -> Option<Candidate> {
        while let Some(c) = self.heap.pop() {
            if !self.eliminated[c.row] && !self.chosen[c.column] && c.stamp == self.stamp[c.row] {
                return Some(c);
            }
        }
        None
    }
}

/// The pivots `(row, column)` of Gaussian elimination with full pivoting on the `m × ncols` matrix whose
/// row `i` has the columns `cols[row_ptr[i]..row_ptr[i + 1]]` (ascending) and the values at the same
/// places, in the order they are chosen; `None` if the rows are dependent (no nonzero entry is left
/// before the `m`-th pivot).
pub(crate) fn full_pivoting(ncols: usize, row_ptr: &[usize], cols: &[usize], values: &[f64]) -> Option<Vec<(usize, usize)>> {
    let m = row_ptr.len() - 1;
    let rows: Vec<Vec<(usize, f64)>> =
        (0..m).map(|i| (row_ptr[i]..row_ptr[i + 1]).map(|e| (cols[e], values[e])).collect()).collect();
    let mut column_rows = vec![Vec::new(); ncols];
    for (i, row) in rows.iter().enumerate() {
        for &(c, _) in row {
            column_rows[c].push(i);
        }
    }
    let mut e = Elimination {
        rows,
        column_rows,
        position: (0..m).collect(),
        row_at: (0..m).collect(),
        eliminated: vec![false; m],
        chosen: vec![false; ncols],
        stamp: vec![0; m],
        heap: BinaryHeap::new(),
    };
    for i in 0..m {
        e.push_row(i);
    }
    let mut pivot_columns = Vec::with_capacity(m);
    let (mut pivot_row, mut merged) = (Vec::new(), Vec::new());
    for k in 0..m {
        let Candidate { row: bi, column: bj, .. } = e.best()?;
        // The dense elimination's row exchange: the row at position k moves to the pivot row's.
        let moved = e.row_at[k];
        let p = e.position[bi];
        (e.row_at[p], e.position[moved]) = (moved, p);
        (e.row_at[k], e.position[bi]) = (bi, k);
        e.eliminated[bi] = true;
        e.chosen[bj] = true;
        pivot_columns.push((bi, bj));
        let pivot = e.rows[bi].iter().find(|(c, _)| *c == bj).map_or(0.0, |(_, v)| *v);
        pivot_row.clear();
        pivot_row.extend(e.rows[bi].iter().filter(|(c, _)| !e.chosen[*c]));
        let mut updated_moved = false;
        for i in std::mem::take(&mut e.column_rows[bj]) {
            if e.eliminated[i] {
                continue;
            }
            let a_ij = e.rows[i].binary_search_by_key(&bj, |(c, _)| *c).map_or(0.0, |s| e.rows[i][s].1);
            let f = a_ij / pivot;
            if f == 0.0 {
                continue;
            }
            // a_i ← a_i − f a_k over the columns not chosen (a fill entry starts at zero, as dense).
            merged.clear();
            let (mut s, mut t) = (0, 0);
            let row = &e.rows[i];
            while s < row.len() || t < pivot_row.len() {
                let (a, b) = (row.get(s).copied(), pivot_row.get(t).copied());
                let order = match (a, b) {
                    (Some((ca, _)), Some((cb, _))) => ca.cmp(&cb),
                    (Some(_), None) => Ordering::Less,
                    _ => Ordering::Greater,
                };
                match (order, a, b) {
                    (Ordering::Equal, Some((ca, va)), Some((_, vb))) => {
                        merged.push((ca, va - f * vb));
                        (s, t) = (s + 1, t + 1);
                    }
                    (Ordering::Less, Some((ca, va)), _) => {
                        if !e.chosen[ca] {
                            merged.push((ca, va));
                        }
                        s += 1;
                    }
                    (_, _, Some((cb, vb))) => {
                        merged.push((cb, 0.0 - f * vb));
                        e.column_rows[cb].push(i);
                        t += 1;
                    }
                    _ => unreachable!("the loop runs while an entry is left"),
                }
            }
            std::mem::swap(&mut e.rows[i], &mut merged);
            e.push_row(i);
            updated_moved |= i == moved;
        }
        if moved != bi && !updated_moved {
            e.push_row(moved);
        }
    }
    Some(pivot_columns)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense elimination with full pivoting the sparse one replaces (the Adams method's partition
    /// before), on a row-major `m × n` matrix.
    fn dense_full_pivoting(mut e: Vec<f64>, m: usize, nq: usize) -> Option<Vec<usize>> {
        let mut chosen = vec![false; nq];
        let mut columns = Vec::new();
        for k in 0..m {
            let (mut best, mut bi, mut bj) = (0.0_f64, k, usize::MAX);
            for i in k..m {
                for j in 0..nq {
                    if !chosen[j] && e[i * nq + j].abs() > best {
                        (best, bi, bj) = (e[i * nq + j].abs(), i, j);
                    }
                }
            }
            if bj == usize::MAX {
                return None;
            }
            for j in 0..nq {
                e.swap(k * nq + j, bi * nq + j);
            }
            let pivot = e[k * nq + bj];
            for i in k + 1..m {
                let f = e[i * nq + bj] / pivot;
                if f != 0.0 {
                    for j in 0..nq {
                        e[i * nq + j] -= f * e[k * nq + j];
                    }
                }
            }
            columns.push(bj);
            chosen[bj] = true;
        }
        Some(columns)
    }

    /// A 64-bit linear congruential generator (Knuth's MMIX constants).
    fn next(seed: &mut u64) -> u64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        *seed >> 33
    }

    /// Random sparse matrices with many ties (entries from a few values, as the unit coefficients of
    /// joint rows), banded as a chain's and with far entries as a loop's, some rank-deficient: the
    /// sparse elimination chooses the dense one's columns in the same order, or finds no pivot too.
    #[test]
    fn the_sparse_choice_is_the_dense_one() {
        let mut seed = 5;
        let mut dependent_found = 0;
        for trial in 0..300 {
            let m = 1 + (next(&mut seed) % 24) as usize;
            let n = m + (next(&mut seed) % 20) as usize;
            let mut dense = vec![0.0; m * n];
            for i in 0..m {
                let band = (i * n / m).min(n - 1);
                for _ in 0..1 + next(&mut seed) % 5 {
                    let c = if next(&mut seed) % 6 == 0 { next(&mut seed) as usize % n } else { (band + next(&mut seed) as usize % 4).min(n - 1) };
                    dense[i * n + c] = [1.0, -1.0, 2.0, 0.5, -0.25, 0.3][next(&mut seed) as usize % 6];
                }
                if trial % 7 == 0 && i > 0 && next(&mut seed) % 4 == 0 {
                    // A row repeating the one before: rank-deficient.
                    let (before, row) = dense.split_at_mut(i * n);
                    row[..n].copy_from_slice(&before[(i - 1) * n..i * n]);
                }
            }
            let (mut row_ptr, mut cols, mut values) = (vec![0], Vec::new(), Vec::new());
            for i in 0..m {
                for c in 0..n {
                    if dense[i * n + c] != 0.0 {
                        cols.push(c);
                        values.push(dense[i * n + c]);
                    }
                }
                row_ptr.push(cols.len());
            }
            let expected = dense_full_pivoting(dense, m, n);
            dependent_found += usize::from(expected.is_none());
            let columns = full_pivoting(n, &row_ptr, &cols, &values).map(|p| p.iter().map(|&(_, c)| c).collect::<Vec<_>>());
            assert_eq!(columns, expected, "trial {trial}: {m} × {n}");
        }
        assert!(dependent_found > 5, "{dependent_found} rank-deficient matrices");
    }
}
