//! A flexible body in modal form (formulation.md §2–§4): reference frame `R, p` plus modal coordinates
//! `a`, with the inertia invariants of its lumped-mass FE model, its modal stiffness and damping, and
//! the nodes where markers attach.
//!
//! The engine never reads files: the `flexmb-fem` preprocessor computes everything here and the
//! program layer converts it.

use nalgebra::{DMatrix, DVector, Matrix3xX};

use crate::math::{Mat3, Vec3};
use super::ModalGeometricStiffness;

/// The inertia invariants of a flexible body (formulation.md §3), with `m` modes.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalInvariants {
    /// `m = Σ mᵢ`.
    pub mass: f64,
    /// `C1 = Σ mᵢ s̄ᵢ`.
    pub c1: Vec3,
    /// `C2 = Σ mᵢ Ψᵢ` (3×m).
    pub c2: Matrix3xX<f64>,
    /// `C3 = Σ mᵢ s̄̃ᵢ s̄̃ᵢ`.
    pub c3: Mat3,
    /// `C4(j) = Σ mᵢ s̄̃ᵢ ψ̃ᵢʲ` (m).
    pub c4: Vec<Mat3>,
    /// `C5(j,k) = Σ mᵢ ψ̃ᵢʲ ψ̃ᵢᵏ`, stored row-major: `c5[j * m + k]`.
    pub c5: Vec<Mat3>,
    /// `C6 = Σ mᵢ s̄̃ᵢ Ψᵢ` (3×m).
    pub c6: Matrix3xX<f64>,
    /// `C7(k) = Σ mᵢ ψ̃ᵢᵏ Ψᵢ` (m of 3×m).
    pub c7: Vec<Matrix3xX<f64>>,
    /// `C9 = Σ mᵢ Ψᵢᵀ Ψᵢ` (m×m).
    pub c9: DMatrix<f64>,
    /// `Σ Jᵢ`, the nodes' own rotary inertia (zero without it).
    pub rotary_inertia: Mat3,
    /// `Σ Jᵢ Θᵢ` (3×m).
    pub rotary_coupling: Matrix3xX<f64>,
    /// `Σ Θᵢᵀ Jᵢ Θᵢ` (m×m).
    pub rotary_modal_mass: DMatrix<f64>,
}

/// Why a modal description cannot be made or analysed: sizes that disagree, a modal mass that is not
/// positive definite, damping ratios that do not fit the modes.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum ModalError {
    /// A node's mode matrix has a column count other than the number of modes.
    #[error("lumped node {node}: {matrix} has {found} columns, expected {modes} (one per mode)")]
    ModeColumns {
        /// The node's index.
        node: usize,
        /// `psi` or `theta`.
        matrix: &'static str,
        /// Its number of columns.
        found: usize,
        /// The number of modes.
        modes: usize,
    },
    /// The modal stiffness is not `m × m`.
    #[error("the modal stiffness is {rows}×{columns}; expected {modes}×{modes}, one row and column per mode")]
    StiffnessSize {
        /// Its rows.
        rows: usize,
        /// Its columns.
        columns: usize,
        /// The number of modes.
        modes: usize,
    },
    /// The modal mass has no Cholesky factor.
    #[error("the modal mass is not positive definite")]
    MassNotPositiveDefinite,
    /// The modal mass's Cholesky factor cannot be inverted.
    #[error("the modal mass is singular")]
    MassSingular,
    /// A high-mode damping whose cutoff is not positive or whose ratio is negative
    /// ([`HighModeDamping::validate`](super::HighModeDamping::validate)).
    #[error("{0}")]
    HighModeDamping(String),
    /// Damping ratios neither one for all modes nor one per mode.
    #[error("{given} damping ratios for {modes} modes; give one for all or one per mode")]
    RatioCount {
        /// How many ratios were given.
        given: usize,
        /// The number of modes.
        modes: usize,
    },
}

/// Every node's `Ψᵢ` and `Θᵢ` has one column per mode.
fn check_mode_columns(nodes: &[LumpedNode], modes: usize) -> Result<(), ModalError> {
    for (node, n) in nodes.iter().enumerate() {
        for (matrix, found) in [("psi", n.psi.ncols()), ("theta", n.theta.ncols())] {
            if found != modes {
                return Err(ModalError::ModeColumns { node, matrix, found, modes });
            }
        }
    }
    Ok(())
}

/// One lumped-mass node, for [`ModalInvariants::from_lumped_nodes`].
#[derive(Clone, Debug, PartialEq)]
pub struct LumpedNode {
    /// Undeformed position `s̄ᵢ` in the body frame.
    pub position: Vec3,
    /// Mass `mᵢ`.
    pub mass: f64,
    /// Rotary inertia `Jᵢ` about the node, body axes (zero if none).
    pub rotary_inertia: Mat3,
    /// Translational mode matrix `Ψᵢ` (3×m).
    pub psi: Matrix3xX<f64>,
    /// Rotational mode matrix `Θᵢ` (3×m).
    pub theta: Matrix3xX<f64>,
}

