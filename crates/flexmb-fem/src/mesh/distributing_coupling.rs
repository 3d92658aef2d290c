//! Distributing (RBE3-like) couplings: a reference node with six degrees of freedom whose motion is
//! the weighted least-squares average of the translations of a set of nodes — the interface node
//! through which a joint acts on a solid without stiffening the face it holds (`*DISTRIBUTING
//! COUPLING` of an `.inp` deck, with a `DCOUP3D` element for the reference node).
//!
//! With weights `w_i` at the coupled nodes `x_i`, their weighted centre `x̄ = Σ w_i x_i / W`,
//! `d_i = x_i − x̄` and `A = Σ w_i (|d_i|² I − d_i d_iᵀ)`, the reference node r at `x_r` moves as the
//! rigid motion that fits the coupled nodes' translations `u_i` best in the weighted least-squares
//! sense:
//!
//! ```text
//! θ_r = A⁻¹ Σ w_i d_i × u_i,        u_r = Σ w_i u_i / W + θ_r × (x_r − x̄)
//! ```
//!
//! A rigid motion of the coupled nodes is reproduced exactly; a force and a moment at the reference
//! node are distributed over the coupled nodes (the transpose of these relations) and add no
//! stiffness. The translations of the reference node are CalculiX's `*DISTRIBUTING COUPLING` when
//! it sits at `x̄` (CalculiX gives the reference node no rotations).
//!
//! The relations are eliminated like those of a [rigid coupling](super::RigidCoupling), but the
//! other way round: the reference node keeps its six dofs (so that it can be supported, loaded and
//! joined), and six of the coupled translations, chosen by pivoting for a well-conditioned
//! elimination, become dependent: `u_m = T_m⁻¹ (q_r − T_n u_n)` with `q_r = (u_r, θ_r)` and `T` the
//! relations above split into the chosen (`m`) and the other (`n`) coupled translations. This is
//! Nastran's choice of an RBE3's dependent ("UM") dofs.

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::coupling::{check_coupling, DependentDof};
use super::{Dof, DofSet, Mesh};
use crate::error::FemError;

/// A reference node and the nodes whose weighted average motion it follows.
#[derive(Clone, Debug, PartialEq)]
pub struct DistributingCoupling {
    /// The reference node (index into [`Mesh::nodes`]): six dofs, the interface node of joints.
    pub reference: usize,
    /// The coupled nodes (indices into [`Mesh::nodes`]); only their translations are coupled.
    pub nodes: Vec<usize>,
    /// The weight of each coupled node (positive; 1 for a uniform average).
    pub weights: Vec<f64>,
}

impl DistributingCoupling {
    /// The relations `q_r = T u_c` (6 × 3n: rows u_r, θ_r; columns the coupled nodes' translations),
    /// or why there are none.
    pub fn relations(&self, mesh: &Mesh) -> Result<DMatrix<f64>, String> {
        let n = self.nodes.len();
        if n != self.weights.len() {
            return Err(format!("{n} coupled nodes but {} weights", self.weights.len()));
        }
        if let Some(w) = self.weights.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
            return Err(format!("the weights must be positive, got {w}"));
        }
        let total: f64 = self.weights.iter().sum();
        let positions: Vec<Vector3<f64>> = self.nodes.iter().map(|&i| mesh.nodes[i].position).collect();
        let center: Vector3<f64> = positions.iter().zip(&self.weights).map(|(x, w)| *w * x).sum::<Vector3<f64>>() / total;
        let arms: Vec<Vector3<f64>> = positions.iter().map(|x| x - center).collect();
        let mut a = Matrix3::zeros();
        for (d, w) in arms.iter().zip(&self.weights) {
            a += *w * (Matrix3::identity() * d.norm_squared() - d * d.transpose());
        }
        // The fit's rotation is defined when A is regular: the nodes are not on one line.
        let scale = a.trace().max(f64::MIN_POSITIVE);
        let eigenvalues = a.symmetric_eigenvalues();
        if eigenvalues.min() <= 1e-9 * scale {
            return Err("the coupled nodes lie on one line (or are one point): the rotation about that line is undefined; couple nodes of a face".into());
        }
        let a_inverse = a.try_inverse().ok_or("the coupled nodes' moment matrix is singular")?;
        let offset = mesh.nodes[self.reference].position - center;
        let mut t = DMatrix::zeros(6, 3 * n);
        for (i, (d, w)) in arms.iter().zip(&self.weights).enumerate() {
            let theta = a_inverse * (*w * d.cross_matrix());
            // θ × e = −[e×] θ
            let translation = Matrix3::identity() * (*w / total) - offset.cross_matrix() * theta;
            t.view_mut((0, 3 * i), (3, 3)).copy_from(&translation);
            t.view_mut((3, 3 * i), (3, 3)).copy_from(&theta);
        }
        Ok(t)
    }
}

