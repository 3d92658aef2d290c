//! Rank-revealing sparse QR by rows: the rows of a matrix are rotated one at a time into an upper
//! trapezoidal `R` by Givens rotations (George and Heath, *Solution of sparse linear least squares
//! problems using Givens rotations*, Linear Algebra Appl. 34, 1980), `Q` never formed. A row that
//! depends on the rows taken before it is not kept; so the rows are judged in the order they are given,
//! whatever the column order, which is free and chosen to reduce the fill of `R` (COLAMD on the
//! matrix's pattern).
//!
//! Why the rotations tell whether a row depends on the earlier ones: each row of `R` starts at its own
//! pivot column, and `R`'s rows span the rows kept. Rotating the new row `a` against the row of `R` of
//! each of its pivot columns in turn zeroes `a` there (and keeps `R` upper trapezoidal, with the same
//! span together with `a`). If `a` lies in the span, what is left of it does too, and a combination of
//! `R`'s rows that is zero in the pivot columns before a column `j` without a pivot is zero at `j`: so
//! the first entry left at a column without a pivot is zero, and `a` ends zero. Otherwise that entry
//! is not zero, and what is left becomes a row of `R` with `j` as its pivot. In floating point a
//! dependent row leaves entries at the round-off of its length (rotations are orthogonal), and an entry
//! left at most a tolerance (10⁻⁸ in the redundancy check) of the row's length counts as zero.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::colamd;
use faer::sparse::SymbolicSparseColMatRef;

use super::sparse_rows::SparseRows;

/// A row of `R`: its columns ascending (the first is its pivot column) and values.
#[derive(Clone, Debug, Default)]
struct RRow {
    cols: Vec<usize>,
    values: Vec<f64>,
}

/// The triangular factor `R` of the rows kept so far, and the workspace of the row being rotated in.
#[derive(Debug)]
pub(crate) struct GivensRowQr {
    /// The row of `R` whose pivot is each column, if there is one.
    rows: Vec<Option<RRow>>,
    rank: usize,
    /// The row being rotated in, scattered: its values and which columns are in its pattern.
    work: Vec<f64>,
    in_pattern: Vec<bool>,
    /// Its pattern's columns not yet reached, smallest first.
    ahead: BinaryHeap<Reverse<usize>>,
    merged: RRow,
    /// The rows of `R` as they were before the current row was rotated against them.
    undo: Vec<(usize, RRow)>,
}

impl GivensRowQr {
    /// An empty factorization of rows with `ncols` columns.
    pub(crate) fn new(ncols: usize) -> Self {
        Self {
            rows: vec![None; ncols],
            rank: 0,
            work: vec![0.0; ncols],
            in_pattern: vec![false; ncols],
            ahead: BinaryHeap::new(),
            merged: RRow::default(),
            undo: Vec::new(),
        }
    }

    /// The rows kept so far.
    #[cfg(test)]
    pub(crate) fn rank(&self) -> usize {
        self.rank
    }

    /// Rotates the row of `(column, value)` entries (columns distinct) into `R`. Returns whether it was
    /// kept: `false` when it depends on the rows kept before (a zero row too), and then `R` is left as it
    /// was, so that only the rows kept make it, as Gram–Schmidt orthogonalizes against them alone.
    ///
    /// The row is rotated against `R`'s rows column by column, smallest first. At a column without a row
    /// of `R`, an entry above `tolerance` times the row's length makes it independent: what is left of it
    /// becomes `R`'s row there. An entry at most that is dropped (a change of the row within the
    /// tolerance; for a dependent row it is round-off, since a combination of `R`'s rows that is zero in
    /// the pivot columns before it is zero there too), and the rotations go on.
    pub(crate) fn add_row(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, tolerance: f64) -> bool {
        for (c, x) in entries {
            if !self.in_pattern[c] {
                self.in_pattern[c] = true;
                self.ahead.push(Reverse(c));
            }
            self.work[c] += x;
        }
        let length = self.ahead.iter().map(|Reverse(c)| self.work[*c].powi(2)).sum::<f64>().sqrt();
        let mut kept = false;
        while let Some(Reverse(j)) = self.ahead.pop() {
            if self.rows[j].is_some() && self.work[j] != 0.0 {
                self.rotate_against(j);
            } else if self.work[j].abs() > tolerance * length {
                self.ahead.push(Reverse(j));
                self.insert_row();
                kept = true;
                break;
            } else {
                self.work[j] = 0.0;
                self.in_pattern[j] = false;
            }
        }
        if kept {
            self.rank += 1;
            self.undo.clear();
        } else {
            while let Some((j, row)) = self.undo.pop() {
                self.rows[j] = Some(row);
            }
        }
        kept
    }

