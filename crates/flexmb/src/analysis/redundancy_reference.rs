//! The dense redundancy check the sparse one replaced, kept as the reference it is tested against:
//! modified Gram–Schmidt, twice, on the rows of `B` in keep order. Its work grows with `nc² nv` and its
//! memory with `nc nv`, so it is for tests on models of modest size only.

use faer::linalg::matmul::matmul;
use faer::prelude::*;
use faer::{Accum, Par};

use super::redundancy::{jacobian_in_keep_order, REDUNDANCY_TOLERANCE};
use crate::data::Data;
use crate::model::Model;

/// The rows of `B` at `(q, t)` that depend on rows kept before them (keep order as in
/// `assemble`), found by dense Gram–Schmidt; in row order.
#[doc(hidden)]
pub fn gram_schmidt_redundant_rows(model: &Model, data: &mut Data, t: f64, q: &[f64], satisfied_tolerance: f64) -> Vec<usize> {
    let b = jacobian_in_keep_order(model, data, t, q, satisfied_tolerance);
    let (nc, nv) = (b.rows.nrows(), b.rows.ncols());
    // Bᵀ with its columns in keep order.
    let mut columns = Mat::<f64>::zeros(nv, nc);
    for k in 0..nc {
        let (cols, values) = b.rows.row(k);
        cols.iter().zip(values).for_each(|(c, x)| columns[(*c, k)] = *x);
    }
    let dependent = dependent_columns(&mut columns);
    let mut rows: Vec<usize> = (0..nc).filter(|&k| dependent[k]).map(|k| b.order[k]).collect();
    rows.sort_unstable();
    rows
}

/// Columns of `a` that depend on the columns before them: Gram–Schmidt with reorthogonalization,
/// blocked so that the projections on the basis found so far are matrix products (classical
/// Gram–Schmidt, twice, against the earlier blocks; modified Gram–Schmidt, twice, within a block). A
/// column whose remainder is at most [`REDUNDANCY_TOLERANCE`] of its length is dependent. `a` is
/// overwritten.
fn dependent_columns(a: &mut Mat<f64>) -> Vec<bool> {
    const BLOCK: usize = 128;
    let (n, m) = (a.nrows(), a.ncols());
    let lengths: Vec<f64> = (0..m).map(|j| a.col(j).norm_l2()).collect();
    let mut basis = Mat::<f64>::zeros(n, m.min(n));
    let mut rank = 0;
    let mut dependent = vec![false; m];
    for start in (0..m).step_by(BLOCK) {
        let width = BLOCK.min(m - start);
        for _ in 0..2 {
            if rank > 0 {
                let q = basis.as_ref().subcols(0, rank);
                let c = q.transpose() * a.as_ref().subcols(start, width);
                matmul(a.as_mut().subcols_mut(start, width), Accum::Add, q, &c, -1.0, Par::Seq);
            }
        }
        let block_rank = rank;
        for j in start..start + width {
            for _ in 0..2 {
                for e in block_rank..rank {
                    let projection = basis.col(e).transpose() * a.col(j);
                    let (q, x) = (basis.col(e), a.col_mut(j));
                    x.iter_mut().zip(q.iter()).for_each(|(x, q)| *x -= projection * q);
                }
            }
            let remainder = a.col(j).norm_l2();
            if lengths[j] == 0.0 || remainder <= REDUNDANCY_TOLERANCE * lengths[j] || rank == n {
                dependent[j] = true;
            } else {
                let (x, q) = (a.col(j), basis.col_mut(rank));
                q.iter_mut().zip(x.iter()).for_each(|(q, x)| *q = x / remainder);
                rank += 1;
            }
        }
    }
    dependent
}