/// Appends the dependent dofs of the distributing couplings of `mesh` to `dependent`: six coupled
/// translations per coupling, as combinations of the reference node's dofs and the other coupled
/// translations. `coupled_to` marks the nodes already coupled (by any coupling); `supported` the
/// held dofs, which are not chosen as dependent.
pub(crate) fn append_dependent_dofs(
    mesh: &Mesh,
    present: &[DofSet],
    supported: &[DofSet],
    coupled_to: &mut [Option<usize>],
    dependent: &mut Vec<DependentDof>,
) -> Result<(), FemError> {
    for coupling in &mesh.distributing_couplings {
        let r = coupling.reference;
        let label = mesh.nodes[r].label;
        let invalid = |reason: String| FemError::InvalidDistributingCoupling { reference: label, reason };
        check_coupling(mesh, present, coupled_to, r, &coupling.nodes).map_err(invalid)?;
        let t = coupling.relations(mesh).map_err(invalid)?;
        // Row scaling: rotations by the coupling's size, so that the pivoting compares like with like.
        let size = coupling.nodes.iter().map(|&i| (mesh.nodes[i].position - mesh.nodes[r].position).norm()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
        let mut scaled = t.clone();
        for row in 3..6 {
            for c in 0..scaled.ncols() {
                scaled[(row, c)] *= size;
            }
        }
        let columns: Vec<usize> = (0..t.ncols()).filter(|&c| !supported[coupling.nodes[c / 3]].contains(Dof::ALL[c % 3])).collect();
        let chosen = pivot_columns(&scaled, &columns).ok_or_else(|| {
            invalid("the coupled translations that are not supported cannot carry the reference node's six motions".into())
        })?;
        let t_m = DMatrix::from_fn(6, 6, |i, j| t[(i, chosen[j])]);
        let t_m_inverse = t_m.try_inverse().ok_or_else(|| invalid("singular elimination".into()))?;
        let global = |c: usize| 6 * coupling.nodes[c / 3] + c % 3;
        for (k, &m) in chosen.iter().enumerate() {
            let mut terms: Vec<(usize, f64)> = (0..6).map(|i| (6 * r + i, t_m_inverse[(k, i)])).collect();
            for c in (0..t.ncols()).filter(|c| !chosen.contains(c)) {
                let value: f64 = -(0..6).map(|i| t_m_inverse[(k, i)] * t[(i, c)]).sum::<f64>();
                if value != 0.0 {
                    terms.push((global(c), value));
                }
            }
            dependent.push((global(m), terms));
        }
    }
    Ok(())
}

/// Six of `candidates` (columns of the 6-row `t`) that are well independent: Gram–Schmidt with the
/// largest remaining column first; `None` when fewer than six are independent.
fn pivot_columns(t: &DMatrix<f64>, candidates: &[usize]) -> Option<Vec<usize>> {
    let mut remaining: Vec<(usize, Vec<f64>)> = candidates.iter().map(|&c| (c, t.column(c).iter().copied().collect())).collect();
    let largest = remaining.iter().map(|(_, v)| norm(v)).fold(0.0, f64::max);
    let mut chosen = Vec::with_capacity(6);
    for _ in 0..6 {
        let (position, _) = remaining.iter().enumerate().max_by(|a, b| norm(&a.1 .1).total_cmp(&norm(&b.1 .1)))?;
        let (column, pivot) = remaining.swap_remove(position);
        let length = norm(&pivot);
        if length <= 1e-8 * largest {
            return None;
        }
        let unit: Vec<f64> = pivot.iter().map(|x| x / length).collect();
        for (_, v) in remaining.iter_mut() {
            let dot: f64 = v.iter().zip(&unit).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(&unit).for_each(|(a, b)| *a -= dot * b);
        }
        chosen.push(column);
    }
    Some(chosen)
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}
