//! Dense LU with partial pivoting (`faer`) in preallocated storage, for the small iteration matrices
//! of mechanisms, where a blocked dense factorization is faster than a sparse one whose factors fill
//! in: factor and solve do not allocate.
//!
//! The solve is two plain column-oriented substitutions rather than `faer`'s blocked triangular solves:
//! for one right-hand side of the size of a mechanism's iteration matrix their setup dominates (the
//! rigid pendulum's 16 unknowns: 5,200 instructions per solve with `faer`, 28 % of a generalized-α run,
//! against about 1,000 for the loops, which touch each factor entry once, as the blocked solve does).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, Par};

/// An `n × n` matrix and, after [`factor`](Self::factor), its packed LU factors and row permutation.
pub(crate) struct DenseLu {
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    factor_buffer: MemBuffer,
    /// The permuted right-hand side during a solve.
    work: Vec<f64>,
}

impl DenseLu {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            lu: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            factor_buffer: MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())),
            work: vec![0.0; n],
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
        factor::lu_in_place(self.lu.as_mut(), &mut self.perm, &mut self.perm_inv, Par::Seq, stack, Default::default());
        (0..self.lu.nrows()).all(|k| {
            let pivot = self.lu[(k, k)];
            pivot != 0.0 && pivot.is_finite()
        })
    }

    /// Solves `A x = b` in place with the factors `P A = L U` (`faer`'s: row `i` of `P b` is row
    /// `perm[i]` of `b`; `L` unit lower, `U` upper, packed in `lu`).
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let n = self.lu.nrows();
        assert_eq!(rhs.len(), n, "right-hand side of the wrong length");
        let x = &mut self.work;
        for (xi, &p) in x.iter_mut().zip(&self.perm) {
            *xi = rhs[p];
        }
        // L y = P b, column by column.
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                let column = &self.lu.col_as_slice(j)[j + 1..];
                for (xi, l) in x[j + 1..].iter_mut().zip(column) {
                    *xi -= l * xj;
                }
            }
        }
        // U x = y, column by column from the last.
        for j in (0..n).rev() {
            let column = &self.lu.col_as_slice(j)[..=j];
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
}
