//! Sparse path: block thick-restart Lanczos (Wu and Simon, "Thick-restart Lanczos method for large
//! symmetric eigenvalue problems", SIAM J. Matrix Anal. Appl. 22, 2000, in its block form) on the
//! shift-invert operator, whose largest eigenvalues are the lowest frequencies.
//!
//! Each pass extends an orthonormal basis `V` block by block, [`BLOCK`] vectors at a time, by the
//! operator's images of the last block, orthogonalized twice against all of `V` (block classical
//! Gram–Schmidt, twice: the basis stays orthonormal to round-off), which also gives the projected
//! matrix `T = Vᵀ B V` whole; its largest eigenpairs `(θ, y)` are the Ritz pairs, with residuals
//! `‖B V y − θ V y‖ = ‖R y_b‖`, `R` the last block's orthogonalized images and `y_b` the last block's
//! rows of `y`. A pass ends by keeping the best Ritz vectors and the residual block `R` as the start
//! of the next. Working on blocks turns each application of the operator into one solve with many
//! right-hand sides (the factor is read once for all of them, with matrix–matrix kernels) and the
//! orthogonalization into matrix products; one vector at a time, the solves were bound by memory
//! bandwidth. Where a new vector vanishes (the basis spans an invariant subspace: an operator of
//! low numerical rank, a film whose bending is 10¹² times softer than its membrane), the basis goes
//! on with a fresh direction. faer's Krylov–Schur, used before, looped forever there,
//! re-orthogonalizing a vector of round-off (found by the fuzz test).

use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use nalgebra::{DMatrix, SymmetricEigen};

use super::shift_invert::ShiftInvert;
use crate::error::FemError;

/// Passes before the iteration gives up (the 220,515-dof solid of the benchmark converges in two).
const MAX_RESTARTS: usize = 100;
/// Below this fraction of the image's norm, a new basis vector has vanished: the basis is invariant.
const BREAKDOWN: f64 = 1e-10;
/// The vectors of a block: the right-hand sides of one solve.
const BLOCK: usize = 12;

/// How many eigenvectors the iteration computes for `count` wanted ones of an operator of dimension
/// `n`: a few more than asked, so that the last wanted one converges as well as the first and a
/// repeated frequency at the end of the range is not cut in half.
fn computed(count: usize, n: usize) -> usize {
    (count + (count / 2).max(4)).min(n)
}

/// The basis kept at a restart and its size at the end of a pass: twice and four times the vectors
/// computed, and at least 32 and 64, each rounded up to whole blocks.
fn krylov_dimensions(count: usize, n: usize) -> (usize, usize) {
    let wanted = computed(count, n);
    let whole_blocks = |k: usize| k.div_ceil(BLOCK) * BLOCK;
    (whole_blocks((2 * wanted).max(32)), whole_blocks((4 * wanted).max(64)))
}

/// Whether the iteration applies to `count` eigenvectors of an operator of rank `n`: its basis must
/// be smaller than the operator's range, else the dense solver is the one for it.
pub fn applies(count: usize, n: usize) -> bool {
    krylov_dimensions(count, n).1 < n
}

/// Eigenvectors `z` of the `count` largest eigenvalues of the operator, largest first, each Ritz
/// residual within `tolerance` times the largest eigenvalue, or within `tolerance` where that is below 1
/// (it is `1/ω²`, in s²): a relative test would never be met where round-off in the operator of an
/// ill-conditioned mesh (a beam of 20,000 elements) exceeds it, and the modes' own residual check
/// follows. The operator must be larger than the basis ([`applies`]).
pub fn largest_eigenvectors(operator: &ShiftInvert, count: usize, tolerance: f64) -> Result<Mat<f64>, FemError> {
    let n = operator.dim();
    assert!(applies(count, n), "{count} eigenvectors of an operator of dimension {n}: solve it densely");
    let wanted = computed(count, n);
    let (kept, m) = krylov_dimensions(count, n);
    let mut basis = Mat::<f64>::zeros(n, m);
    let mut fresh = 0;
    // The start block: the images of directions with no structure, in the operator's range.
    let start = Mat::from_fn(n, BLOCK, fresh_component);
    fresh += BLOCK;
    let mut first = operator.apply_to(start.as_ref());
    // A non-finite operator never converges: the iteration ran forever on NaN (a plate at z = −1e300).
    if !(0..BLOCK).all(|j| first.col(j).iter().all(|x| x.is_finite())) {
        return Err(FemError::NotFinite);
    }
    let norms = column_norms(first.as_ref());
    orthonormalize_columns(basis.as_ref().subcols(0, 0), first.as_mut(), &norms, &mut fresh);
    basis.as_mut().subcols_mut(0, BLOCK).copy_from(&first);
    let mut t = DMatrix::<f64>::zeros(m, m);
    let mut block_start = 0;
    for _ in 0..MAX_RESTARTS {
        let (mut residual, last, image_norms) = extend(operator, &mut basis, &mut t, block_start, m, &mut fresh);
        let eigen = SymmetricEigen::new(t.clone());
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        let scale = eigen.eigenvalues[order[0]].abs();
        // ‖R y_b‖² = y_bᵀ (RᵀR) y_b.
        let gram = residual.transpose() * &residual;
        let residual_norm = |k: usize| {
            let y = Mat::from_fn(m - last, 1, |i, _| eigen.eigenvectors[(last + i, k)]);
            let r = &gram * &y;
            (0..m - last).map(|i| y[(i, 0)] * r[(i, 0)]).sum::<f64>().max(0.0).sqrt()
        };
        let converged = order[..wanted].iter().all(|&k| residual_norm(k) <= tolerance * scale.max(1.0));
        let ritz = |columns: &[usize]| {
            let y = Mat::from_fn(m, columns.len(), |i, c| eigen.eigenvectors[(i, columns[c])]);
            basis.as_ref() * &y
        };
        if converged {
            return Ok(ritz(&order[..count]));
        }
        // Thick restart: the best Ritz vectors, then the residual block.
        let ritz_vectors = ritz(&order[..kept]);
        basis.as_mut().subcols_mut(0, kept).copy_from(&ritz_vectors);
        t.fill(0.0);
        for (r, &k) in order[..kept].iter().enumerate() {
            t[(r, r)] = eigen.eigenvalues[k];
        }
        let width = residual.ncols();
        project_out(basis.as_ref().subcols(0, kept), residual.as_mut());
        orthonormalize_columns(basis.as_ref().subcols(0, kept), residual.as_mut(), &image_norms, &mut fresh);
        basis.as_mut().subcols_mut(kept, width).copy_from(&residual);
        block_start = kept;
    }
    Err(FemError::EigenNotConverged { asked: count, converged: 0 })
}

