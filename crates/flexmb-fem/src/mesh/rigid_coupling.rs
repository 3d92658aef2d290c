//! Rigid (RBE2-like) couplings: a reference node with six degrees of freedom to which a set of nodes
//! is tied as one rigid body — the interface node through which a joint acts on a solid, whose own
//! nodes have no rotations (`*KINEMATIC COUPLING` or `*RIGID BODY` of an `.inp` deck).
//!
//! A coupled node s at `x_s` moves with the reference node r at `x_r`:
//! `u_s = u_r + θ_r × (x_s − x_r)`, and, where s has rotations (a beam or shell node) and the
//! coupling includes them, `θ_s = θ_r`. The coupled dofs are eliminated: they have no equation of
//! their own, and everything that acts on them (stiffness, mass, loads) acts through these relations
//! on the reference node's dofs (constraint elimination, `u = T u_r`).

use super::coupling::{check_coupling, DependentDof};
use super::{Dof, DofSet, FeModel, Mesh};
use crate::error::FemError;

/// A reference node and the nodes tied rigidly to it.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidCoupling {
    /// The reference node (index into [`Mesh::nodes`]): six dofs, the interface node of joints.
    pub reference: usize,
    /// The coupled nodes (indices into [`Mesh::nodes`]).
    pub nodes: Vec<usize>,
    /// Whether the coupled nodes' rotations (where they have them) follow the reference node's too.
    pub rotations: bool,
}

/// Appends the dependent dofs of the rigid couplings of `model` to `dependent`: each coupled node's
/// translations (and, with `rotations`, its rotations) as combinations of the reference node's dofs.
/// `coupled_to` marks the nodes already coupled (by any coupling).
pub(crate) fn append_dependent_dofs(
    model: &FeModel,
    present: &[DofSet],
    coupled_to: &mut [Option<usize>],
    dependent: &mut Vec<DependentDof>,
) -> Result<(), FemError> {
    let mesh: &Mesh = &model.mesh;
    for coupling in &mesh.rigid_couplings {
        let r = coupling.reference;
        let label = mesh.nodes[r].label;
        let invalid = |reason: String| FemError::InvalidCoupling { reference: label, reason };
        let reference_dof = |dof: Dof| 6 * r + dof.index();
        check_coupling(mesh, present, coupled_to, r, &coupling.nodes).map_err(invalid)?;
        for &s in &coupling.nodes {
            let slave = mesh.nodes[s].label;
            if model.supports.iter().any(|support| support.node == s && !support.dofs.is_empty()) {
                return Err(invalid(format!("node {slave} is coupled and supported: support the reference node instead")));
            }
            let d = mesh.nodes[s].position - mesh.nodes[r].position;
            // u_s = u_r + θ_r × d.
            let translations = [
                (Dof::Ux, vec![(Dof::Ux, 1.0), (Dof::Ry, d.z), (Dof::Rz, -d.y)]),
                (Dof::Uy, vec![(Dof::Uy, 1.0), (Dof::Rz, d.x), (Dof::Rx, -d.z)]),
                (Dof::Uz, vec![(Dof::Uz, 1.0), (Dof::Rx, d.y), (Dof::Ry, -d.x)]),
            ];
            for (dof, terms) in translations {
                let terms = terms.into_iter().filter(|(_, c)| *c != 0.0).map(|(rd, c)| (reference_dof(rd), c)).collect();
                dependent.push((6 * s + dof.index(), terms));
            }
            if coupling.rotations && present[s].contains(Dof::Rx) {
                for dof in [Dof::Rx, Dof::Ry, Dof::Rz] {
                    dependent.push((6 * s + dof.index(), vec![(reference_dof(dof), 1.0)]));
                }
            }
        }
    }
    Ok(())
}
