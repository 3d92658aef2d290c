//! `[[beam]]` and `[[shell]]`: elements listed by their node labels. Each element is checked where it
//! is written: node count, known and distinct labels, a beam's orientation, and the element's own
//! geometry checks (zero length, degenerate or warped shells).

use std::collections::HashMap;

use toml::Spanned;

use flexmb_fem::element::element_matrices;
use flexmb_fem::{Element, ElementKind};

use super::build::Builder;
use super::node_ref::node_by_label;
use super::schema::ElementSection;
use super::sections::check_orientation;
use crate::model_file::key_path::KeyPath;
use crate::model_file::ModelFileError;

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Beam,
    Shell,
}

pub(crate) fn add_beams(b: &mut Builder, tables: &[Spanned<ElementSection>]) -> Result<(), ModelFileError> {
    add_elements(b, tables, Kind::Beam)
}

pub(crate) fn add_shells(b: &mut Builder, tables: &[Spanned<ElementSection>]) -> Result<(), ModelFileError> {
    add_elements(b, tables, Kind::Shell)
}

fn add_elements(b: &mut Builder, tables: &[Spanned<ElementSection>], kind: Kind) -> Result<(), ModelFileError> {
    if tables.is_empty() {
        return Ok(());
    }
    let labels: HashMap<u64, usize> = b.model.mesh.nodes.iter().enumerate().map(|(i, n)| (n.label, i)).collect();
    let mut next_label = b.model.mesh.max_element_label() + 1;
    let (table_name, what) = match kind {
        Kind::Beam => ("beam", "a beam element has 2 nodes"),
        Kind::Shell => ("shell", "a shell element has 3 (triangle) or 4 (quadrilateral) nodes"),
    };
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key(table_name).index(k);
        let t = table.get_ref();
        let section_key = element.key("section");
        let section = match kind {
            Kind::Beam => b.beam_sections.resolve(&t.section, &section_key, b.source())?,
            Kind::Shell => b.shell_sections.resolve(&t.section, &section_key, b.source())?,
        };
        let nodes_key = element.key("nodes");
        if t.nodes.get_ref().is_empty() {
            return Err(b.ctx.invalid(&t.nodes.span(), &nodes_key, "expected at least one element, got none"));
        }
        for (e, entry) in t.nodes.get_ref().iter().enumerate() {
            let entry_key = nodes_key.index(e);
            let count = entry.get_ref().len();
            let count_ok = match kind {
                Kind::Beam => count == 2,
                Kind::Shell => count == 3 || count == 4,
            };
            if !count_ok {
                return Err(b.ctx.invalid(&entry.span(), &entry_key, format!("{what}, got {count}")));
            }
            let mut nodes = Vec::with_capacity(count);
            for (m, label) in entry.get_ref().iter().enumerate() {
                let label_key = entry_key.index(m);
                let value = label.get_ref().0;
                let node = match labels.get(&value) {
                    Some(&node) => node,
                    None => node_by_label(&b.ctx, &b.model.mesh, value, &label.span(), &label_key)?,
                };
                if nodes.contains(&node) {
                    return Err(b.ctx.invalid(
                        &label.span(),
                        &label_key,
                        format!("node {value} appears twice in this element; its nodes must be different"),
                    ));
                }
                nodes.push(node);
            }
            let mesh = &b.model.mesh;
            if kind == Kind::Beam {
                let axis = mesh.nodes[nodes[1]].position - mesh.nodes[nodes[0]].position;
                if axis.norm() > 0.0 {
                    let [first, second] = [entry.get_ref()[0].get_ref().0, entry.get_ref()[1].get_ref().0];
                    let what = format!("the beam from node {first} to node {second}");
                    check_orientation(b, section, &axis, &entry.span(), &entry_key, &what)?;
                }
            }
            let new = Element {
                label: next_label,
                kind: match kind {
                    Kind::Beam => ElementKind::Beam { section },
                    Kind::Shell => ElementKind::Shell { section },
                },
                nodes,
            };
            if let Err(problem) = element_matrices(mesh, &new, &b.model.options) {
                return Err(b.ctx.invalid(&entry.span(), &entry_key, format!("element {}: {problem}", new.label)));
            }
            b.model.mesh.elements.push(new);
            next_label += 1;
        }
    }
    Ok(())
}
