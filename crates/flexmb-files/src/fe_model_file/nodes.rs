//! `[[node]]`: nodes with labels, for explicit elements; and the check that every one of them belongs
//! to an element.

use std::collections::{BTreeSet, HashSet};

use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::build::Builder;
use super::schema::NodeSection;
use crate::model_file::key_path::KeyPath;
use crate::model_file::ModelFileError;

pub(crate) fn add_nodes(b: &mut Builder, tables: &[Spanned<NodeSection>]) -> Result<(), ModelFileError> {
    let from_mesh: HashSet<u64> = b.model.mesh.nodes.iter().map(|n| n.label).collect();
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key("node").index(k);
        let n = table.get_ref();
        let label = n.label.get_ref().0;
        let label_key = element.key("label");
        if let Some((_, previous, span)) = b.explicit_nodes.get(&label) {
            return Err(b.ctx.invalid(
                &n.label.span(),
                &label_key,
                format!("node label {label} is already used by {previous} on line {}", b.source().line(span.start)),
            ));
        }
        if from_mesh.contains(&label) {
            let mesh = b.mesh_file.as_deref().unwrap_or("the mesh file");
            return Err(b.ctx.invalid(
                &n.label.span(),
                &label_key,
                format!("node label {label} is already used in the mesh file `{mesh}`"),
            ));
        }
        let position = b.ctx.vector_of(&n.position, &element.key("position"), Quantity::Length)?;
        let index = b.model.mesh.add_node(label, position);
        b.explicit_nodes.insert(label, (index, element, n.label.span()));
    }
    Ok(())
}

/// Every `[[node]]` must belong to an element: a node without one has no stiffness, and the mode
/// analysis would fail on it.
pub(crate) fn check_connected(b: &Builder) -> Result<(), ModelFileError> {
    let mesh = &b.model.mesh;
    let connected: BTreeSet<usize> = mesh.elements.iter().flat_map(|e| e.nodes.iter().copied()).collect();
    for (label, (index, element, span)) in &b.explicit_nodes {
        if !connected.contains(index) {
            return Err(b.ctx.invalid(
                span,
                &element.key("label"),
                format!(
                    "node {label} belongs to no element: it would have no stiffness; use it in a [[beam]] or [[shell]], \
                     or remove it"
                ),
            ));
        }
    }
    Ok(())
}