    /// Makes what is left of the work row (its columns ahead, the first without a row of `R`) a row of
    /// `R`, and clears the work row.
    fn insert_row(&mut self) {
        let mut cols: Vec<usize> = Vec::with_capacity(self.ahead.len());
        for Reverse(c) in self.ahead.drain() {
            self.in_pattern[c] = false;
            if self.work[c] != 0.0 {
                cols.push(c);
            }
        }
        cols.sort_unstable();
        let values = cols.iter().map(|&c| std::mem::take(&mut self.work[c])).collect();
        let pivot = cols[0];
        self.rows[pivot] = Some(RRow { cols, values });
    }

    /// One Givens rotation of `R`'s row `j` and the work row, zeroing the work row's column `j`:
    /// `[r; w] ← [c s; −s c] [r; w]` with `c = r_j / ρ`, `s = w_j / ρ`, `ρ = hypot(r_j, w_j)`, on the
    /// union of the two patterns (the work row's columns beyond `j` are those still ahead).
    fn rotate_against(&mut self, j: usize) {
        let row = self.rows[j].as_mut().expect("a row of R at its pivot column");
        self.undo.push((j, row.clone()));
        let (rj, wj) = (row.values[0], self.work[j]);
        let rho = rj.hypot(wj);
        let (c, s) = (rj / rho, wj / rho);
        let merged = &mut self.merged;
        merged.cols.clear();
        merged.values.clear();
        merged.cols.extend(self.ahead.iter().map(|Reverse(k)| *k));
        merged.cols.extend(row.cols[1..].iter().filter(|&&k| !self.in_pattern[k]));
        merged.cols.sort_unstable();
        merged.values.resize(merged.cols.len(), 0.0);
        let mut next = 1;
        for (k, value) in merged.cols.iter().zip(merged.values.iter_mut()) {
            let r = if next < row.cols.len() && row.cols[next] == *k {
                next += 1;
                row.values[next - 1]
            } else {
                0.0
            };
            let w = self.work[*k];
            *value = c * r + s * w;
            self.work[*k] = c * w - s * r;
            if !self.in_pattern[*k] {
                self.in_pattern[*k] = true;
                self.ahead.push(Reverse(*k));
            }
        }
        row.cols.truncate(1);
        row.values.truncate(1);
        row.values[0] = rho;
        row.cols.extend_from_slice(&merged.cols);
        row.values.extend_from_slice(&merged.values);
        self.work[j] = 0.0;
        self.in_pattern[j] = false;
    }
}

/// Which rows of `a` depend on the rows before them: each row is rotated into a [`GivensRowQr`] in row
/// order, its columns in a fill-reducing order, and is dependent when what is left of it is at most
/// `tolerance` of its length.
pub(crate) fn dependent_rows(a: &SparseRows, tolerance: f64) -> Vec<bool> {
    let position = fill_reducing_column_order(a);
    let mut qr = GivensRowQr::new(a.ncols());
    (0..a.nrows())
        .map(|r| {
            let (cols, values) = a.row(r);
            !qr.add_row(cols.iter().zip(values).map(|(c, x)| (position[*c], *x)), tolerance)
        })
        .collect()
}

