//! The inertia invariants of a flexible body (formulation section 3; the seed's "constants from the
//! finite-element model"): sums over the mass points (the lumped-mass nodes, or the Gauss points of
//! a consistent mass) of the undeformed positions `s̄ᵢ` and the translational mode matrices `Ψᵢ`,
//! from which the mass matrix and the velocity terms of the equations of motion follow for any
//! modal state `a`.

use faer::Mat;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::serde_matrix;
use crate::error::FemError;

/// The nine sets of invariants, plus the rotary-inertia sums when the model lumps rotary inertia.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InertiaInvariants {
    /// `m = Σ mᵢ` (kg).
    pub mass: f64,
    /// `C1 = Σ mᵢ s̄ᵢ` (3).
    #[serde(with = "serde_matrix::vector3")]
    pub c1: Vector3<f64>,
    /// `C2 = Σ mᵢ Ψᵢ` (3×m).
    #[serde(with = "serde_matrix::dmatrix")]
    pub c2: DMatrix<f64>,
    /// `C3 = Σ mᵢ s̄̃ᵢ s̄̃ᵢ` (3×3); the inertia about the frame origin is `−C3`.
    #[serde(with = "serde_matrix::matrix3")]
    pub c3: Matrix3<f64>,
    /// `C4(j) = Σ mᵢ s̄̃ᵢ ψ̃ᵢʲ` (m of 3×3).
    #[serde(with = "serde_matrix::matrix3_list")]
    pub c4: Vec<Matrix3<f64>>,
    /// `C5(j,k) = Σ mᵢ ψ̃ᵢʲ ψ̃ᵢᵏ` (m×m of 3×3), `c5[j][k]`.
    #[serde(with = "serde_matrix::matrix3_table")]
    pub c5: Vec<Vec<Matrix3<f64>>>,
    /// `C6 = Σ mᵢ s̄̃ᵢ Ψᵢ` (3×m).
    #[serde(with = "serde_matrix::dmatrix")]
    pub c6: DMatrix<f64>,
    /// `C7(k) = Σ mᵢ ψ̃ᵢᵏ Ψᵢ` (m of 3×m).
    #[serde(with = "serde_matrix::dmatrix_list")]
    pub c7: Vec<DMatrix<f64>>,
    /// `C8(j) = Σ mᵢ s̄ᵢᵀ ψᵢʲ` (m).
    #[serde(with = "serde_matrix::dvector")]
    pub c8: DVector<f64>,
    /// `C9 = Σ mᵢ Ψᵢᵀ Ψᵢ`, the translational modal mass (m×m).
    #[serde(with = "serde_matrix::dmatrix")]
    pub c9: DMatrix<f64>,
    /// `Σ Jᵢ`: the nodes' own rotary inertia (3×3), zero without rotary inertia.
    #[serde(with = "serde_matrix::matrix3")]
    pub rotary_inertia: Matrix3<f64>,
    /// `Σ Jᵢ Θᵢ` (3×m), zero without rotary inertia.
    #[serde(with = "serde_matrix::dmatrix")]
    pub rotary_coupling: DMatrix<f64>,
    /// `Σ Θᵢᵀ Jᵢ Θᵢ` (m×m), zero without rotary inertia; `C9` plus this is `Φᵀ M Φ`.
    #[serde(with = "serde_matrix::dmatrix")]
    pub rotary_modal_mass: DMatrix<f64>,
}

/// One mass, rotary inertia and pair of mode matrices per point, each mode matrix 3×`modes`.
fn check_inputs(
    points: usize,
    lengths: [usize; 4],
    psi: &[DMatrix<f64>],
    theta: &[DMatrix<f64>],
    modes: usize,
) -> Result<(), FemError> {
    let bad = |message: String| Err(FemError::InvariantInputs { message });
    let names = ["masses", "rotary inertias", "psi matrices", "theta matrices"];
    if let Some((name, n)) = names.iter().zip(lengths).find(|(_, n)| *n != points) {
        return bad(format!("{n} {name} for {points} points"));
    }
    for (i, (p, t)) in psi.iter().zip(theta).enumerate() {
        if p.shape() != (3, modes) || t.shape() != (3, modes) {
            return bad(format!("point {i}: mode matrices {:?} and {:?}, expected (3, {modes})", p.shape(), t.shape()));
        }
    }
    Ok(())
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    v.cross_matrix()
}

/// `Σ Jᵢ`, `Σ Jᵢ Θᵢ` and `Σ Θᵢᵀ Jᵢ Θᵢ` over the points with rotary inertia, the last as one product
/// `Tᵀ U` of the tables `T` (row i: the components of `Θᵢ`) and `U` (row i: those of `Jᵢ Θᵢ`).
fn rotary_sums(rotary: &[Matrix3<f64>], theta: &[DMatrix<f64>], m: usize) -> (Matrix3<f64>, DMatrix<f64>, DMatrix<f64>) {
    let points: Vec<usize> = (0..rotary.len()).filter(|&i| rotary[i] != Matrix3::zeros()).collect();
    let mut inertia = Matrix3::zeros();
    let mut coupling = DMatrix::zeros(3, m);
    let (mut t, mut u) = (Mat::<f64>::zeros(points.len(), 3 * m), Mat::<f64>::zeros(points.len(), 3 * m));
    for (row, &i) in points.iter().enumerate() {
        let j_i = DMatrix::from_fn(3, 3, |r, c| rotary[i][(r, c)]);
        let j_theta = &j_i * &theta[i];
        inertia += rotary[i];
        coupling += &j_theta;
        for c in 0..3 * m {
            t[(row, c)] = theta[i][(c / m, c % m)];
            u[(row, c)] = j_theta[(c / m, c % m)];
        }
    }
    let products = t.transpose() * &u;
    let modal_mass = DMatrix::from_fn(m, m, |j, k| (0..3).map(|r| products[(r * m + j, r * m + k)]).sum());
    (inertia, coupling, modal_mass)
}