impl ModalInvariants {
    /// The invariants of formulation.md §3 summed over lumped-mass nodes with `modes` modes (for a
    /// modal body from another FE code's nodal masses and mode shapes).
    pub fn from_lumped_nodes(nodes: &[LumpedNode], modes: usize) -> Result<ModalInvariants, ModalError> {
        check_mode_columns(nodes, modes)?;
        let m = modes;
        let column = |p: &Matrix3xX<f64>, j: usize| Vec3::new(p[(0, j)], p[(1, j)], p[(2, j)]);
        let mut inv = ModalInvariants {
            mass: 0.0,
            c1: Vec3::zeros(),
            c2: Matrix3xX::zeros(m),
            c3: Mat3::zeros(),
            c4: vec![Mat3::zeros(); m],
            c5: vec![Mat3::zeros(); m * m],
            c6: Matrix3xX::zeros(m),
            c7: vec![Matrix3xX::zeros(m); m],
            c9: DMatrix::zeros(m, m),
            rotary_inertia: Mat3::zeros(),
            rotary_coupling: Matrix3xX::zeros(m),
            rotary_modal_mass: DMatrix::zeros(m, m),
        };
        for n in nodes {
            let s = n.position.cross_matrix();
            inv.mass += n.mass;
            inv.c1 += n.mass * n.position;
            inv.c2 += n.mass * &n.psi;
            inv.c3 += n.mass * s * s;
            inv.c6 += n.mass * s * &n.psi;
            inv.c9 += n.mass * n.psi.transpose() * &n.psi;
            inv.rotary_inertia += n.rotary_inertia;
            inv.rotary_coupling += n.rotary_inertia * &n.theta;
            inv.rotary_modal_mass += n.theta.transpose() * n.rotary_inertia * &n.theta;
            for j in 0..m {
                let pj = column(&n.psi, j).cross_matrix();
                inv.c4[j] += n.mass * s * pj;
                inv.c7[j] += n.mass * pj * &n.psi;
                for k in 0..m {
                    inv.c5[j * m + k] += n.mass * pj * column(&n.psi, k).cross_matrix();
                }
            }
        }
        Ok(inv)
    }

    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.c9.nrows()
    }

    /// `C5(j, k)`.
    #[inline]
    pub fn c5(&self, j: usize, k: usize) -> &Mat3 {
        &self.c5[j * self.modes() + k]
    }

    /// The modal mass `Φᵀ M Φ = C9 + Σ Θᵢᵀ Jᵢ Θᵢ`.
    pub fn modal_mass(&self) -> DMatrix<f64> {
        &self.c9 + &self.rotary_modal_mass
    }

    /// Inertia about the frame origin of the undeformed body, rotary inertia included: `−C3 + Σ Jᵢ`.
    pub fn undeformed_inertia(&self) -> Mat3 {
        -self.c3 + self.rotary_inertia
    }
}

/// A node of a flexible body: undeformed position in the body frame, and its translational and
/// rotational mode matrices `Ψᵢ`, `Θᵢ` (3×m).
#[derive(Clone, Debug, PartialEq)]
pub struct ModalNode {
    /// The node's label in the FE model, for messages and outputs.
    pub label: u64,
    /// Undeformed position `s̄ᵢ` in the body frame (m).
    pub position: Vec3,
    /// Translational mode matrix `Ψᵢ` (3×m): the node's displacement per unit modal coordinate.
    pub psi: Matrix3xX<f64>,
    /// Rotational mode matrix `Θᵢ` (3×m): the node's small rotation per unit modal coordinate.
    pub theta: Matrix3xX<f64>,
}

/// Modal damping of a flexible body.
#[derive(Clone, Debug, PartialEq)]
pub enum ModalDamping {
    /// No damping.
    None,
    /// A damping ratio ζ for every natural mode of the reduced model (one value for all, or one per
    /// mode): `D = M X diag(2 ζⱼ ωⱼ) Xᵀ M` with `X` the mass-normalized eigenvectors of `(K, M)`.
    Ratios(Vec<f64>),
    /// Rayleigh damping `D = α M + β K`.
    Rayleigh {
        /// The mass factor α (1/s).
        alpha: f64,
        /// The stiffness factor β (s).
        beta: f64,
    },
}

/// A flexible body's modal description.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalBody {
    /// The inertia invariants of its FE model.
    pub invariants: ModalInvariants,
    /// Modal stiffness `K_aa` (m×m).
    pub stiffness: DMatrix<f64>,
    /// Modal damping `D_aa` (m×m), from [`ModalDamping`] by [`ModalBody::damping_matrix`].
    pub damping: DMatrix<f64>,
    /// All nodes of the FE model (markers attach at nodes; outputs read them).
    pub nodes: Vec<ModalNode>,
    /// Mode labels (`N1`, `S2`, `O3`, …), for outputs.
    pub mode_labels: Vec<String>,
    /// Initial modal coordinates `a(0)` (default zero).
    pub initial_coordinates: DVector<f64>,
    /// Initial modal rates `ȧ(0)` (default zero).
    pub initial_rates: DVector<f64>,
    /// The geometric stiffening of its unit inertia loads, added to the modal equations when
    /// present (`None`: the body keeps its unstressed stiffness).
    pub geometric_stiffness: Option<ModalGeometricStiffness>,
}

