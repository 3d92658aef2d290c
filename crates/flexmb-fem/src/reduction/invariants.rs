//! The inertia invariants of a flexible body (formulation section 3; the seed's "constants from the
//! finite-element model"): sums over the mass points (the lumped-mass nodes, or the Gauss points of
//! a consistent mass) of the undeformed positions `s̄ᵢ` and the translational mode matrices `Ψᵢ`,
//! from which the mass matrix and the velocity terms of the equations of motion follow for any
//! modal state `a`.

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
        let m = modes;
        let mut inv = InertiaInvariants {
            mass: 0.0,
            c1: Vector3::zeros(),
            c2: DMatrix::zeros(3, m),
            c3: Matrix3::zeros(),
            c4: vec![Matrix3::zeros(); m],
            c5: vec![vec![Matrix3::zeros(); m]; m],
            c6: DMatrix::zeros(3, m),
            c7: vec![DMatrix::zeros(3, m); m],
            c8: DVector::zeros(m),
            c9: DMatrix::zeros(m, m),
            rotary_inertia: Matrix3::zeros(),
            rotary_coupling: DMatrix::zeros(3, m),
            rotary_modal_mass: DMatrix::zeros(m, m),
        };
        for i in 0..positions.len() {
            let (mi, s) = (masses[i], positions[i]);
            let s_tilde = skew(&s);
            let p = &psi[i];
            inv.mass += mi;
            inv.c1 += mi * s;
            inv.c2 += mi * p;
            inv.c3 += mi * s_tilde * s_tilde;
            inv.c6 += mi * s_tilde * p;
            inv.c9 += mi * p.transpose() * p;
            let psi_tilde: Vec<Matrix3<f64>> =
                (0..m).map(|j| skew(&Vector3::new(p[(0, j)], p[(1, j)], p[(2, j)]))).collect();
            for j in 0..m {
                inv.c4[j] += mi * s_tilde * psi_tilde[j];
                inv.c8[j] += mi * s.dot(&Vector3::new(p[(0, j)], p[(1, j)], p[(2, j)]));
                for k in 0..m {
                    inv.c5[j][k] += mi * psi_tilde[j] * psi_tilde[k];
                }
                inv.c7[j] += mi * DMatrix::from_fn(3, 3, |r, c| psi_tilde[j][(r, c)]) * p;
            }
            let j_i = DMatrix::from_fn(3, 3, |r, c| rotary[i][(r, c)]);
            if rotary[i] != Matrix3::zeros() {
                inv.rotary_inertia += rotary[i];
                inv.rotary_coupling += &j_i * &theta[i];
                inv.rotary_modal_mass += theta[i].transpose() * &j_i * &theta[i];
            }
        }
        Ok(inv)
    }

    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.c9.nrows()
    }
}
