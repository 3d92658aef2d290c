//! Dense LU with partial pivoting (`faer`) in preallocated storage, for the small iteration matrices
//! of mechanisms, where a blocked dense factorization is faster than a sparse one whose factors fill
//! in: factor and solve do not allocate.
//!
//! The solve is two plain column-oriented substitutions rather than `faer`'s blocked triangular solves:
//! for one right-hand side of the size of a mechanism's iteration matrix their setup dominates (the
//! rigid pendulum's 16 unknowns: 5,200 instructions per solve with `faer`, 28 % of a generalized-α run,
//! against about 1,000 for the loops, which touch each factor entry once, as the blocked solve does).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, MatMut, MatRef, Par};

use super::lu_refactorization::pivot_ratio;

/// The workspace of [`lu_in_place`] for an `n × n` matrix.
pub(crate) fn lu_in_place_scratch(n: usize) -> StackReq {
    factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())
}

/// Up to this dimension [`lu_in_place`] eliminates column by column in plain loops; above it `faer`'s
/// blocked recursive LU. Below a few dozen unknowns the blocked factorization's setup and its rank-one
/// updates by general matrix products dominate: the rigid pendulum's 16 unknowns cost 14,500
/// instructions per factorization with `faer` (17 % of a 5 s BDF run of the peer case with its output,
/// an acceleration solve per output time: 625 factorizations), against 2,500 for the loops.
const ELIMINATION_LIMIT: usize = 32;

/// `P A = L U` in place (LU with partial pivoting: `L` unit lower and `U` upper packed in `a`, row `i`
/// of `P A` row `perm[i]` of `A`); the smallest over the largest magnitude of `U`'s pivots, 0 if one is
/// zero or not finite.
pub(crate) fn lu_in_place(mut a: MatMut<'_, f64>, perm: &mut [usize], perm_inv: &mut [usize], stack: &mut MemStack) -> f64 {
    if a.nrows() <= ELIMINATION_LIMIT {
        eliminate(a.as_mut(), perm, perm_inv);
    } else {
        factor::lu_in_place(a.as_mut(), perm, perm_inv, Par::Seq, stack, Default::default());
    }
    pivot_ratio((0..a.nrows()).map(|k| a[(k, k)]))
}

/// Gaussian elimination with partial pivoting, right-looking, on a small square matrix: at column `k`
/// the largest magnitude at or below the diagonal (the first of equals) is brought to the diagonal by
/// exchanging whole rows, the column below it is scaled by the pivot's reciprocal and its outer product
/// with the pivot row is subtracted from the columns to the right (the elimination of `faer`'s unblocked
/// kernel, in loops over contiguous columns).
fn eliminate(mut a: MatMut<'_, f64>, perm: &mut [usize], perm_inv: &mut [usize]) {
    let n = a.nrows();
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    for k in 0..n {
        let (mut pivot_row, mut largest) = (k, 0.0);
        for (i, x) in column_mut(&mut a, k).iter().enumerate().skip(k) {
            if x.abs() > largest {
                (pivot_row, largest) = (i, x.abs());
            }
        }
        if pivot_row != k {
            perm.swap(k, pivot_row);
            for j in 0..n {
                column_mut(&mut a, j).swap(k, pivot_row);
            }
        }
        if largest == 0.0 {
            continue;
        }
        let (mut left, mut right) = a.as_mut().split_at_col_mut(k + 1);
        let multipliers = &mut column_mut(&mut left, k)[k..];
        let inverse = multipliers[0].recip();
        for l in &mut multipliers[1..] {
            *l *= inverse;
        }
        let multipliers = &multipliers[1..];
        for j in 0..right.ncols() {
            let target = &mut column_mut(&mut right, j)[k..];
            let u = target[0];
            if u != 0.0 {
                for (x, l) in target[1..].iter_mut().zip(multipliers) {
                    *x -= l * u;
                }
            }
        }
    }
    for (i, &p) in perm.iter().enumerate() {
        perm_inv[p] = i;
    }
}

/// Column `j` of a column-major matrix as a slice.
fn column_mut<'a>(a: &'a mut MatMut<'_, f64>, j: usize) -> &'a mut [f64] {
    a.as_mut().col_mut(j).try_as_col_major_mut().expect("contiguous columns").as_slice_mut()
}

/// Solves `A x = b` in place (`rhs` holds `b` on entry) with the factors of [`lu_in_place`]; `work` is
/// of `A`'s dimension.
pub(crate) fn solve_with_lu(lu: MatRef<'_, f64>, perm: &[usize], rhs: &mut [f64], work: &mut [f64]) {
    let n = lu.nrows();
    assert_eq!(rhs.len(), n, "right-hand side of the wrong length");
    let x = work;
    for (xi, &p) in x.iter_mut().zip(perm) {
        *xi = rhs[p];
    }
    // L y = P b, column by column.
    for j in 0..n {
        let xj = x[j];
        if xj != 0.0 {
            let column = &lu.col(j).try_as_col_major().expect("contiguous columns").as_slice()[j + 1..];
            for (xi, l) in x[j + 1..].iter_mut().zip(column) {
                *xi -= l * xj;
            }
        }
    }
    // U x = y, column by column from the last.
    for j in (0..n).rev() {
        let column = &lu.col(j).try_as_col_major().expect("contiguous columns").as_slice()[..=j];
        let xj = x[j] / column[j];
        x[j] = xj;
        if xj != 0.0 {
            for (xi, u) in x[..j].iter_mut().zip(column) {
                *xi -= u * xj;
            }
        }
    }
    rhs.copy_from_slice(x);
}

