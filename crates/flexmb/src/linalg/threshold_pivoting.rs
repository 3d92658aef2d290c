//! Which columns Gaussian elimination takes as pivots in a sparse `m × n` matrix (`m ≤ n`), on its
//! rows alone, with threshold full pivoting and Markowitz's choice among the entries that pass: at each
//! step the candidates are the entries of the rows not yet eliminated in the columns not yet chosen
//! whose magnitude is at least `threshold` times the largest one's, and of those the one of least
//! Markowitz cost `(r − 1)(c − 1)` is taken (`r` the entries of its row, `c` the rows holding its
//! column, both among those left), its row eliminated from the others (`a_i ← a_i − (a_ij / a_kj) a_k`
//! over the pivot row's entries). The pivot columns are the dependent coordinates of a coordinate
//! partitioning (Wehage and Haug 1982), the rest the independent ones.
//!
//! **Why a threshold.** Full pivoting (`threshold = 1`) takes the largest entry, and is the choice of
//! the dense elimination: without ties of magnitude it takes the same columns. But it takes them in the
//! order of their magnitudes wherever they are in the matrix, and among equal magnitudes (the unit
//! coefficients of joint rows) by position, blind to the fill: on a straight chain of rods it eliminated
//! a third of the joints from the far end back, each joint's rows taking the fill of the one after it,
//! `O(m²)` fill and work (0.32 s at 1,024 rods, ×4 per doubling). With a threshold the multipliers stay
//! bounded by `1 / threshold` (1 with full pivoting), so does the growth of the entries per step
//! (`1 + 1 / threshold`), and the choice among the entries that pass is left to the fill: the chain's
//! rows are then eliminated along their neighbours, a bounded work per pivot. The partition takes
//! [`PARTITION_THRESHOLD`]. (If an update makes an entry larger than the largest before it, the bar
//! stays where it was, so such a pivot is at least `threshold` times an earlier largest entry.)
//!
//! **The work.** Each entry is a candidate when its row is pushed (at the start, after each update of
//! the row, and when a pivot row leaves one of its columns), with its magnitude, its row's stamp and
//! its Markowitz cost then; a candidate of an older stamp, of an eliminated row or of a chosen column
//! is stale and skipped when it comes up. Exact zeros are left out of the rows. Three heaps hold the
//! candidates: by magnitude for the largest entry left, by magnitude for those below the bar
//! (`threshold ×` the largest entry left, never raised during an elimination), and by cost for those
//! above it; a candidate passes from the second to the third once. So the work is that of the
//! updates and of the rows pushed again, times the heaps' logarithm: bounded per pivot on a chain of
//! bodies (`the_work_on_a_chain_grows_with_its_length`). A cost is still approximate where an update
//! of another row fills a column (its count grows without the column's rows being pushed again); it
//! only guides the choice among the entries above the bar, which alone bounds the pivots.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The threshold of the Adams method's partition: a pivot at least a tenth of the largest entry left,
/// the multipliers at most 10. The usual value of threshold pivoting in sparse LU codes (Duff, Erisman
/// and Reid, *Direct Methods for Sparse Matrices*; MA48's and UMFPACK's default), the balance
/// between the factors' sparsity and the growth of their entries; here it keeps the pivots of the
/// joints' unit coefficients and of the Euler parameters' normalization (2 pᵢ) together in the choice.
pub(crate) const PARTITION_THRESHOLD: f64 = 0.1;

/// An entry as a pivot candidate.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    magnitude: f64,
    /// The Markowitz cost `(r − 1)(c − 1)` when the row was pushed.
    cost: usize,
    row: usize,
    column: usize,
    stamp: usize,
}

impl Candidate {
    /// Larger magnitude first, then the smaller row and column.
    fn by_magnitude(&self, other: &Self) -> Ordering {
        self.magnitude
            .total_cmp(&other.magnitude)
            .then_with(|| other.row.cmp(&self.row))
            .then_with(|| other.column.cmp(&self.column))
    }

    /// Smaller cost first, then as [`by_magnitude`](Self::by_magnitude).
    fn by_cost(&self, other: &Self) -> Ordering {
        other.cost.cmp(&self.cost).then_with(|| self.by_magnitude(other))
    }
}