/// Extends the basis, whose last block starts at column `start`, to `m` vectors: fills `T = Vᵀ B V`
/// for the blocks whose images it takes, and returns the last block's images orthogonalized against
/// the basis (the residual block, unnormalized), the column where that block starts, and the images'
/// norms.
fn extend(
    operator: &ShiftInvert,
    basis: &mut Mat<f64>,
    t: &mut DMatrix<f64>,
    mut start: usize,
    m: usize,
    fresh: &mut usize,
) -> (Mat<f64>, usize, Vec<f64>) {
    loop {
        let end = start + BLOCK;
        let mut w = operator.apply_to(basis.as_ref().subcols(start, BLOCK));
        let image_norms = column_norms(w.as_ref());
        let projections = project_out(basis.as_ref().subcols(0, end), w.as_mut());
        for c in 0..BLOCK {
            for i in 0..end {
                t[(i, start + c)] = projections[(i, c)];
                t[(start + c, i)] = projections[(i, c)];
            }
        }
        if end == m {
            return (w, start, image_norms);
        }
        // A vanished vector means an invariant subspace: go on with a fresh direction, uncoupled.
        orthonormalize_columns(basis.as_ref().subcols(0, end), w.as_mut(), &image_norms, fresh);
        basis.as_mut().subcols_mut(end, BLOCK).copy_from(&w);
        start = end;
    }
}

/// Removes from the columns of `w` their components along the orthonormal columns of `basis`, twice;
/// returns the projections `basisᵀ w` summed over the two passes.
fn project_out(basis: MatRef<'_, f64>, mut w: MatMut<'_, f64>) -> Mat<f64> {
    let mut projections = Mat::zeros(basis.ncols(), w.ncols());
    for _ in 0..2 {
        let p = basis.transpose() * w.rb();
        matmul(w.rb_mut(), Accum::Add, basis, &p, -1.0, Par::Seq);
        projections += &p;
    }
    projections
}

/// Makes the columns of `w`, already orthogonal to `basis`, orthonormal among themselves (modified
/// Gram–Schmidt, twice); a column left below [`BREAKDOWN`] times its `reference` norm is replaced by
/// a fresh direction orthogonal to the basis and the columns before it.
fn orthonormalize_columns(basis: MatRef<'_, f64>, mut w: MatMut<'_, f64>, reference: &[f64], fresh: &mut usize) {
    let n = w.nrows();
    for c in 0..w.ncols() {
        let (before, mut column) = w.rb_mut().split_at_col_mut(c);
        let mut column = column.rb_mut().col_mut(0);
        for _ in 0..2 {
            for k in 0..c {
                let h = before.rb().col(k).transpose() * column.rb();
                column -= h * before.rb().col(k);
            }
        }
        let length = column.norm_l2();
        if length > BREAKDOWN * reference[c] && length > 0.0 {
            column /= length;
            continue;
        }
        loop {
            assert!(*fresh < 1000, "no direction orthogonal to {} basis vectors in dimension {n}", basis.ncols() + c);
            let mut v = Mat::from_fn(n, 1, |i, _| fresh_component(i, *fresh));
            *fresh += 1;
            project_out(basis, v.as_mut());
            for _ in 0..2 {
                for k in 0..c {
                    let h = before.rb().col(k).transpose() * v.col(0);
                    let mut v = v.col_mut(0);
                    v -= h * before.rb().col(k);
                }
            }
            let length = v.col(0).norm_l2();
            if length > f64::EPSILON {
                column.copy_from(v.col(0) / length);
                break;
            }
        }
    }
}

/// The Euclidean norms of the columns of `a`.
fn column_norms(a: MatRef<'_, f64>) -> Vec<f64> {
    (0..a.ncols()).map(|j| a.col(j).norm_l2()).collect()
}

/// Component `i` of fresh direction `k`, every component nonzero and no structure:
/// `frac((i + 1) φ + k √2)` around zero.
fn fresh_component(i: usize, k: usize) -> f64 {
    ((i as f64 + 1.0) * 0.618_033_988_749_895 + k as f64 * std::f64::consts::SQRT_2).fract() - 0.5
}
