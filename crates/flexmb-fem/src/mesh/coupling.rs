//! What the rigid and distributing couplings share: the dependent dofs they make (constraint
//! elimination, `u = T u_r`), the checks of their reference and coupled nodes, and the list of both
//! kinds' dependent dofs that the assembly eliminates.

use super::{distributing_coupling, rigid_coupling, Dof, DofSet, FeModel, Mesh};
use crate::error::FemError;

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
    rigid_coupling::append_dependent_dofs(model, present, &mut coupled_to, &mut dependent)?;
    distributing_coupling::append_dependent_dofs(mesh, present, supported, &mut coupled_to, &mut dependent)?;
    Ok(dependent)
}