/// A candidate in a heap by magnitude.
#[derive(Clone, Copy, Debug)]
struct ByMagnitude(Candidate);

/// A candidate in a heap by Markowitz cost.
#[derive(Clone, Copy, Debug)]
struct ByCost(Candidate);

macro_rules! heap_order {
    ($name:ident, $order:ident) => {
        impl PartialEq for $name {
            fn eq(&self, other: &Self) -> bool {
                self.cmp(other) == Ordering::Equal
            }
        }
        impl Eq for $name {}
        impl PartialOrd for $name {
            fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
                Some(self.cmp(other))
            }
        }
        impl Ord for $name {
            fn cmp(&self, other: &Self) -> Ordering {
                self.0.$order(&other.0)
            }
        }
    };
}
heap_order!(ByMagnitude, by_magnitude);
heap_order!(ByCost, by_cost);

/// The rows during the elimination, and the candidates.
struct Elimination {
    threshold: f64,
    /// Each row's entries, columns ascending (entries of chosen columns are dropped when it is updated).
    rows: Vec<Vec<(usize, f64)>>,
    /// The rows that hold (or held) an entry in each column.
    column_rows: Vec<Vec<usize>>,
    /// The rows left that hold an entry in each column.
    column_count: Vec<usize>,
    eliminated: Vec<bool>,
    chosen: Vec<bool>,
    stamp: Vec<usize>,
    /// Every candidate, for the largest entry left.
    largest: BinaryHeap<ByMagnitude>,
    /// The bar a candidate must reach: the threshold times the smallest of the largest entries left
    /// at the steps so far.
    bar: f64,
    /// The candidates below the bar.
    waiting: BinaryHeap<ByMagnitude>,
    /// The candidates that have reached it.
    eligible: BinaryHeap<ByCost>,
    /// The entries of the rows the updates made, for the tests.
    work: usize,
}

impl Elimination {
    /// Pushes every entry of row `i` as a candidate with a new stamp (its older candidates go stale).
    fn push_row(&mut self, i: usize) {
        self.stamp[i] += 1;
        let length = self.rows[i].iter().filter(|(c, _)| !self.chosen[*c]).count();
        for &(column, value) in &self.rows[i] {
            // A zero or NaN is never a pivot.
            if value.abs() > 0.0 && !self.chosen[column] {
                let cost = (length - 1) * self.column_count[column].saturating_sub(1);
                let candidate = Candidate { magnitude: value.abs(), cost, row: i, column, stamp: self.stamp[i] };
                self.largest.push(ByMagnitude(candidate));
                self.waiting.push(ByMagnitude(candidate));
            }
        }
    }

    fn is_current(&self, c: &Candidate) -> bool {
        !self.eliminated[c.row] && !self.chosen[c.column] && c.stamp == self.stamp[c.row]
    }

    /// The candidate of least cost among those above the bar, if any is left; the bar is lowered to the
    /// threshold times the largest entry left if that is below it.
    fn next_pivot(&mut self) -> Option<Candidate> {
        let largest = loop {
            let &ByMagnitude(c) = self.largest.peek()?;
            if self.is_current(&c) {
                break c.magnitude;
            }
            self.largest.pop();
        };
        self.bar = self.bar.min(self.threshold * largest);
        while let Some(&ByMagnitude(c)) = self.waiting.peek() {
            if self.is_current(&c) && c.magnitude < self.bar {
                break;
            }
            self.waiting.pop();
            if self.is_current(&c) {
                self.eligible.push(ByCost(c));
            }
        }
        // The largest entry is among the eligible ones, so this finds a pivot.
        while let Some(ByCost(c)) = self.eligible.pop() {
            if self.is_current(&c) {
                return Some(c);
            }
        }
        None
    }
}

/// The pivots `(row, column)` of Gaussian elimination with threshold full pivoting and Markowitz's
/// choice (the module's documentation) on the `m × ncols` matrix whose row `i` has the columns
/// `cols[row_ptr[i]..row_ptr[i + 1]]` (ascending) and the values at the same places, in the order they
/// are chosen; `None` if the rows are dependent (no nonzero entry is left before the `m`-th pivot).
pub(crate) fn threshold_pivoting(
    ncols: usize,
    row_ptr: &[usize],
    cols: &[usize],
    values: &[f64],
    threshold: f64,
) -> Option<Vec<(usize, usize)>> {
    eliminate(ncols, row_ptr, cols, values, threshold).map(|(pivots, _)| pivots)
}