/// The position of each column of `a` in a column order that keeps `R` sparse: COLAMD (Davis, Gilbert,
/// Larimore and Ng 2004), which orders for a sparse Cholesky factor of `aᵀa`, i.e. for `R`.
fn fill_reducing_column_order(a: &SparseRows) -> Vec<usize> {
    let (m, n) = (a.nrows(), a.ncols());
    let identity = || (0..n).collect();
    if a.nnz() == 0 {
        return identity();
    }
    let column_rows = a.column_rows();
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(a.nnz());
    col_ptr.push(0);
    for rows in &column_rows {
        row_idx.extend_from_slice(rows);
        col_ptr.push(row_idx.len());
    }
    let pattern = SymbolicSparseColMatRef::new_checked(m, n, &col_ptr, None, &row_idx);
    let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
    let mut buffer = MemBuffer::new(colamd::order_scratch::<usize>(m, n, a.nnz()));
    match colamd::order(&mut perm, &mut perm_inv, pattern, colamd::Control::default(), MemStack::new(&mut buffer)) {
        Ok(()) => perm_inv,
        // Any column order gives the same rows; only the fill differs.
        Err(_) => identity(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (64-bit LCG), uniform in [−1, 1).
    struct Random(u64);
    impl Random {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
        fn below(&mut self, n: usize) -> usize {
            ((self.next() + 1.0) * 0.5 * n as f64) as usize % n
        }
    }

    /// `m` random sparse rows of `n` columns: each new row independent (3 random entries) or, with
    /// probability 0.4, a combination of two to four earlier rows; returns the rows and which were made
    /// dependent.
    fn random_rows(random: &mut Random, m: usize, n: usize) -> (SparseRows, Vec<bool>) {
        let mut dense: Vec<Vec<f64>> = Vec::new();
        let mut made_dependent = Vec::new();
        for _ in 0..m {
            let mut row = vec![0.0; n];
            let dependent = !dense.is_empty() && random.next() < -0.2;
            if dependent {
                for _ in 0..2 + random.below(3) {
                    let k = random.below(dense.len());
                    let w = random.next();
                    row.iter_mut().zip(&dense[k]).for_each(|(x, y)| *x += w * y);
                }
            } else {
                for _ in 0..3 {
                    row[random.below(n)] += random.next();
                }
            }
            made_dependent.push(dependent);
            dense.push(row);
        }
        let entries = dense
            .iter()
            .enumerate()
            .flat_map(|(r, row)| row.iter().enumerate().filter(|(_, x)| **x != 0.0).map(move |(c, x)| (r, c, *x)))
            .collect();
        (SparseRows::from_entries(m, n, entries), made_dependent)
    }

    /// The rank of the rows of `a` by dense modified Gram–Schmidt, twice (the reference).
    fn gram_schmidt_dependent(a: &SparseRows, tolerance: f64) -> Vec<bool> {
        let n = a.ncols();
        let mut basis: Vec<Vec<f64>> = Vec::new();
        (0..a.nrows())
            .map(|r| {
                let mut x = vec![0.0; n];
                let (cols, values) = a.row(r);
                cols.iter().zip(values).for_each(|(c, v)| x[*c] = *v);
                let length = a.row_norm(r);
                for _ in 0..2 {
                    for q in &basis {
                        let p: f64 = q.iter().zip(&x).map(|(a, b)| a * b).sum();
                        x.iter_mut().zip(q).for_each(|(x, q)| *x -= p * q);
                    }
                }
                let remainder = x.iter().map(|v| v * v).sum::<f64>().sqrt();
                let dependent = length == 0.0 || remainder <= tolerance * length;
                if !dependent {
                    basis.push(x.iter().map(|v| v / remainder).collect());
                }
                dependent
            })
            .collect()
    }

    #[test]
    fn random_dependent_rows_are_found_as_gram_schmidt_finds_them() {
        let mut random = Random(7);
        for (m, n) in [(5, 3), (20, 12), (60, 40), (200, 150), (300, 90)] {
            for _ in 0..10 {
                let (a, _) = random_rows(&mut random, m, n);
                let sparse = dependent_rows(&a, 1e-8);
                assert_eq!(sparse, gram_schmidt_dependent(&a, 1e-8), "{m}×{n}");
                // The rank is that of the rows, whatever the column order.
                let rank = sparse.iter().filter(|d| !**d).count();
                let mut qr = GivensRowQr::new(n);
                for r in 0..m {
                    let (cols, values) = a.row(r);
                    qr.add_row(cols.iter().zip(values).map(|(c, x)| (n - 1 - c, *x)), 1e-8);
                }
                assert_eq!(qr.rank(), rank);
            }
        }
    }

    #[test]
    fn a_row_made_from_earlier_rows_is_the_one_found() {
        let mut random = Random(11);
        let (a, made_dependent) = random_rows(&mut random, 80, 200);
        // With many more columns than rows, the independent rows stay independent.
        assert_eq!(dependent_rows(&a, 1e-8), made_dependent);
        assert!(made_dependent.iter().filter(|d| **d).count() > 10);
    }

    #[test]
    fn zero_rows_repeated_rows_and_a_full_rank_are_dependent() {
        let entries = vec![(0, 0, 1.0), (1, 0, 2.0), (2, 1, 3.0), (3, 0, 1.0), (3, 1, 1.0), (5, 1, 1.0)];
        let a = SparseRows::from_entries(6, 2, entries);
        assert_eq!(dependent_rows(&a, 1e-8), [false, true, false, true, true, true].to_vec());
    }
}
