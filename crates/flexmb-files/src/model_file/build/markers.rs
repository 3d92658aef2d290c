//! `[[marker]]` → [`Marker`]: a frame on a body or on ground; on a flexible body, a frame at one of
//! its nodes (`node`), which moves and turns with the node.

use flexmb::body::Marker;
use flexmb::math::Mat3;
use flexmb::model::{BodyId, BodyRef, MarkerId};
use flexmb::ModelBuilder;
use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::bodies::GROUND;
use super::context::Context;
use super::engine_errors;
use super::names::NameTable;
use super::nodes::{resolve_node, FlexibleNodes};
use super::orientation::{axes_from_z, orientation};
use crate::model_file::error::{ErrorKind, ModelFileError};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::MarkerSection;

pub(crate) fn add_markers(
    ctx: &Context,
    sections: &[Spanned<MarkerSection>],
    bodies: &NameTable<BodyId>,
    flexible: &FlexibleNodes,
    builder: &mut ModelBuilder,
    names: &mut NameTable<MarkerId>,
) -> Result<(), ModelFileError> {
    for (index, section) in sections.iter().enumerate() {
        let element = KeyPath::root().key("marker").index(index);
        let m = section.get_ref();
        names.check_new(&m.name, &element, ctx.source)?;
        let body = if m.body.get_ref() == GROUND {
            BodyRef::Ground
        } else {
            let id = bodies
                .get(m.body.get_ref())
                .ok_or_else(|| bodies.unknown(&m.body, &element.key("body"), ctx.source, &[GROUND]))?;
            BodyRef::Body(id)
        };
        let axes = axes(ctx, m, &element)?;
        let on_flexible = body.body().and_then(|id| flexible.get(id).map(|nodes| (id, nodes)));
        let id = match (on_flexible, &m.node) {
            (Some((body_id, nodes)), Some(node)) => {
                if let Some(origin) = &m.origin {
                    return Err(ctx.invalid(
                        &origin.span(),
                        &element.key("origin"),
                        "`origin` does not go with `node`: a marker at a node has its origin at the node",
                    ));
                }
                let node = resolve_node(ctx, nodes, node, &element.key("node"))?;
                builder
                    .add_node_marker(m.name.get_ref().clone(), body_id, node.index, axes)
                    .map_err(engine_errors::at(ctx.source, &m.name.span(), &element))?
            }
            (Some((_, nodes)), None) => {
                return Err(ctx.source.error(
                    ErrorKind::Schema,
                    &section.span(),
                    &element.key("node"),
                    format!(
                        "missing required key `node`: `{}` is a flexible body, and a marker on it sits at one of its \
                         nodes: `node = <label>` or `node = [x, y, z]` (body frame)",
                        nodes.body
                    ),
                ))
            }
            (None, Some(node)) => {
                let what = match body {
                    BodyRef::Ground => "ground".to_string(),
                    BodyRef::Body(_) => format!("`{}`, a rigid body", m.body.get_ref()),
                };
                return Err(ctx.invalid(
                    &node.span(),
                    &element.key("node"),
                    format!(
                        "`node` applies to markers on flexible bodies only, and this marker is on {what}; give its \
                         `origin` instead"
                    ),
                ));
            }
            (None, None) => builder.add_marker(Marker {
                name: m.name.get_ref().clone(),
                body,
                origin: ctx.vector_or_zero(&m.origin, &element.key("origin"), Quantity::Length)?,
                axes,
            })
            .map_err(engine_errors::at(ctx.source, &m.name.span(), &element))?,
        };
        names.define(&m.name, &element, id);
    }
    Ok(())
}

/// The marker's axes in its body's frame: from `orientation`, from `z_axis` (and `x_axis`), or the
/// body's own axes.
fn axes(ctx: &Context, m: &MarkerSection, element: &KeyPath) -> Result<Mat3, ModelFileError> {
    match (&m.orientation, &m.z_axis, &m.x_axis) {
        (Some(_), Some(z), _) => Err(ctx.invalid(
            &z.span(),
            &element.key("z_axis"),
            "give either `orientation` or `z_axis` (with optional `x_axis`), not both",
        )),
        (Some(_), None, Some(x)) | (None, None, Some(x)) => {
            Err(ctx.invalid(&x.span(), &element.key("x_axis"), "`x_axis` goes with `z_axis` only"))
        }
        (Some(o), None, None) => Ok(orientation(ctx, o, &element.key("orientation"))?.rotation_matrix()),
        (None, Some(z), x) => axes_from_z(ctx, z, x.as_ref(), element),
        (None, None, None) => Ok(Mat3::identity()),
    }
}