impl ModalBody {
    /// A modal body from lumped-mass nodes and a modal stiffness (m×m): the invariants summed over the
    /// nodes, modes labelled `M1`, `M2`, …, no damping, initial modal coordinates and rates zero.
    pub fn from_lumped_nodes(nodes: &[LumpedNode], stiffness: DMatrix<f64>) -> Result<ModalBody, ModalError> {
        let m = stiffness.nrows();
        if stiffness.ncols() != m {
            return Err(ModalError::StiffnessSize { rows: m, columns: stiffness.ncols(), modes: m });
        }
        Ok(ModalBody {
            invariants: ModalInvariants::from_lumped_nodes(nodes, m)?,
            stiffness,
            damping: DMatrix::zeros(m, m),
            nodes: nodes
                .iter()
                .enumerate()
                .map(|(k, n)| ModalNode { label: k as u64 + 1, position: n.position, psi: n.psi.clone(), theta: n.theta.clone() })
                .collect(),
            mode_labels: (1..=m).map(|j| format!("M{j}")).collect(),
            initial_coordinates: DVector::zeros(m),
            initial_rates: DVector::zeros(m),
            geometric_stiffness: None,
        })
    }

    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.invariants.modes()
    }

    /// The natural modes of the reduced model: the eigenvalues `ω²` of `(K_aa, M_aa)`, lowest first,
    /// and the mass-normalized eigenvectors `X` (columns, in the same order); an error if the modal
    /// mass is not positive definite.
    pub fn natural_modes(&self) -> Result<(Vec<f64>, DMatrix<f64>), ModalError> {
        let m = self.modes();
        if self.stiffness.shape() != (m, m) {
            let (rows, columns) = self.stiffness.shape();
            return Err(ModalError::StiffnessSize { rows, columns, modes: m });
        }
        let mass = self.invariants.modal_mass();
        let chol = nalgebra::Cholesky::new(mass).ok_or(ModalError::MassNotPositiveDefinite)?;
        let l_inv = chol.l().try_inverse().ok_or(ModalError::MassSingular)?;
        let reduced = &l_inv * &self.stiffness * l_inv.transpose();
        let reduced = 0.5 * (&reduced + reduced.transpose());
        let eigen = nalgebra::SymmetricEigen::new(reduced);
        // X = L⁻ᵀ Y; nalgebra does not sort the eigenvalues.
        let x = l_inv.transpose() * &eigen.eigenvectors;
        let mut order: Vec<usize> = (0..self.modes()).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
        let omega_squared = order.iter().map(|&k| eigen.eigenvalues[k]).collect();
        Ok((omega_squared, x.select_columns(order.iter())))
    }

    /// The lowest natural circular frequency of the reduced model (rad/s); `None` without modes or
    /// with a modal mass that is not positive definite.
    pub fn lowest_frequency(&self) -> Option<f64> {
        let (omega_squared, _) = self.natural_modes().ok()?;
        omega_squared.first().map(|w2| w2.max(0.0).sqrt())
    }

    /// The damping matrix of `damping` for this body's modal mass and stiffness; an error if the
    /// modal mass is not positive definite, the stiffness not `m × m` or a ratio list has the wrong
    /// length.
    pub fn damping_matrix(&self, damping: &ModalDamping) -> Result<DMatrix<f64>, ModalError> {
        let m = self.modes();
        if m == 0 {
            return Ok(DMatrix::zeros(0, 0));
        }
        let mass = self.invariants.modal_mass();
        match damping {
            ModalDamping::None => Ok(DMatrix::zeros(m, m)),
            ModalDamping::Rayleigh { alpha, beta } => {
                if self.stiffness.shape() != (m, m) {
                    let (rows, columns) = self.stiffness.shape();
                    return Err(ModalError::StiffnessSize { rows, columns, modes: m });
                }
                Ok(*alpha * &mass + *beta * &self.stiffness)
            }
            ModalDamping::Ratios(ratios) => {
                if ratios.len() != 1 && ratios.len() != m {
                    return Err(ModalError::RatioCount { given: ratios.len(), modes: m });
                }
                // D = M X diag(2ζω) Xᵀ M. The k-th ratio goes to the mode of k-th lowest frequency.
                let (omega_squared, x) = self.natural_modes()?;
                let mut diag = DMatrix::zeros(m, m);
                for (k, w2) in omega_squared.iter().enumerate() {
                    let zeta = if ratios.len() == 1 { ratios[0] } else { ratios[k] };
                    diag[(k, k)] = 2.0 * zeta * w2.max(0.0).sqrt();
                }
                let mx = &mass * &x;
                Ok(&mx * diag * mx.transpose())
            }
        }
    }
}
