//! `[[interface]]`: the interface nodes of the body, where joints and force elements of a mechanism
//! act on it; one node or every node of a set per table. A node named twice is one interface node.

use toml::Spanned;

use super::build::Builder;
use super::node_ref::resolve_nodes;
use super::schema::InterfaceSection;
use crate::model_file::key_path::KeyPath;
use crate::model_file::ModelFileError;

pub(crate) fn add_interfaces(b: &mut Builder, tables: &[Spanned<InterfaceSection>]) -> Result<(), ModelFileError> {
    for (k, table) in tables.iter().enumerate() {
        let at_key = KeyPath::root().key("interface").index(k).key("at");
        let at = &table.get_ref().at;
        let nodes = resolve_nodes(&b.ctx, &b.model.mesh, at, &at_key)?;
        if nodes.is_empty() {
            return Err(b.ctx.invalid(&at.span(), &at_key, "this node set holds no nodes"));
        }
        for node in nodes {
            if !b.model.interface_nodes.contains(&node) {
                b.model.interface_nodes.push(node);
            }
        }
    }
    Ok(())
}
