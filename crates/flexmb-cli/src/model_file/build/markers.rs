//! `[[marker]]` → [`Marker`]: a frame on a body or on ground.

use flexmb::body::Marker;
use flexmb::math::Mat3;
use flexmb::model::{BodyId, BodyRef, MarkerId};
use flexmb::ModelBuilder;
use toml::Spanned;

use super::bodies::GROUND;
use super::context::Context;
use super::names::NameTable;
use super::orientation::{axes_from_z, orientation};
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::MarkerSection;

pub(crate) fn add_markers(
    ctx: &Context,
    sections: &[Spanned<MarkerSection>],
    bodies: &NameTable<BodyId>,
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
        let marker = Marker {
            name: m.name.get_ref().clone(),
            body,
            origin: ctx.vector_or_zero(&m.origin, &element.key("origin"))?,
            axes: axes(ctx, m, &element)?,
        };
        let id = builder.add_marker(marker);
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
