//! The shift-invert operator of the generalized problem `K φ = λ M φ`, in a symmetric form that
//! allows a singular (lumped, rotations without inertia) mass matrix:
//!
//! `B = P S (K + σ M)⁻¹ S P`, with `S = M^{1/2}` (block-diagonal, per node) and `P` the projector
//! that removes the rigid motions `S R`.
//!
//! If `B z = μ z` with `μ > 0`, then `φ = (K + σM)⁻¹ S z` satisfies `(K + σM)⁻¹ M φ = μ φ`, i.e.
//! `K φ = λ M φ` with `λ = 1/μ − σ`. The largest `μ` are the lowest frequencies; massless
//! degrees of freedom give `μ = 0` (infinite frequency) and the rigid motions, projected out, too.
//! Distinct eigenvectors `z` give M-orthogonal `φ`, repeated frequencies included.

use faer::linalg::solvers::Solve;
use faer::matrix_free::LinOp;
use faer::prelude::*;
use faer::sparse::linalg::LltError;
use faer::sparse::{SparseColMat, Triplet};
use faer::{dyn_stack::MemStack, dyn_stack::StackReq, MatMut, MatRef, Par, Side};
use nalgebra::{Matrix3, SymmetricEigen};

use crate::assembly::{AssembledModel, DofMap};
use crate::element::NodalMass;
use crate::mesh::Dof;

/// The factored shifted stiffness, the mass square root and the rigid-motion projector.
#[derive(Debug)]
pub struct ShiftInvert {
    pub shift: f64,
    factor: faer::sparse::linalg::solvers::Llt<usize, f64>,
    sqrt_mass: SparseColMat<usize, f64>,
    /// Orthonormal basis of `S R` (the rigid motions in the mass-weighted space).
    deflation: Mat<f64>,
}

impl ShiftInvert {
    /// Factors `K + shift M`; `rigid` holds the rigid motions over the free dofs (any basis).
    pub fn new(assembled: &AssembledModel, rigid: &Mat<f64>, shift: f64) -> Result<Self, LltError> {
        let shifted = if shift == 0.0 {
            assembled.stiffness.clone()
        } else {
            let scaled = scale_sparse(&assembled.mass, shift);
            &assembled.stiffness + &scaled
        };
        let factor = shifted.sp_cholesky(Side::Lower)?;
        let sqrt_mass = mass_square_root(&assembled.dofs, &assembled.nodal_masses);
        let mut deflation = &sqrt_mass * rigid;
        super::rigid::orthonormalize_columns(&mut deflation);
        Ok(ShiftInvert { shift, factor, sqrt_mass, deflation })
    }

    /// Dimension of the operator (the free dofs).
    pub fn dim(&self) -> usize {
        self.sqrt_mass.nrows()
    }

    /// Removes the rigid components from the columns of `x`: `x ← (I − Z Zᵀ) x`.
    fn deflate(&self, mut x: MatMut<'_, f64>) {
        if self.deflation.ncols() == 0 {
            return;
        }
        let coefficients = self.deflation.transpose() * x.rb();
        x -= &self.deflation * &coefficients;
    }

    /// `B x` for the columns of `x`.
    pub fn apply_to(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let mut projected = x.to_owned();
        self.deflate(projected.as_mut());
        let mut y = &self.sqrt_mass * &projected;
        self.factor.solve_in_place(y.as_mut());
        let mut z = &self.sqrt_mass * &y;
        self.deflate(z.as_mut());
        z
    }

    /// The mode shapes `φ = (K + σM)⁻¹ S z` of eigenvectors `z` of `B`.
    pub fn mode_shapes(&self, z: MatRef<'_, f64>) -> Mat<f64> {
        let mut phi = &self.sqrt_mass * z;
        self.factor.solve_in_place(phi.as_mut());
        phi
    }

    /// Solves `(K + σM) x = b` in place.
    pub fn solve_in_place(&self, b: MatMut<'_, f64>) {
        self.factor.solve_in_place(b);
    }
}

impl LinOp<f64> for ShiftInvert {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.dim()
    }

    fn ncols(&self) -> usize {
        self.dim()
    }

    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, _stack: &mut MemStack) {
        out.copy_from(self.apply_to(rhs));
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, stack: &mut MemStack) {
        self.apply(out, rhs, par, stack);
    }
}

fn scale_sparse(m: &SparseColMat<usize, f64>, factor: f64) -> SparseColMat<usize, f64> {
    let mut scaled = m.clone();
    for v in scaled.val_mut() {
        *v *= factor;
    }
    scaled
}

/// `M^{1/2}` over the free dofs: `√m` on each free translation, the symmetric square root of the
/// free part of each node's rotary inertia on its rotations.
fn mass_square_root(dofs: &DofMap, nodal: &[NodalMass]) -> SparseColMat<usize, f64> {
    let mut triplets = Vec::new();
    for (node, m) in nodal.iter().enumerate() {
        for dof in [Dof::Ux, Dof::Uy, Dof::Uz] {
            if let Some(e) = dofs.equation(node, dof) {
                triplets.push(Triplet::new(e, e, m.mass.max(0.0).sqrt()));
            }
        }
        let free: Vec<(usize, usize)> = [Dof::Rx, Dof::Ry, Dof::Rz]
            .into_iter()
            .enumerate()
            .filter_map(|(k, d)| dofs.equation(node, d).map(|e| (k, e)))
            .collect();
        if free.is_empty() || m.rotary_inertia == Matrix3::zeros() {
            continue;
        }
        let mut block = Matrix3::zeros();
        for &(a, _) in &free {
            for &(b, _) in &free {
                block[(a, b)] = m.rotary_inertia[(a, b)];
            }
        }
        let eigen = SymmetricEigen::new(block);
        let roots = eigen.eigenvalues.map(|v| v.max(0.0).sqrt());
        let root = eigen.eigenvectors * Matrix3::from_diagonal(&roots) * eigen.eigenvectors.transpose();
        for &(a, ea) in &free {
            for &(b, eb) in &free {
                triplets.push(Triplet::new(ea, eb, root[(a, b)]));
            }
        }
    }
    let n = dofs.n_free();
    SparseColMat::try_new_from_triplets(n, n, &triplets).expect("indices are within the free dofs")
}
