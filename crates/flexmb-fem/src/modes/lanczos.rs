//! Sparse path: thick-restart Lanczos (Wu and Simon, "Thick-restart Lanczos method for large
//! symmetric eigenvalue problems", SIAM J. Matrix Anal. Appl. 22, 2000) on the shift-invert operator,
//! whose largest eigenvalues are the lowest frequencies.
//!
//! Each pass extends an orthonormal basis `V` by the operator's images to `m` vectors, orthogonalized
//! twice against all of `V` (classical Gram–Schmidt, twice: the basis stays orthonormal to round-off),
//! which also gives the projected matrix `T = Vᵀ B V` whole; its largest eigenpairs `(θ, y)` are the
//! Ritz pairs, with residuals `‖B V y − θ V y‖ = β |y_m|`. A pass ends by keeping the best Ritz vectors
//! and the last residual direction as the start of the next. Where the new vector vanishes (the basis
//! spans an invariant subspace: an operator of low numerical rank, a film whose bending is 10¹² times
//! softer than its membrane), the basis goes on with a fresh direction. faer's Krylov–Schur, used
//! before, looped forever there, re-orthogonalizing a vector of round-off (found by the fuzz test).

use faer::{Col, Mat};
use nalgebra::{DMatrix, SymmetricEigen};

use super::shift_invert::ShiftInvert;
use crate::error::FemError;

/// Passes before the iteration gives up (the 49,000-dof plate of the benchmark converges in one).
const MAX_RESTARTS: usize = 100;
/// Below this fraction of the image's norm, a new basis vector has vanished: the basis is invariant.
const BREAKDOWN: f64 = 1e-10;

/// How many eigenvectors the iteration computes for `count` wanted ones of an operator of dimension
/// `n`: a few more than asked, so that the last wanted one converges as well as the first and a
/// repeated frequency at the end of the range is not cut in half.
fn computed(count: usize, n: usize) -> usize {
    (count + (count / 2).max(4)).min(n)
}

/// The basis kept at a restart and its size at the end of a pass: twice and four times the vectors
/// computed, and at least 32 and 64.
fn krylov_dimensions(count: usize, n: usize) -> (usize, usize) {
    let wanted = computed(count, n);
    ((2 * wanted).max(32), (4 * wanted).max(64))
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
    // A start vector in the operator's range, with no structure (the image of a golden-ratio sequence).
    let mut v = image(operator, &fresh_direction(n, 0));
    // A non-finite operator never converges: the iteration ran forever on NaN (a plate at z = −1e300).
    if !v.iter().all(|x| x.is_finite()) {
        return Err(FemError::NotFinite);
    }
    if normalize(&mut v) == 0.0 {
        v = fresh_direction(n, 0);
        normalize(&mut v);
    }
    let mut basis: Vec<Vec<f64>> = vec![v];
    let mut t = DMatrix::<f64>::zeros(m, m);
    let mut fresh = 1;
    for _ in 0..MAX_RESTARTS {
        let residual = extend(operator, &mut basis, &mut t, m, &mut fresh);
        let eigen = SymmetricEigen::new(t.clone());
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        let scale = eigen.eigenvalues[order[0]].abs();
        let beta = norm(&residual);
        let converged = order[..wanted].iter().all(|&k| beta * eigen.eigenvectors[(m - 1, k)].abs() <= tolerance * scale.max(1.0));
        if converged {
            let z: Vec<Vec<f64>> = order[..count].iter().map(|&k| ritz(&basis, &eigen.eigenvectors, k)).collect();
            return Ok(Mat::from_fn(n, count, |i, j| z[j][i]));
        }
        // Thick restart: the best Ritz vectors, then the residual direction.
        let ritz_vectors: Vec<Vec<f64>> = order[..kept].iter().map(|&k| ritz(&basis, &eigen.eigenvectors, k)).collect();
        t.fill(0.0);
        for (r, &k) in order[..kept].iter().enumerate() {
            t[(r, r)] = eigen.eigenvalues[k];
        }
        basis = ritz_vectors;
        let mut next = residual;
        let left = orthogonalize(&basis, &mut next).1;
        if !left || normalize(&mut next) == 0.0 {
            next = new_direction(&basis, n, &mut fresh);
        }
        basis.push(next);
    }
    Err(FemError::EigenNotConverged { asked: count, converged: 0 })
}

