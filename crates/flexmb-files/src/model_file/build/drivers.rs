//! `[[driver]]` → an angle or displacement driver: a joint of the engine with the same markers as the
//! driven joint, prescribing its relative angle or displacement as a function of time.

use flexmb::joint::{Joint, JointKind};
use flexmb::model::JointId;
use flexmb::ModelBuilder;
use toml::Spanned;

use super::context::Context;
use super::engine_errors;
use super::names::NameTable;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::DriverSection;

#[derive(Clone, Copy, PartialEq, Eq)]
enum DriverType {
    Angle,
    Displacement,
}

const DRIVER_TYPES: &[(&str, DriverType)] = &[("angle", DriverType::Angle), ("displacement", DriverType::Displacement)];

/// Adds the drivers; they share the joints' name space.
pub(crate) fn add_drivers(
    ctx: &Context,
    sections: &[Spanned<DriverSection>],
    builder: &mut ModelBuilder,
    joints: &mut NameTable<JointId>,
) -> Result<(), ModelFileError> {
    for (index, section) in sections.iter().enumerate() {
        let element = KeyPath::root().key("driver").index(index);
        let d = section.get_ref();
        joints.check_new(&d.name, &element, ctx.source)?;
        let joint_key = element.key("joint");
        let driven = joints.resolve(&d.joint, &joint_key, ctx.source)?;
        let joint = builder.joint(driven).cloned().ok_or_else(|| joints.unknown(&d.joint, &joint_key, ctx.source, &[]))?;
        let driver_type = driver_type(ctx, d, &joint, &element)?;
        let function = ctx.time_function(&d.function, &element.key("function"))?;
        let kind = match driver_type {
            DriverType::Angle => JointKind::AngleDriver { function },
            DriverType::Displacement => JointKind::DisplacementDriver { function },
        };
        let id = builder.add_joint(Joint {
            name: d.name.get_ref().clone(),
            kind,
            marker_i: joint.marker_i,
            marker_j: joint.marker_j,
        })
        .map_err(engine_errors::at(ctx.source, &d.name.span(), &element))?;
        joints.define(&d.name, &element, id);
    }
    Ok(())
}

/// The driver type given, or the one the joint allows; it must suit the joint.
fn driver_type(
    ctx: &Context,
    d: &DriverSection,
    joint: &Joint,
    element: &KeyPath,
) -> Result<DriverType, ModelFileError> {
    let joint_key = element.key("joint");
    let joint_kind = joint.kind.keyword();
    let drivable = "a driver acts on a revolute (angle), translational (displacement) or cylindrical (either) joint";
    if matches!(joint.kind, JointKind::AngleDriver { .. } | JointKind::DisplacementDriver { .. }) {
        return Err(ctx.invalid(
            &d.joint.span(),
            &joint_key,
            format!("`{}` is itself a driver; {drivable}", joint.name),
        ));
    }
    let given = d
        .kind
        .as_ref()
        .map(|k| ctx.keyword(k, &element.key("type"), "driver type", DRIVER_TYPES).map(|t| (t, k.span())))
        .transpose()?;
    let rotates = joint.kind.has_rotation_about_z();
    let slides = joint.kind.has_translation_along_z();
    match given {
        Some((DriverType::Angle, span)) if !rotates => Err(ctx.invalid(
            &span,
            &element.key("type"),
            format!("an angle driver needs a revolute or cylindrical joint, but `{}` is {joint_kind}", joint.name),
        )),
        Some((DriverType::Displacement, span)) if !slides => Err(ctx.invalid(
            &span,
            &element.key("type"),
            format!(
                "a displacement driver needs a translational or cylindrical joint, but `{}` is {joint_kind}",
                joint.name
            ),
        )),
        Some((t, _)) => Ok(t),
        None if rotates && slides => Err(ctx.invalid(
            &d.joint.span(),
            &element.key("type"),
            format!("`{}` is cylindrical: say `type = \"angle\"` or `type = \"displacement\"`", joint.name),
        )),
        None if rotates => Ok(DriverType::Angle),
        None if slides => Ok(DriverType::Displacement),
        None => Err(ctx.invalid(&d.joint.span(), &joint_key, format!("`{}` is {joint_kind}; {drivable}", joint.name))),
    }
}
