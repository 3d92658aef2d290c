//! The indices an FE model's parts refer to (nodes, materials, sections), checked against what the
//! model holds before anything is assembled: an index out of range is an error that names the part,
//! never a panic.

use super::{ElementKind, FeModel, Mesh};
use crate::error::FemError;

/// `Ok` if `index` is below `count`; otherwise the error that names `part` and what it refers to.
fn known(part: impl FnOnce() -> String, kind: &'static str, index: usize, count: usize) -> Result<(), FemError> {
    if index < count {
        Ok(())
    } else {
        Err(FemError::UnknownIndex { part: part(), kind, index, count })
    }
}

impl Mesh {
    /// Checks that every element's nodes and section, every section's material, every point mass's
    /// node and every node set's members are in the mesh.
    pub fn check_references(&self) -> Result<(), FemError> {
        let nodes = self.nodes.len();
        for s in &self.beam_sections {
            known(|| format!("beam section '{}'", s.name), "material", s.material, self.materials.len())?;
        }
        for s in &self.shell_sections {
            known(|| format!("shell section '{}'", s.name), "material", s.material, self.materials.len())?;
        }
        for s in &self.solid_sections {
            known(|| format!("solid section '{}'", s.name), "material", s.material, self.materials.len())?;
        }
        for e in &self.elements {
            let part = || format!("element {}", e.label);
            let (kind, section, count) = match e.kind {
                ElementKind::Beam { section } => ("beam section", section, self.beam_sections.len()),
                ElementKind::Shell { section } => ("shell section", section, self.shell_sections.len()),
                ElementKind::Solid { section, .. } => ("solid section", section, self.solid_sections.len()),
            };
            known(part, kind, section, count)?;
            e.nodes.iter().try_for_each(|&n| known(part, "node", n, nodes))?;
        }
        for pm in &self.point_masses {
            known(|| "a point mass".to_string(), "node", pm.node, nodes)?;
        }
        for coupling in &self.rigid_couplings {
            let part = || format!("the rigid coupling of reference node index {}", coupling.reference);
            known(part, "node", coupling.reference, nodes)?;
            coupling.nodes.iter().try_for_each(|&n| known(part, "node", n, nodes))?;
        }
        for coupling in &self.distributing_couplings {
            let part = || format!("the distributing coupling of reference node index {}", coupling.reference);
            known(part, "node", coupling.reference, nodes)?;
            coupling.nodes.iter().try_for_each(|&n| known(part, "node", n, nodes))?;
        }
        for (name, members) in &self.node_sets {
            members.iter().try_for_each(|&n| known(|| format!("node set '{name}'"), "node", n, nodes))?;
        }
        Ok(())
    }
}

impl FeModel {
    /// Checks the mesh's references ([`Mesh::check_references`]) and that every support, static
    /// load and interface node is a node of the mesh.
    pub fn check_references(&self) -> Result<(), FemError> {
        self.mesh.check_references()?;
        let nodes = self.mesh.nodes.len();
        for s in &self.supports {
            known(|| "a support".to_string(), "node", s.node, nodes)?;
        }
        for l in &self.static_loads {
            known(|| format!("static load '{}'", l.name), "node", l.node, nodes)?;
        }
        for &n in &self.interface_nodes {
            known(|| "an interface".to_string(), "node", n, nodes)?;
        }
        Ok(())
    }
}
