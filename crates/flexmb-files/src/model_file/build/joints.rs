//! `[[joint]]` → [`Joint`]: a joint between two markers on different bodies.

use flexmb::joint::{Axis, Joint, JointKind};
use flexmb::model::{BodyId, JointId, MarkerId};
use flexmb::ModelBuilder;
use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::context::Context;
use super::engine_errors;
use super::names::NameTable;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{JointSection, Name};
use crate::model_file::value::NumberOrExpression;

/// Joint types as written in the file.
#[derive(Clone, Copy, PartialEq, Eq)]
enum JointType {
    Spherical,
    Revolute,
    Universal,
    Cylindrical,
    Translational,
    Fixed,
    Planar,
    Distance,
    Dot1,
    Dot2,
    PointOnLine,
    PointInPlane,
}

const JOINT_TYPES: &[(&str, JointType)] = &[
    ("spherical", JointType::Spherical),
    ("revolute", JointType::Revolute),
    ("universal", JointType::Universal),
    ("cylindrical", JointType::Cylindrical),
    ("translational", JointType::Translational),
    ("fixed", JointType::Fixed),
    ("planar", JointType::Planar),
    ("distance", JointType::Distance),
    ("dot-1", JointType::Dot1),
    ("dot-2", JointType::Dot2),
    ("point-on-line", JointType::PointOnLine),
    ("point-in-plane", JointType::PointInPlane),
];

const AXES: &[(&str, Axis)] = &[("x", Axis::X), ("y", Axis::Y), ("z", Axis::Z)];

pub(crate) fn add_joints(
    ctx: &Context,
    sections: &[Spanned<JointSection>],
    bodies: &NameTable<BodyId>,
    markers: &NameTable<MarkerId>,
    builder: &mut ModelBuilder,
    names: &mut NameTable<JointId>,
) -> Result<(), ModelFileError> {
    for (index, section) in sections.iter().enumerate() {
        let element = KeyPath::root().key("joint").index(index);
        let j = section.get_ref();
        names.check_new(&j.name, &element, ctx.source)?;
        let joint_type = ctx.keyword(&j.kind, &element.key("type"), "joint type", JOINT_TYPES)?;
        let marker_i = markers.resolve(&j.i, &element.key("i"), ctx.source)?;
        let marker_j = markers.resolve(&j.j, &element.key("j"), ctx.source)?;
        check_two_bodies(ctx, builder, bodies, (marker_i, &j.i), (marker_j, &j.j), &element.key("j"))?;
        let kind = joint_kind(ctx, j, joint_type, (marker_i, marker_j), builder, &element, &section.span())?;
        let id = builder
            .add_joint(Joint { name: j.name.get_ref().clone(), kind, marker_i, marker_j })
            .map_err(engine_errors::at(ctx.source, &j.name.span(), &element))?;
        names.define(&j.name, &element, id);
    }
    Ok(())
}

/// A joint must connect markers on two different bodies (or a body and ground). Drivers reuse the
/// markers of the joint they drive, so this covers them too.
fn check_two_bodies(
    ctx: &Context,
    builder: &ModelBuilder,
    bodies: &NameTable<BodyId>,
    (marker_i, name_i): (MarkerId, &Name),
    (marker_j, name_j): (MarkerId, &Name),
    key: &KeyPath,
) -> Result<(), ModelFileError> {
    let body_of = |marker| builder.marker(marker).map(|m| m.body);
    let body_i = body_of(marker_i);
    if body_i != body_of(marker_j) {
        return Ok(());
    }
    let body = match body_i.and_then(|b| b.body()).and_then(|id| bodies.name_of(id)) {
        None => "ground".to_string(),
        Some(name) => format!("body `{name}`"),
    };
    Err(ctx.invalid(
        &name_j.span(),
        key,
        format!(
            "markers `{}` and `{}` are both on {body}; a joint connects two different bodies (or a body and ground)",
            name_i.get_ref(),
            name_j.get_ref()
        ),
    ))
}

fn joint_kind(
    ctx: &Context,
    j: &JointSection,
    joint_type: JointType,
    (marker_i, marker_j): (MarkerId, MarkerId),
    builder: &ModelBuilder,
    element: &KeyPath,
    element_span: &std::ops::Range<usize>,
) -> Result<JointKind, ModelFileError> {
    let description = format!("a {} joint", j.kind.get_ref());
    let used: &[&str] = match joint_type {
        JointType::Distance => &["length"],
        JointType::Dot1 => &["axis_i", "axis_j"],
        JointType::Dot2 => &["axis_i"],
        _ => &[],
    };
    ctx.reject_unused_keys(element, &description, &j.optional_keys(), used)?;
    let axis = |value: &Option<Name>, name: &str| -> Result<Axis, ModelFileError> {
        let value = ctx.required(value, element, element_span, name, &description)?;
        ctx.keyword(value, &element.key(name), "axis", AXES)
    };
    Ok(match joint_type {
        JointType::Spherical => JointKind::Spherical,
        JointType::Revolute => JointKind::Revolute,
        JointType::Universal => JointKind::Universal,
        JointType::Cylindrical => JointKind::Cylindrical,
        JointType::Translational => JointKind::Translational,
        JointType::Fixed => JointKind::Fixed,
        JointType::Planar => JointKind::Planar,
        JointType::PointOnLine => JointKind::PointOnLine,
        JointType::PointInPlane => JointKind::PointInPlane,
        JointType::Dot1 => JointKind::Dot1 { axis_i: axis(&j.axis_i, "axis_i")?, axis_j: axis(&j.axis_j, "axis_j")? },
        JointType::Dot2 => JointKind::Dot2 { axis_i: axis(&j.axis_i, "axis_i")? },
        JointType::Distance => {
            let key = element.key("length");
            let length = match &j.length {
                Some(length) if matches!(length.get_ref(), NumberOrExpression::Number(_)) => {
                    let l = ctx.quantity(length, &key, Quantity::Length)?;
                    if l <= 0.0 {
                        return Err(ctx.invalid(&length.span(), &key, format!("length must be positive, got {l}")));
                    }
                    ctx.constant_time_function(l, &length.span(), &key)?
                }
                Some(length) => ctx.time_function(length, &key)?,
                None => {
                    let l = builder.initial_distance(marker_i, marker_j).unwrap_or(0.0);
                    if l <= 0.0 {
                        return Err(ctx.invalid(
                            element_span,
                            &key,
                            "the markers coincide initially, so the distance joint needs a positive `length`",
                        ));
                    }
                    ctx.constant_time_function(l, element_span, &key)?
                }
            };
            JointKind::Distance { length }
        }
    })
}