impl InertiaInvariants {
    /// The invariants of mass points at `positions` with `masses`, rotary inertias `rotary` (3×3 each),
    /// translational mode matrices `psi` and rotational ones `theta` (3×m each).
    ///
    /// # Errors
    /// [`FemError::InvariantInputs`] if the slices differ in length or a mode matrix is not 3×m.
    pub fn new(
        positions: &[Vector3<f64>],
        masses: &[f64],
        rotary: &[Matrix3<f64>],
        psi: &[DMatrix<f64>],
        theta: &[DMatrix<f64>],
        modes: usize,
    ) -> Result<InertiaInvariants, FemError> {
        check_inputs(positions.len(), [masses.len(), rotary.len(), psi.len(), theta.len()], psi, theta, modes)?;
        let (m, n) = (modes, positions.len());
        let (mut mass, mut c1, mut c3) = (0.0, Vector3::zeros(), Matrix3::zeros());
        for (&mi, s) in masses.iter().zip(positions) {
            mass += mi;
            c1 += mi * s;
            c3 += mi * skew(s) * skew(s);
        }
        // The sums over the points as products of point-by-point tables (matrix–matrix products,
        // not 3 × 3 products per point and pair of modes): `P = [Ψ_x Ψ_y Ψ_z]` (n × 3m, row i the
        // components of point i's mode displacements), `W = diag(mᵢ) P`, `X` the positions (n × 3).
        // `S = WᵀP` holds `S_rc(j, k) = Σ mᵢ ψʲ_r ψᵏ_c` and `Q = WᵀX` holds `Q_rc(j) = Σ mᵢ ψʲ_r s_c`.
        let psi_table = Mat::from_fn(n, 3 * m, |i, c| psi[i][(c / m, c % m)]);
        let weighted = Mat::from_fn(n, 3 * m, |i, c| masses[i] * psi_table[(i, c)]);
        let x = Mat::from_fn(n, 3, |i, c| positions[i][c]);
        let s_table = weighted.transpose() * &psi_table;
        let q_table = weighted.transpose() * &x;
        let s = |r: usize, c: usize, j: usize, k: usize| s_table[(r * m + j, c * m + k)];
        let q = |r: usize, c: usize, j: usize| q_table[(r * m + j, c)];
        // C2 = Σ mᵢ Ψᵢ: the column sums of W.
        let c2 = DMatrix::from_fn(3, m, |r, j| weighted.col(r * m + j).sum());
        // C9 = Σ mᵢ ΨᵢᵀΨᵢ = Σ_r S_rr.
        let c9 = DMatrix::from_fn(m, m, |j, k| (0..3).map(|r| s(r, r, j, k)).sum());
        // C8(j) = Σ mᵢ s̄ᵢ·ψᵢʲ = Σ_r Q_rr(j).
        let c8 = DVector::from_fn(m, |j, _| (0..3).map(|r| q(r, r, j)).sum());
        // ã b̃ = b aᵀ − (a·b) I, and ã b = a × b.
        // C4(j) = Σ mᵢ s̄̃ᵢ ψ̃ᵢʲ: (r, c) entry Q_rc(j) − δ_rc C8(j).
        let c4 = (0..m).map(|j| Matrix3::from_fn(|r, c| q(r, c, j) - if r == c { c8[j] } else { 0.0 })).collect();
        // C5(j, k) = Σ mᵢ ψ̃ᵢʲ ψ̃ᵢᵏ: (r, c) entry S_rc(k, j) − δ_rc C9(j, k).
        let c5 = (0..m)
            .map(|j| (0..m).map(|k| Matrix3::from_fn(|r, c| s(r, c, k, j) - if r == c { c9[(j, k)] } else { 0.0 })).collect())
            .collect();
        // C6 = Σ mᵢ s̄̃ᵢ Ψᵢ: column j is Σ mᵢ s̄ᵢ × ψᵢʲ.
        let cross = |f: &dyn Fn(usize, usize) -> f64, r: usize| {
            let (a, b) = ((r + 1) % 3, (r + 2) % 3);
            f(a, b) - f(b, a)
        };
        let c6 = DMatrix::from_fn(3, m, |r, j| cross(&|a, b| q(b, a, j), r));
        // C7(k) = Σ mᵢ ψ̃ᵢᵏ Ψᵢ: column j is Σ mᵢ ψᵢᵏ × ψᵢʲ.
        let c7 = (0..m).map(|k| DMatrix::from_fn(3, m, |r, j| cross(&|a, b| s(a, b, k, j), r))).collect();
        let (rotary_inertia, rotary_coupling, rotary_modal_mass) = rotary_sums(rotary, theta, m);
        Ok(InertiaInvariants { mass, c1, c2, c3, c4, c5, c6, c7, c8, c9, rotary_inertia, rotary_coupling, rotary_modal_mass })
    }

    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.c9.nrows()
    }
}
