//! Dense LU with partial pivoting (`faer`) in preallocated storage, for the small iteration matrices
//! of mechanisms, where a blocked dense factorization is faster than a sparse one whose factors fill
//! in: factor and solve do not allocate.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Conj, Mat, MatMut, Par};

/// An `n × n` matrix and, after [`factor`](Self::factor), its packed LU factors and row permutation.
pub(crate) struct DenseLu {
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    factor_buffer: MemBuffer,
    solve_buffer: MemBuffer,
}

impl DenseLu {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            lu: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            factor_buffer: MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())),
            solve_buffer: MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq)),
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

    /// Solves `A x = b` in place with the factors.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let n = self.lu.nrows();
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let stack = MemStack::new(&mut self.solve_buffer);
        let rhs = MatMut::from_column_major_slice_mut(rhs, n, 1);
        solve::solve_in_place_with_conj(self.lu.as_ref(), self.lu.as_ref(), perm, Conj::No, rhs, Par::Seq, stack);
    }
}
