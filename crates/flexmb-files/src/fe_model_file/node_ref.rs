//! Node references (`at = …`): a node label, a position (the node there), or the name of a node set.

use std::fmt;

use nalgebra::Vector3;
use serde::de::{self, Deserializer, SeqAccess, Unexpected, Visitor};
use serde::Deserialize;
use toml::Spanned;

use flexmb_fem::Mesh;

use super::format::{number, point};
use crate::model_file::build::context::Context;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::Number;
use crate::model_file::suggest::did_you_mean;
use crate::model_file::ModelFileError;

/// A position refers to the nearest node if it lies within this fraction of the mesh size of it.
pub(crate) const POSITION_TOLERANCE: f64 = 1e-6;
/// The smallest tolerance of a position reference (m), for tiny meshes.
pub(crate) const MIN_POSITION_TOLERANCE: f64 = 1e-9;

/// What `at` names.
#[derive(Clone, Debug)]
pub(crate) enum NodeRef {
    /// The node with this label.
    Label(u64),
    /// The node at this position `[x, y, z]`.
    Position(Vec<Number>),
    /// The nodes of a node set.
    Set(String),
}

impl<'de> Deserialize<'de> for NodeRef {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(NodeRefVisitor)
    }
}

struct NodeRefVisitor;

impl<'de> Visitor<'de> for NodeRefVisitor {
    type Value = NodeRef;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a node reference: a node label (a positive integer), a position [x, y, z] or a node set name")
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        match u64::try_from(v) {
            Ok(label) if label > 0 => Ok(NodeRef::Label(label)),
            _ => Err(E::invalid_value(Unexpected::Signed(v), &self)),
        }
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        if v > 0 {
            Ok(NodeRef::Label(v))
        } else {
            Err(E::invalid_value(Unexpected::Unsigned(v), &self))
        }
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        Ok(NodeRef::Set(v.to_string()))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut components = Vec::new();
        while let Some(component) = seq.next_element::<Number>()? {
            components.push(component);
        }
        Ok(NodeRef::Position(components))
    }
}

/// The node with `label`, or an error at `span` that says which labels exist.
pub(crate) fn node_by_label(
    ctx: &Context,
    mesh: &Mesh,
    label: u64,
    span: &std::ops::Range<usize>,
    key: &KeyPath,
) -> Result<usize, ModelFileError> {
    mesh.node_index(label).ok_or_else(|| {
        let known = match (mesh.nodes.iter().map(|n| n.label).min(), mesh.nodes.iter().map(|n| n.label).max()) {
            (Some(lo), Some(hi)) => format!("the mesh has {} nodes, labelled {lo} to {hi}", mesh.nodes.len()),
            _ => "the mesh has no nodes".to_string(),
        };
        ctx.invalid(span, key, format!("no node labelled {label} ({known})"))
    })
}

/// The nodes `at` refers to: one node, or all the nodes of a set.
pub(crate) fn resolve_nodes(
    ctx: &Context,
    mesh: &Mesh,
    at: &Spanned<NodeRef>,
    key: &KeyPath,
) -> Result<Vec<usize>, ModelFileError> {
    let span = at.span();
    match at.get_ref() {
        NodeRef::Label(label) => Ok(vec![node_by_label(ctx, mesh, *label, &span, key)?]),
        NodeRef::Position(components) => {
            let vector = Spanned::new(span.clone(), components.clone());
            let position = ctx.vector(&vector, key)?;
            Ok(vec![node_at(ctx, mesh, &position, &span, key)?])
        }
        NodeRef::Set(name) => match node_set(mesh, name) {
            Some(nodes) => Ok(nodes.clone()),
            None => Err(unknown_set(ctx, mesh, name, &span, key)),
        },
    }
}

/// The node set `name`; failing an exact match, the only set whose name differs in case (the mesh
/// file's names are case-insensitive).
fn node_set<'m>(mesh: &'m Mesh, name: &str) -> Option<&'m Vec<usize>> {
    mesh.node_sets.get(name).or_else(|| {
        let mut same = mesh.node_sets.iter().filter(|(n, _)| n.eq_ignore_ascii_case(name));
        match (same.next(), same.next()) {
            (Some((_, nodes)), None) => Some(nodes),
            _ => None,
        }
    })
}

/// The single node `at` refers to; a set must hold exactly one node. `what` (e.g. "a mass") is what
/// needs the node, for the message.
pub(crate) fn resolve_node(
    ctx: &Context,
    mesh: &Mesh,
    at: &Spanned<NodeRef>,
    key: &KeyPath,
    what: &str,
) -> Result<usize, ModelFileError> {
    let nodes = resolve_nodes(ctx, mesh, at, key)?;
    match (nodes.as_slice(), at.get_ref()) {
        ([node], _) => Ok(*node),
        (_, NodeRef::Set(name)) => {
            let held = match nodes.len() {
                0 => "holds no nodes".to_string(),
                n => format!("holds {n} nodes"),
            };
            let example = mesh
                .node_sets
                .iter()
                .find(|(_, set)| set.len() == 1)
                .map(|(name, _)| format!(" such as `{name}`"))
                .unwrap_or_default();
            Err(ctx.invalid(
                &at.span(),
                key,
                format!(
                    "node set `{name}` {held}, but {what} acts on exactly one node: give a node label, a \
                     position, or a set of one node{example}"
                ),
            ))
        }
        _ => unreachable!("a label or a position resolves to one node"),
    }
}

/// The node nearest `position`, if within the tolerance; otherwise an error naming the nearest node.
fn node_at(
    ctx: &Context,
    mesh: &Mesh,
    position: &Vector3<f64>,
    span: &std::ops::Range<usize>,
    key: &KeyPath,
) -> Result<usize, ModelFileError> {
    let tolerance = (POSITION_TOLERANCE * mesh.size()).max(MIN_POSITION_TOLERANCE);
    match mesh.nearest_node(position) {
        Some((index, distance)) if distance <= tolerance => Ok(index),
        Some((index, distance)) => {
            let nearest = &mesh.nodes[index];
            Err(ctx.invalid(
                span,
                key,
                format!(
                    "no node at {}: the nearest is node {} at {}, {} m away; a position must be within {} m of a \
                     node (1e-6 of the mesh size)",
                    point(position),
                    nearest.label,
                    point(&nearest.position),
                    number(distance),
                    number(tolerance)
                ),
            ))
        }
        None => Err(ctx.invalid(span, key, format!("no node at {}: the mesh has no nodes", point(position)))),
    }
}

fn unknown_set(ctx: &Context, mesh: &Mesh, name: &str, span: &std::ops::Range<usize>, key: &KeyPath) -> ModelFileError {
    let hint = did_you_mean(name, mesh.node_sets.keys().map(String::as_str));
    let known = if mesh.node_sets.is_empty() {
        " (the model has no node sets; name [[beam_line]] and [[plate]] tables to make some)".to_string()
    } else if hint.is_empty() && mesh.node_sets.len() <= 12 {
        let names: Vec<String> = mesh.node_sets.keys().map(|n| format!("`{n}`")).collect();
        format!(" (node sets: {})", names.join(", "))
    } else {
        String::new()
    };
    ctx.invalid(span, key, format!("no node set named `{name}`{hint}{known}"))
}
