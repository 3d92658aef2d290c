//! The assembly step of [`ModalAssembly::Static`]: the body frames stay where the model puts them and
//! the flexible bodies take the deformation of least strain energy that closes the joints — a
//! structure held by its reference frame and bent statically to fit its joints, as a door held open
//! on misaligned hinges is.
//!
//! With the frames held, the constraints depend on the modal coordinates `a` alone. Each Newton step
//! solves the quadratic program
//!
//! ```text
//! minimize ½ aₙᵀ K aₙ   subject to   G (aₙ − a) = −Φ̂,
//! ```
//!
//! with `K` the block-diagonal modal stiffness and `G = Φ̂_a`: `aₙ = K⁻¹ Gᵀ μ`, `(G K⁻¹ Gᵀ) μ = G a − Φ̂`.
//! At convergence `K a = Gᵀ μ`: the strain forces are balanced by joint reactions, which is the static
//! equilibrium of the structure under its joints' loads. Rows that do not depend on `a` (a joint
//! between frames alone, the Euler-parameter normalization) must already hold; the pseudo-inverse
//! leaves them out, and if they do not hold the assembly reports them as unconverged.
//!
//! [`ModalAssembly::Static`]: super::ModalAssembly::Static

use faer::prelude::*;
use faer::Side;

use crate::model::Model;

/// The change of the modal coordinates in `q` (zero elsewhere) for one step, from the position
/// Jacobian `gq` (rows: active constraints then normalizations; columns: `q`) and the residual `phi`.
/// `None` if a body's modal stiffness is not positive definite.
pub(crate) fn static_deformation_step(model: &Model, q: &[f64], gq: &Mat<f64>, phi: &[f64]) -> Option<Mat<f64>> {
    let l = &model.layout;
    let m = gq.nrows();
    // K⁻¹ Gᵀ, body by body (zero rows for the frames).
    let mut k_inv_gt = Mat::<f64>::zeros(l.nq, m);
    for (b, modal) in model.modal.iter().enumerate() {
        let Some(modal) = modal else { continue };
        let (qa, n) = (l.q_offset[b] + 7, l.modes[b]);
        if n == 0 {
            continue;
        }
        let cholesky = modal.stiffness.clone().cholesky()?;
        for r in 0..m {
            let g = nalgebra::DVector::from_fn(n, |k, _| gq[(r, qa + k)]);
            let x = cholesky.solve(&g);
            for k in 0..n {
                k_inv_gt[(qa + k, r)] = x[k];
            }
        }
    }
    let s = gq * &k_inv_gt;
    let mut rhs = Mat::<f64>::zeros(m, 1);
    for r in 0..m {
        rhs[(r, 0)] = -phi[r] + (0..l.nq).filter(|&c| is_modal(model, c)).map(|c| gq[(r, c)] * q[c]).sum::<f64>();
    }
    let mu = pseudo_inverse_solve(&s, &rhs)?;
    let a_new = &k_inv_gt * &mu;
    Some(Mat::from_fn(l.nq, 1, |c, _| if is_modal(model, c) { a_new[(c, 0)] - q[c] } else { 0.0 }))
}

/// Whether position coordinate `c` is a modal coordinate.
fn is_modal(model: &Model, c: usize) -> bool {
    let l = &model.layout;
    (0..model.bodies.len()).any(|b| c >= l.q_offset[b] + 7 && c < l.q_offset[b] + 7 + l.modes[b])
}

/// `S⁺ r` for a symmetric positive semi-definite `S`, dropping eigenvalues below 1e-12 of the largest.
fn pseudo_inverse_solve(s: &Mat<f64>, r: &Mat<f64>) -> Option<Mat<f64>> {
    let eigen = s.self_adjoint_eigen(Side::Lower).ok()?;
    let (u, values) = (eigen.U(), eigen.S());
    let largest = (0..s.nrows()).map(|k| values[k].abs()).fold(0.0, f64::max);
    let mut x = Mat::<f64>::zeros(s.nrows(), 1);
    if largest == 0.0 {
        return Some(x);
    }
    for k in 0..s.nrows() {
        let lambda = values[k];
        if lambda > 1e-12 * largest {
            let coefficient = (0..s.nrows()).map(|i| u[(i, k)] * r[(i, 0)]).sum::<f64>() / lambda;
            for i in 0..s.nrows() {
                x[(i, 0)] += coefficient * u[(i, k)];
            }
        }
    }
    Some(x)
}
