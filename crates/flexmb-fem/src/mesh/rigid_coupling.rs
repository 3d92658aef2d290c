//! Rigid (RBE2-like) couplings: a reference node with six degrees of freedom to which a set of nodes
//! is tied as one rigid body — the interface node through which a joint acts on a solid, whose own
//! nodes have no rotations (`*KINEMATIC COUPLING` or `*RIGID BODY` of an `.inp` deck).
//!
//! A coupled node s at `x_s` moves with the reference node r at `x_r`:
//! `u_s = u_r + θ_r × (x_s − x_r)`, and, where s has rotations (a beam or shell node) and the
//! coupling includes them, `θ_s = θ_r`. The coupled dofs are eliminated: they have no equation of
//! their own, and everything that acts on them (stiffness, mass, loads) acts through these relations
//! on the reference node's dofs (constraint elimination, `u = T u_r`).

use super::distributing_coupling::append_dependent_dofs;
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

/// A dependent global dof (`6 node + dof`) and its combination of the reference node's global dofs.
pub(crate) type DependentDof = (usize, Vec<(usize, f64)>);

/// Checks that reference node `r` has rotations and is not coupled itself, and that each of `nodes`
/// is neither `r`, nor coupled before (by any coupling; marked now in `coupled_to`), nor a reference
/// node.
pub(crate) fn check_coupling(mesh: &Mesh, present: &[DofSet], coupled_to: &mut [Option<usize>], r: usize, nodes: &[usize]) -> Result<(), String> {
    if !present[r].contains(Dof::Rx) {
        return Err("the reference node is a node of solid elements only, without rotations: give it a node of its own".into());
    }
    if coupled_to[r].is_some() {
        return Err("the reference node is itself coupled to another reference node".into());
    }
    let references = || mesh.rigid_couplings.iter().map(|c| c.reference).chain(mesh.distributing_couplings.iter().map(|c| c.reference));
    for &s in nodes {
        let label = mesh.nodes[s].label;
        if s == r {
            return Err("the reference node is among the coupled nodes".into());
        }
        if let Some(other) = coupled_to[s].replace(r) {
            return Err(format!("node {label} is coupled twice (also to reference node {})", mesh.nodes[other].label));
        }
        if references().any(|x| x == s) {
            return Err(format!("node {label} is the reference node of another coupling"));
        }
    }
    Ok(())
}

/// The dependent dofs of the rigid and distributing couplings of `model`, given the dofs every node
/// has (`present`) and those its supports hold (`supported`).
pub(crate) fn dependent_dofs(model: &FeModel, present: &[DofSet], supported: &[DofSet]) -> Result<Vec<DependentDof>, FemError> {
    let mesh: &Mesh = &model.mesh;
    let mut coupled_to: Vec<Option<usize>> = vec![None; mesh.nodes.len()];
    let mut dependent = Vec::new();
    for coupling in &mesh.rigid_couplings {
        let r = coupling.reference;
        let label = mesh.nodes[r].label;
        let invalid = |reason: String| FemError::InvalidCoupling { reference: label, reason };
        let reference_dof = |dof: Dof| 6 * r + dof.index();
        check_coupling(mesh, present, &mut coupled_to, r, &coupling.nodes).map_err(invalid)?;
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
    append_dependent_dofs(mesh, present, supported, &mut coupled_to, &mut dependent)?;
    Ok(dependent)
}