/// An `n × n` matrix and, after [`factor`](Self::factor), its packed LU factors and row permutation.
pub(crate) struct DenseLu {
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    factor_buffer: MemBuffer,
    /// The permuted right-hand side during a solve.
    work: Vec<f64>,
    /// The pivot ratio of the last factorization ([`lu_in_place`]'s).
    pivot_ratio: f64,
}

impl DenseLu {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            lu: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            factor_buffer: MemBuffer::new(lu_in_place_scratch(n)),
            work: vec![0.0; n],
            pivot_ratio: 0.0,
        }
    }

    /// Factors the matrix whose columns are `(values, rows)` pairs; `false` if a pivot is zero or not
    /// finite.
    pub(crate) fn factor<'a>(&mut self, columns: impl Iterator<Item = (&'a [f64], &'a [usize])>) -> bool {
        self.lu.fill(0.0);
        for (c, (values, rows)) in columns.enumerate() {
            for (v, r) in values.iter().zip(rows) {
                self.lu[(*r, c)] = *v;
            }
        }
        let stack = MemStack::new(&mut self.factor_buffer);
        self.pivot_ratio = lu_in_place(self.lu.as_mut(), &mut self.perm, &mut self.perm_inv, stack);
        self.pivot_ratio > 0.0
    }

    /// The smallest over the largest magnitude of the last factorization's pivots.
    pub(crate) fn pivot_ratio(&self) -> f64 {
        self.pivot_ratio
    }

    /// Solves `A x = b` in place with the factors.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        solve_with_lu(self.lu.as_ref(), &self.perm, rhs, &mut self.work);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix whose zero diagonal forces row exchanges at every column: the substitutions with the
    /// pivoted factors solve it to round-off.
    #[test]
    fn a_matrix_that_needs_pivoting_is_solved_to_round_off() {
        let n = 23;
        let a = |r: usize, c: usize| if r == c { 0.0 } else { ((r * 7 + c * 3) as f64 * 0.61).sin() + if r == (c + 1) % n { 4.0 } else { 0.0 } };
        let columns: Vec<(Vec<f64>, Vec<usize>)> = (0..n).map(|c| ((0..n).map(|r| a(r, c)).collect(), (0..n).collect())).collect();
        let mut lu = DenseLu::new(n);
        assert!(lu.factor(columns.iter().map(|(v, r)| (v.as_slice(), r.as_slice()))));
        assert!(lu.perm.iter().enumerate().any(|(i, &p)| i != p), "no row was exchanged");
        let b: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).cos()).collect();
        let mut x = b.clone();
        lu.solve_in_place(&mut x);
        let residual = (0..n).map(|r| ((0..n).map(|c| a(r, c) * x[c]).sum::<f64>() - b[r]).abs()).fold(0.0, f64::max);
        assert!(residual < 1e-13, "residual {residual:e}");
    }

    /// The plain elimination of small matrices chooses the same pivots as `faer`'s blocked LU where no
    /// two candidates are near equal, and gives the same factors to round-off (a matrix of a size at
    /// which the blocked LU recurses).
    #[test]
    fn the_elimination_of_small_matrices_agrees_with_the_blocked_lu() {
        let n = 24;
        assert!(n <= ELIMINATION_LIMIT);
        let a = Mat::from_fn(n, n, |r, c| ((r * 13 + c * 5) as f64 * 0.37).sin() + if r == (c * 5 + 1) % n { 6.0 } else { 0.0 });
        let (mut eliminated, mut blocked) = (a.clone(), a.clone());
        let (mut perm, mut perm_inv) = (vec![0; n], vec![0; n]);
        eliminate(eliminated.as_mut(), &mut perm, &mut perm_inv);
        let (mut blocked_perm, mut blocked_perm_inv) = (vec![0; n], vec![0; n]);
        let mut buffer = MemBuffer::new(lu_in_place_scratch(n));
        factor::lu_in_place(blocked.as_mut(), &mut blocked_perm, &mut blocked_perm_inv, Par::Seq, MemStack::new(&mut buffer), Default::default());
        assert_eq!((&perm, &perm_inv), (&blocked_perm, &blocked_perm_inv));
        assert!(perm.iter().enumerate().any(|(i, &p)| i != p), "no row was exchanged");
        let largest = (0..n).flat_map(|c| (0..n).map(move |r| (r, c))).map(|(r, c)| (eliminated[(r, c)] - blocked[(r, c)]).abs()).fold(0.0, f64::max);
        assert!(largest < 1e-12, "factors differ by {largest:e}");
    }
}
