//! The shift-invert operator of the generalized problem `K φ = λ M φ`, in a symmetric form that
//! allows a singular (lumped, rotations without inertia) mass matrix:
//!
//! `B = P F (K + σ M)⁻¹ Fᵀ P`, with `F` the mass points' square-root factor of the mass
//! (`Fᵀ F = M`, one row per massive motion of a mass point; see
//! [`AssembledModel::mass_root`](crate::assembly::AssembledModel::mass_root)) and `P` the projector
//! that removes the rigid motions `F R`.
//!
//! If `B z = μ z` with `μ > 0`, then `φ = (K + σM)⁻¹ Fᵀ z` satisfies `(K + σM)⁻¹ M φ = μ φ`, i.e.
//! `K φ = λ M φ` with `λ = 1/μ − σ`. The largest `μ` are the lowest frequencies; massless
//! motions give `μ = 0` (infinite frequency) and the rigid motions, projected out, too. Distinct
//! eigenvectors `z` give M-orthogonal `φ`, repeated frequencies included.

use faer::linalg::solvers::Solve;
use faer::matrix_free::LinOp;
use faer::prelude::*;
use faer::dyn_stack::MemBuffer;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::linalg::LltError;
use faer::Conj;
use faer::sparse::SparseColMat;
use faer::{dyn_stack::MemStack, dyn_stack::StackReq, MatMut, MatRef, Par, Side};

use crate::assembly::AssembledModel;
use nalgebra::Vector3;

/// The factored shifted stiffness, the mass factor and the rigid-motion projector.
#[derive(Debug)]
pub struct ShiftInvert {
    /// The shift σ of `K + σ M` (1/s²).
    pub shift: f64,
    factor: Factor,
    /// `F` (r × n).
    mass_root: SparseColMat<usize, f64>,
    /// `Fᵀ` (n × r).
    mass_root_transpose: SparseColMat<usize, f64>,
    /// Orthonormal basis of `F R` (the rigid motions in the mass-weighted space).
    deflation: Mat<f64>,
    /// The rigid motions `R` (n × r) and `(RᵀMR)⁻¹ (MR)ᵀ` (r × n): the M-orthogonal projection onto
    /// them, removed from the mode shapes.
    rigid: Mat<f64>,
    rigid_coefficients: Mat<f64>,
}

impl ShiftInvert {
    /// Factors `K + shift M`; `rigid` holds the rigid motions over the free dofs (any basis).
    pub fn new(assembled: &AssembledModel, rigid: &Mat<f64>, shift: f64) -> Result<Self, LltError> {
        // Coordinate cuts where every equation is a translation (solid elements; their interface
        // nodes held); with rotations (beams, shells) the breadth-first levels. On the shell plate of
        // the `plate-modes` benchmark the coordinate cuts gave a factor with fewer nonzeros (4.47
        // million against AMD's 5.55 million) whose numeric factorization took four times as long
        // (1.4 s against 0.33 s; its estimated operations were fewer too, the cause is not found).
        let positions = assembled.dofs.only_translations().then_some(&assembled.equation_positions[..]);
        let factor = if shift == 0.0 {
            Factor::new(&assembled.stiffness, positions)?
        } else {
            Factor::new(&(&assembled.stiffness + &scale_sparse(&assembled.mass, shift)), positions)?
        };
        let mass_root = assembled.mass_root.clone();
        let mass_root_transpose = mass_root.transpose().to_col_major().expect("the transpose of a valid sparse matrix");
        let mut deflation = &mass_root * rigid;
        super::rigid::orthonormalize_columns(&mut deflation);
        let mass_rigid = &assembled.mass * rigid;
        let gram = rigid.transpose() * &mass_rigid;
        let rigid_coefficients = if rigid.ncols() == 0 {
            Mat::zeros(0, rigid.nrows())
        } else {
            gram.partial_piv_lu().solve(mass_rigid.transpose())
        };
        Ok(ShiftInvert { shift, factor, mass_root, mass_root_transpose, deflation, rigid: rigid.clone(), rigid_coefficients })
    }

    /// Dimension of the operator (the rows of the mass factor: the massive motions of the mass
    /// points).
    pub fn dim(&self) -> usize {
        self.mass_root.nrows()
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
        let mut y = &self.mass_root_transpose * &projected;
        self.factor.solve_in_place(y.as_mut());
        let mut z = &self.mass_root * &y;
        self.deflate(z.as_mut());
        z
    }

    /// The mode shapes `φ = (K + σM)⁻¹ Fᵀ z` of eigenvectors `z` of `B`, freed of the rigid motions
    /// that rounding in the solve with the nearly singular `K + σM` leaves in them (elastic modes
    /// are M-orthogonal to the rigid motions: `φ ← φ − R (RᵀMR)⁻¹ RᵀM φ`).
    pub fn mode_shapes(&self, z: MatRef<'_, f64>) -> Mat<f64> {
        let mut phi = &self.mass_root_transpose * z;
        self.factor.solve_in_place(phi.as_mut());
        if self.rigid.ncols() > 0 {
            let coefficients = &self.rigid_coefficients * &phi;
            phi -= &self.rigid * &coefficients;
        }
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

/// The sparse Cholesky factor of the shifted stiffness, with the fill-reducing ordering of the two
/// below that gives the smaller factor: faer's approximate minimum degree (AMD), or the nested
/// dissection of [`nested_dissection`](super::nested_dissection) (coordinate bisection of the
/// equations' nodes for solids, breadth-first levels otherwise), which on the 220,515-dof solid of the `solid-reduction` benchmark has
/// 108.1 million nonzeros against AMD's 193.4 million (159.0 million with breadth-first levels) and factors faster. Both symbolic analyses
/// are cheap next to the numeric factorization.
#[derive(Debug)]
struct Factor {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
}

impl Factor {
    /// Factors `a`, whose equations are at `positions` where given (the nested dissection's cuts).
    fn new(a: &SparseColMat<usize, f64>, positions: Option<&[Vector3<f64>]>) -> Result<Self, LltError> {
        let analyse = |ordering| factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, Default::default()).map_err(LltError::Generic);
        let amd = analyse(SymmetricOrdering::Amd)?;
        let (order, inverse) = super::nested_dissection::nested_dissection(a, positions);
        let dissection = analyse(SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, a.ncols())))?;
        let symbolic = if dissection.len_val() < amd.len_val() { dissection } else { amd };
        let mut values = vec![0.0; symbolic.len_val()];
        let scratch = symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        symbolic.factorize_numeric_llt(&mut values, a.as_ref(), Side::Lower, Default::default(), Par::Seq, MemStack::new(&mut MemBuffer::new(scratch)), Default::default())?;
        Ok(Factor { symbolic, values })
    }

    /// Solves `A x = b` in place for the columns of `b` (one pass over the factor for all of them).
    fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        let scratch = self.symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), Par::Seq);
        LltRef::<usize, f64>::new(&self.symbolic, &self.values).solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut MemBuffer::new(scratch)));
    }
}

fn scale_sparse(m: &SparseColMat<usize, f64>, factor: f64) -> SparseColMat<usize, f64> {
    let mut scaled = m.clone();
    for v in scaled.val_mut() {
        *v *= factor;
    }
    scaled
}