/// [`threshold_pivoting`], and the number of entries of the rows its updates made (its work).
fn eliminate(ncols: usize, row_ptr: &[usize], cols: &[usize], values: &[f64], threshold: f64) -> Option<(Vec<(usize, usize)>, usize)> {
    let m = row_ptr.len() - 1;
    // Exact zeros are left out (of the rows, the pivot rows and the updates' results): they are never
    // pivots, and carried along they would spread the pattern (the straight chain's zeros did, with
    // `O(n²)` work) without changing a value.
    let rows: Vec<Vec<(usize, f64)>> = (0..m)
        .map(|i| (row_ptr[i]..row_ptr[i + 1]).filter(|&e| values[e] != 0.0).map(|e| (cols[e], values[e])).collect())
        .collect();
    let mut column_rows = vec![Vec::new(); ncols];
    for (i, row) in rows.iter().enumerate() {
        for &(c, _) in row {
            column_rows[c].push(i);
        }
    }
    let column_count = column_rows.iter().map(Vec::len).collect();
    let mut e = Elimination {
        threshold,
        rows,
        column_rows,
        column_count,
        eliminated: vec![false; m],
        chosen: vec![false; ncols],
        stamp: vec![0; m],
        largest: BinaryHeap::new(),
        bar: f64::INFINITY,
        waiting: BinaryHeap::new(),
        eligible: BinaryHeap::new(),
        work: 0,
    };
    for i in 0..m {
        e.push_row(i);
    }
    let mut pivots = Vec::with_capacity(m);
    let (mut pivot_row, mut merged) = (Vec::new(), Vec::new());
    let mut pushed_at = vec![usize::MAX; m];
    for k in 0..m {
        let Candidate { row: bi, column: bj, .. } = e.next_pivot()?;
        e.eliminated[bi] = true;
        e.chosen[bj] = true;
        pivots.push((bi, bj));
        let pivot = e.rows[bi].iter().find(|(c, _)| *c == bj).map_or(0.0, |(_, v)| *v);
        pivot_row.clear();
        pivot_row.extend(e.rows[bi].iter().filter(|(c, v)| !e.chosen[*c] && *v != 0.0));
        // The pivot row leaves its columns.
        for &(c, _) in &pivot_row {
            e.column_count[c] -= 1;
        }
        for i in std::mem::take(&mut e.column_rows[bj]) {
            if e.eliminated[i] {
                continue;
            }
            let a_ij = e.rows[i].binary_search_by_key(&bj, |(c, _)| *c).map_or(0.0, |s| e.rows[i][s].1);
            let f = a_ij / pivot;
            if f == 0.0 {
                continue;
            }
            // a_i ← a_i − f a_k over the columns not chosen (a fill entry starts at zero).
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
                        let x = va - f * vb;
                        if x == 0.0 {
                            e.column_count[ca] -= 1;
                        } else {
                            merged.push((ca, x));
                        }
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
                        e.column_count[cb] += 1;
                        t += 1;
                    }
                    _ => unreachable!("the loop runs while an entry is left"),
                }
            }
            e.work += merged.len();
            std::mem::swap(&mut e.rows[i], &mut merged);
            e.push_row(i);
            pushed_at[i] = k;
        }
        // The rows left in the pivot row's columns have new costs: their columns' counts fell (a row
        // whose other rows are all eliminated is then a pivot without updates, and not left to grow).
        for &(c, _) in &pivot_row {
            for s in 0..e.column_rows[c].len() {
                let i = e.column_rows[c][s];
                if !e.eliminated[i] && pushed_at[i] != k {
                    e.push_row(i);
                    pushed_at[i] = k;
                }
            }
        }
    }
    Some((pivots, e.work))
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

    /// A random sparse matrix with `m` rows over `n` columns, banded as a chain's and with far entries
    /// as a loop's, its entries from `value`, some rows repeating the one before (rank-deficient) when
    /// `dependent`: the dense row-major matrix and its rows (`row_ptr`, `cols`, `values`).
    fn random_matrix(seed: &mut u64, m: usize, n: usize, dependent: bool, value: impl Fn(&mut u64) -> f64) -> (Vec<f64>, Vec<usize>, Vec<usize>, Vec<f64>) {
        let mut dense = vec![0.0; m * n];
        for i in 0..m {
            let band = (i * n / m).min(n - 1);
            for _ in 0..1 + next(seed) % 5 {
                let c = if next(seed) % 6 == 0 { next(seed) as usize % n } else { (band + next(seed) as usize % 4).min(n - 1) };
                dense[i * n + c] = value(seed);
            }
            if dependent && i > 0 && next(seed) % 4 == 0 {
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
        (dense, row_ptr, cols, values)
    }

    fn pivot_columns(pivots: Option<Vec<(usize, usize)>>) -> Option<Vec<usize>> {
        pivots.map(|p| p.iter().map(|&(_, c)| c).collect())
    }

    /// The 2-norm condition number of the columns `columns` of the row-major `m × n` matrix.
    fn condition(dense: &[f64], m: usize, n: usize, columns: &[usize]) -> f64 {
        let a = nalgebra::DMatrix::from_fn(m, m, |i, j| dense[i * n + columns[j]]);
        let s = a.singular_values();
        s.max() / s.min()
    }

    /// Without ties of magnitude (entries uniform in ±[0.5, 2]), at threshold 1 the elimination is full
    /// pivoting and takes the dense elimination's columns in the same order, or finds no pivot too
    /// (repeated rows tie only with their copies, which are eliminated to zero whichever is taken).
    #[test]
    fn without_ties_threshold_one_is_the_dense_full_pivoting() {
        let mut seed = 11;
        let mut dependent_found = 0;
        for trial in 0..300 {
            let m = 1 + (next(&mut seed) % 24) as usize;
            let n = m + (next(&mut seed) % 20) as usize;
            let generic = |s: &mut u64| {
                let x = 0.5 + 1.5 * (next(s) % (1 << 30)) as f64 / (1 << 30) as f64;
                if next(s) % 2 == 0 { x } else { -x }
            };
            let (dense, row_ptr, cols, values) = random_matrix(&mut seed, m, n, trial % 7 == 0, generic);
            let expected = dense_full_pivoting(dense, m, n);
            dependent_found += usize::from(expected.is_none());
            let columns = pivot_columns(threshold_pivoting(n, &row_ptr, &cols, &values, 1.0));
            assert_eq!(columns, expected, "trial {trial}: {m} × {n}");
        }
        assert!(dependent_found > 5, "{dependent_found} rank-deficient matrices");
    }

    /// Random sparse matrices with many ties (entries from a few values, as the unit coefficients of
    /// joint rows), some rank-deficient: at the partition's threshold the elimination finds them
    /// dependent where the dense full pivoting does, and its dependent columns are about as well
    /// conditioned as the dense choice's (2-norm condition numbers; worst and median ratio printed).
    #[test]
    fn the_partition_is_conditioned_as_the_dense_full_pivoting_one() {
        let mut seed = 5;
        let (mut dependent_found, mut ratios) = (0, Vec::new());
        for trial in 0..300 {
            let m = 1 + (next(&mut seed) % 24) as usize;
            let n = m + (next(&mut seed) % 20) as usize;
            let few = |s: &mut u64| [1.0, -1.0, 2.0, 0.5, -0.25, 0.3][next(s) as usize % 6];
            let (dense, row_ptr, cols, values) = random_matrix(&mut seed, m, n, trial % 7 == 0, few);
            let expected = dense_full_pivoting(dense.clone(), m, n);
            let columns = pivot_columns(threshold_pivoting(n, &row_ptr, &cols, &values, PARTITION_THRESHOLD));
            assert_eq!(columns.is_none(), expected.is_none(), "trial {trial}: {m} × {n}");
            let (Some(columns), Some(expected)) = (columns, expected) else {
                dependent_found += 1;
                continue;
            };
            let mut sorted = columns.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), m, "trial {trial}: distinct columns");
            ratios.push(condition(&dense, m, n, &columns) / condition(&dense, m, n, &expected));
        }
        ratios.sort_by(f64::total_cmp);
        let (worst, median) = (ratios[ratios.len() - 1], ratios[ratios.len() / 2]);
        eprintln!("condition number against the dense full pivoting's: median ×{median:.2}, worst ×{worst:.2}");
        assert!(dependent_found > 5, "{dependent_found} rank-deficient matrices");
        assert!(median <= 1.5 && worst <= WORST_CONDITION_RATIO, "median ×{median}, worst ×{worst}");
    }

    /// The worst ratio allowed of the partition's condition number to the dense full pivoting's.
    const WORST_CONDITION_RATIO: f64 = 20.0;

    /// `Φ̂_q` of a chain of `n` rods on spherical joints, the first to ground (the engine's rows: three
    /// per joint, `R_i + A_i s_i − R_j − A_j s_j`, over the two rods' `[R, p]`, then `2 pᵀ` per rod), with
    /// the rods' Euler parameters `p(k)`: its rows.
    fn chain_jacobian(n: usize, p: impl Fn(usize) -> [f64; 4]) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        // ∂(A(p) s)/∂p = 2 [(e₀ I + ẽ) s, e sᵀ − (e₀ I + ẽ) s̃] (Haug, Computer-Aided Kinematics and
        // Dynamics, (6.3.18)).
        let b = |p: [f64; 4], s: [f64; 3]| {
            let (e0, e) = (p[0], [p[1], p[2], p[3]]);
            let tilde = |v: [f64; 3]| [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]];
            let mut a = tilde(e);
            (0..3).for_each(|i| a[i][i] += e0);
            let st = tilde(s);
            let mut out = [[0.0; 4]; 3];
            for i in 0..3 {
                out[i][0] = 2.0 * (0..3).map(|k| a[i][k] * s[k]).sum::<f64>();
                for j in 0..3 {
                    out[i][1 + j] = 2.0 * (e[i] * s[j] - (0..3).map(|k| a[i][k] * st[k][j]).sum::<f64>());
                }
            }
            out
        };
        let (start, end) = ([-0.25, 0.0, 0.0], [0.25, 0.0, 0.0]);
        let (mut row_ptr, mut cols, mut values) = (vec![0], Vec::new(), Vec::new());
        for k in 0..n {
            for i in 0..3 {
                if k > 0 {
                    let bp = b(p(k - 1), end);
                    cols.extend(7 * (k - 1)..7 * k);
                    values.extend((0..3).map(|j| if i == j { 1.0 } else { 0.0 }).chain(bp[i]));
                }
                let bp = b(p(k), start);
                cols.extend(7 * k..7 * k + 7);
                values.extend((0..3).map(|j| if i == j { -1.0 } else { 0.0 }).chain(bp[i].map(|x| -x)));
                row_ptr.push(cols.len());
            }
        }
        for k in 0..n {
            cols.extend(7 * k + 3..7 * k + 7);
            values.extend(p(k).map(|x| 2.0 * x));
            row_ptr.push(cols.len());
        }
        (row_ptr, cols, values)
    }

    /// The elimination's work per rod (the entries of the rows its updates make) stays bounded as the
    /// chain doubles, straight (every rod at the identity: many ties of magnitude and exact zeros, where
    /// full pivoting filled `O(n²)`) and with every rod turned its own way (a row that took the updates
    /// of a whole chain's length cost `O(n²)` when its costs were not renewed).
    #[test]
    fn the_work_on_a_chain_grows_with_its_length() {
        let turned = |k: usize| {
            let (a, b) = (0.3 + 0.7 * k as f64, 1.1 * k as f64);
            [a.cos(), a.sin() * b.cos(), a.sin() * b.sin() * 0.6, a.sin() * b.sin() * 0.8]
        };
        for (name, p) in [("straight", (|_| [1.0, 0.0, 0.0, 0.0]) as fn(usize) -> [f64; 4]), ("turned", turned)] {
            let mut per_rod = Vec::new();
            for n in [64, 128, 256, 512] {
                let (row_ptr, cols, values) = chain_jacobian(n, p);
                let (pivots, work) = eliminate(7 * n, &row_ptr, &cols, &values, PARTITION_THRESHOLD).expect("independent rows");
                assert_eq!(pivots.len(), 4 * n);
                per_rod.push(work as f64 / n as f64);
            }
            eprintln!("{name} chain, entries updated per rod at n = 64 … 512: {per_rod:.1?}");
            assert!(per_rod.iter().all(|&w| w <= 1.1 * per_rod[0] + 1.0), "{name}: {per_rod:?}");
        }
    }
}