/// Extends the basis to `m + 1` vectors' worth: returns the residual `w` after the last vector (the
/// unnormalized next direction), and fills `T = Vᵀ B V` for the vectors it adds.
fn extend(operator: &ShiftInvert, basis: &mut Vec<Vec<f64>>, t: &mut DMatrix<f64>, m: usize, fresh: &mut usize) -> Vec<f64> {
    let n = basis[0].len();
    loop {
        let j = basis.len() - 1;
        let mut w = image(operator, &basis[j]);
        let image_norm = norm(&w);
        let (projections, kept) = orthogonalize(&basis[..], &mut w);
        for (i, h) in projections.iter().enumerate() {
            t[(i, j)] = *h;
            t[(j, i)] = *h;
        }
        if j + 1 == m {
            return w;
        }
        // A vanished vector means an invariant subspace: go on with a fresh direction, uncoupled.
        let next = if kept && norm(&w) > BREAKDOWN * image_norm {
            normalize(&mut w);
            w
        } else {
            new_direction(basis, n, fresh)
        };
        basis.push(next);
    }
}

/// `B x`.
fn image(operator: &ShiftInvert, x: &[f64]) -> Vec<f64> {
    let y = operator.apply_to(Col::from_fn(x.len(), |i| x[i]).as_mat());
    (0..x.len()).map(|i| y[(i, 0)]).collect()
}

/// Removes from `w` its components along the basis, twice; returns the projections (summed over the
/// two passes) and whether anything is left of `w`.
fn orthogonalize(basis: &[Vec<f64>], w: &mut [f64]) -> (Vec<f64>, bool) {
    let before = norm(w);
    let mut projections = vec![0.0; basis.len()];
    for _ in 0..2 {
        for (v, p) in basis.iter().zip(projections.iter_mut()) {
            let h = dot(v, w);
            *p += h;
            w.iter_mut().zip(v).for_each(|(x, vi)| *x -= h * vi);
        }
    }
    (projections, norm(w) > f64::EPSILON * before)
}

/// A unit vector orthogonal to the basis, from a golden-ratio sequence shifted by `fresh`.
fn new_direction(basis: &[Vec<f64>], n: usize, fresh: &mut usize) -> Vec<f64> {
    loop {
        let mut v = fresh_direction(n, *fresh);
        *fresh += 1;
        if orthogonalize(basis, &mut v).1 && normalize(&mut v) > 0.0 {
            return v;
        }
        assert!(*fresh < 1000, "no direction orthogonal to {} basis vectors in dimension {n}", basis.len());
    }
}

/// Every component nonzero and no structure: `frac((i + 1) φ + k √2)` around zero.
fn fresh_direction(n: usize, k: usize) -> Vec<f64> {
    (0..n).map(|i| ((i as f64 + 1.0) * 0.618_033_988_749_895 + k as f64 * std::f64::consts::SQRT_2).fract() - 0.5).collect()
}

/// The Ritz vector `V y_k` of eigenvector `k` of `T`.
fn ritz(basis: &[Vec<f64>], y: &DMatrix<f64>, k: usize) -> Vec<f64> {
    let mut z = vec![0.0; basis[0].len()];
    for (r, v) in basis.iter().enumerate() {
        let c = y[(r, k)];
        z.iter_mut().zip(v).for_each(|(zi, vi)| *zi += c * vi);
    }
    z
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Scales `a` to unit length and returns its former length (0: left as it was).
fn normalize(a: &mut [f64]) -> f64 {
    let length = norm(a);
    if length > 0.0 {
        a.iter_mut().for_each(|x| *x /= length);
    }
    length
}
