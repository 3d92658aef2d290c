//! The nodes of the model's flexible bodies, for the markers and outputs that refer to them: `node =
//! <label>`, `node = [x, y, z]` (the nearest node in the body frame) or, for bodies reduced from an FE
//! model file, `node = "set"` (a node set of one node).

use std::collections::BTreeMap;
use std::ops::Range;

use flexmb::math::Vec3;
use flexmb::model::BodyId;
use toml::Spanned;

use super::context::Context;
use crate::fe_model_file::format::{number, point};
use crate::fe_model_file::node_ref::NodeRef;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::suggest::did_you_mean;

/// A position names the nearest node if it lies within this fraction of the body's size of it.
pub(crate) const POSITION_TOLERANCE: f64 = 1e-6;
/// The smallest tolerance of a position (m), for tiny bodies.
const MIN_POSITION_TOLERANCE: f64 = 1e-9;

/// The nodes of one flexible body, in the engine's order (node index = position in these lists).
#[derive(Clone, Debug)]
pub(crate) struct BodyNodes {
    /// The body's name, for messages.
    pub body: String,
    pub labels: Vec<u64>,
    /// Undeformed positions in the body frame.
    pub positions: Vec<Vec3>,
    /// The FE model's node sets (by label), for bodies reduced from an FE model file; `None` for a
    /// flexible-body file, which has none.
    pub sets: Option<BTreeMap<String, Vec<u64>>>,
}

impl BodyNodes {
    /// The diagonal of the box around all nodes.
    fn size(&self) -> f64 {
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for p in &self.positions {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if self.positions.is_empty() {
            0.0
        } else {
            (hi - lo).norm()
        }
    }

    fn index_of(&self, label: u64) -> Option<usize> {
        self.labels.iter().position(|l| *l == label)
    }

    /// The label range, for messages.
    fn label_summary(&self) -> String {
        match (self.labels.iter().min(), self.labels.iter().max()) {
            (Some(lo), Some(hi)) => format!("{} nodes, labelled {lo} to {hi}", self.labels.len()),
            _ => "no nodes".to_string(),
        }
    }
}

/// The flexible bodies of the model, by id.
#[derive(Default)]
pub(crate) struct FlexibleNodes {
    bodies: BTreeMap<BodyId, BodyNodes>,
}

impl FlexibleNodes {
    pub(crate) fn insert(&mut self, id: BodyId, nodes: BodyNodes) {
        self.bodies.insert(id, nodes);
    }

    /// The nodes of `id`, if it is a flexible body.
    pub(crate) fn get(&self, id: BodyId) -> Option<&BodyNodes> {
        self.bodies.get(&id)
    }
}

/// A node reference resolved: the node's index in the body and its label.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ResolvedNode {
    pub index: usize,
    pub label: u64,
}

/// The node `node` names on the flexible body `nodes`.
pub(crate) fn resolve_node(
    ctx: &Context,
    nodes: &BodyNodes,
    node: &Spanned<NodeRef>,
    key: &KeyPath,
) -> Result<ResolvedNode, ModelFileError> {
    let span = node.span();
    let body = &nodes.body;
    let index = match node.get_ref() {
        NodeRef::Label(label) => nodes.index_of(*label).ok_or_else(|| {
            ctx.invalid(
                &span,
                key,
                format!("flexible body `{body}` has no node labelled {label} (it has {})", nodes.label_summary()),
            )
        })?,
        NodeRef::Position(components) => {
            let position = ctx.vector(&Spanned::new(span.clone(), components.clone()), key)?;
            node_at(ctx, nodes, &position, &span, key)?
        }
        NodeRef::Set(name) => node_of_set(ctx, nodes, name, &span, key)?,
    };
    Ok(ResolvedNode { index, label: nodes.labels[index] })
}

/// The node nearest `position` (body frame), if within the tolerance.
fn node_at(
    ctx: &Context,
    nodes: &BodyNodes,
    position: &Vec3,
    span: &Range<usize>,
    key: &KeyPath,
) -> Result<usize, ModelFileError> {
    let tolerance = (POSITION_TOLERANCE * nodes.size()).max(MIN_POSITION_TOLERANCE);
    let nearest =
        nodes.positions.iter().enumerate().map(|(k, p)| (k, (p - position).norm())).min_by(|a, b| a.1.total_cmp(&b.1));
    match nearest {
        Some((index, distance)) if distance <= tolerance => Ok(index),
        Some((index, distance)) => Err(ctx.invalid(
            span,
            key,
            format!(
                "flexible body `{}` has no node at {} (body frame): the nearest is node {} at {}, {} m away; a \
                 position must be within {} m of a node (1e-6 of the body's size)",
                nodes.body,
                point(position),
                nodes.labels[index],
                point(&nodes.positions[index]),
                number(distance),
                number(tolerance)
            ),
        )),
        None => Err(ctx.invalid(span, key, format!("flexible body `{}` has no nodes", nodes.body))),
    }
}

/// The single node of the FE model's node set `name`.
fn node_of_set(
    ctx: &Context,
    nodes: &BodyNodes,
    name: &str,
    span: &Range<usize>,
    key: &KeyPath,
) -> Result<usize, ModelFileError> {
    let body = &nodes.body;
    let Some(sets) = &nodes.sets else {
        return Err(ctx.invalid(
            span,
            key,
            format!(
                "flexible body `{body}` was read from a flexible-body file, which has no node sets: give a node label \
                 (`node = 21`) or a position (`node = [x, y, z]`)"
            ),
        ));
    };
    let set = sets.get(name).or_else(|| {
        let mut same = sets.iter().filter(|(n, _)| n.eq_ignore_ascii_case(name));
        match (same.next(), same.next()) {
            (Some((_, labels)), None) => Some(labels),
            _ => None,
        }
    });
    let Some(labels) = set else {
        let hint = did_you_mean(name, sets.keys().map(String::as_str));
        let known = if sets.is_empty() {
            " (its FE model has no node sets; give a node label or a position)".to_string()
        } else if hint.is_empty() && sets.len() <= 12 {
            let names: Vec<String> = sets.keys().map(|n| format!("`{n}`")).collect();
            format!(" (node sets: {})", names.join(", "))
        } else {
            String::new()
        };
        return Err(ctx.invalid(
            span,
            key,
            format!("flexible body `{body}` has no node set named `{name}`{hint}{known}"),
        ));
    };
    match labels.as_slice() {
        [label] => nodes.index_of(*label).ok_or_else(|| {
            ctx.invalid(span, key, format!("node {label} of node set `{name}` is not a node of flexible body `{body}`"))
        }),
        _ => Err(ctx.invalid(
            span,
            key,
            format!(
                "node set `{name}` of flexible body `{body}` holds {} nodes, but a marker or output is at exactly one \
                 node: give a node label, a position, or a set of one node",
                labels.len()
            ),
        )),
    }
}
