//! `[[measure]]` → [`Measure`]. Measure names appear in expressions, so they must be identifiers that
//! the expression language does not already give a meaning, and differ from every parameter.

use flexmb::measure::{Measure, MeasureKind};
use flexmb::model::{JointId, MarkerId, MeasureId};
use flexmb::ModelBuilder;
use toml::Spanned;

use super::context::Context;
use super::engine_errors;
use super::names::NameTable;
use crate::model_file::error::ModelFileError;
use flexmb::function::expression_text::{is_plain_identifier, BINARY_FUNCTION_NAMES, BUILTIN_NAMES};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{MeasureSection, Name};

#[derive(Clone, Copy, PartialEq, Eq)]
enum MeasureType {
    JointAngle,
    JointRate,
    JointDisplacement,
    JointVelocity,
    Distance,
    DistanceRate,
    Position,
    Velocity,
    Speed,
}

const MEASURE_TYPES: &[(&str, MeasureType)] = &[
    ("joint_angle", MeasureType::JointAngle),
    ("joint_rate", MeasureType::JointRate),
    ("joint_displacement", MeasureType::JointDisplacement),
    ("joint_velocity", MeasureType::JointVelocity),
    ("distance", MeasureType::Distance),
    ("distance_rate", MeasureType::DistanceRate),
    ("position", MeasureType::Position),
    ("velocity", MeasureType::Velocity),
    ("speed", MeasureType::Speed),
];

const COMPONENTS: &[(&str, usize)] = &[("x", 0), ("y", 1), ("z", 2)];

/// Adds every measure and records their names in `ctx` for the expressions that follow.
pub(crate) fn add_measures(
    ctx: &mut Context,
    sections: &[Spanned<MeasureSection>],
    joints: &NameTable<JointId>,
    markers: &NameTable<MarkerId>,
    builder: &mut ModelBuilder,
    names: &mut NameTable<MeasureId>,
) -> Result<(), ModelFileError> {
    for (index, section) in sections.iter().enumerate() {
        let element = KeyPath::root().key("measure").index(index);
        let m = section.get_ref();
        names.check_new(&m.name, &element, ctx.source)?;
        check_identifier(ctx, m, &element)?;
        let kind = measure_kind(ctx, m, joints, markers, builder, &element, &section.span())?;
        let id = builder
            .add_measure(Measure { name: m.name.get_ref().clone(), kind })
            .map_err(engine_errors::at(ctx.source, &m.name.span(), &element))?;
        names.define(&m.name, &element, id);
        ctx.measures.insert(m.name.get_ref().clone(), id);
    }
    Ok(())
}

fn check_identifier(ctx: &Context, m: &MeasureSection, element: &KeyPath) -> Result<(), ModelFileError> {
    let name = m.name.get_ref().as_str();
    let problem = if !is_plain_identifier(name) {
        "a measure name is used in expressions, so it must be an identifier: a letter or `_`, then letters, digits and `_`".to_string()
    } else if name == "t" {
        "`t` is time and cannot name a measure".to_string()
    } else if BUILTIN_NAMES.contains(&name) {
        format!("`{name}` is a constant or function of the expression language and cannot name a measure")
    } else if let Some(f) = BINARY_FUNCTION_NAMES.iter().find(|f| name.starts_with(**f)) {
        format!("a measure name cannot begin with `{f}`: the expression language would read it as the function `{f}`")
    } else if ctx.parameters.contains_key(name) {
        format!("`{name}` is also a parameter; parameters are substituted into expressions, so the names must differ")
    } else {
        return Ok(());
    };
    Err(ctx.invalid(&m.name.span(), &element.key("name"), problem))
}

fn measure_kind(
    ctx: &Context,
    m: &MeasureSection,
    joints: &NameTable<JointId>,
    markers: &NameTable<MarkerId>,
    builder: &ModelBuilder,
    element: &KeyPath,
    element_span: &std::ops::Range<usize>,
) -> Result<MeasureKind, ModelFileError> {
    let measure_type = ctx.keyword(&m.kind, &element.key("type"), "measure type", MEASURE_TYPES)?;
    let description = format!("a {} measure", m.kind.get_ref());
    let used: &[&str] = match measure_type {
        MeasureType::JointAngle
        | MeasureType::JointRate
        | MeasureType::JointDisplacement
        | MeasureType::JointVelocity => &["joint"],
        MeasureType::Distance | MeasureType::DistanceRate => &["i", "j"],
        MeasureType::Position | MeasureType::Velocity => &["marker", "component"],
        MeasureType::Speed => &["marker"],
    };
    ctx.reject_unused_keys(element, &description, &m.optional_keys(), used)?;
    let joint = || -> Result<JointId, ModelFileError> {
        let name = ctx.required(&m.joint, element, element_span, "joint", &description)?;
        let id = joints.resolve(name, &element.key("joint"), ctx.source)?;
        let kind = &builder.joint(id).ok_or_else(|| joints.unknown(name, &element.key("joint"), ctx.source, &[]))?.kind;
        let (fits, needs) = match measure_type {
            MeasureType::JointAngle | MeasureType::JointRate => {
                (kind.has_rotation_about_z(), "a revolute, cylindrical or angle-driven joint (a rotation about z_i)")
            }
            _ => (
                kind.has_translation_along_z(),
                "a translational, cylindrical or displacement-driven joint (a translation along z_i)",
            ),
        };
        if fits {
            Ok(id)
        } else {
            Err(ctx.invalid(
                &name.span(),
                &element.key("joint"),
                format!("{description} needs {needs}, but `{}` is {}", name.get_ref(), kind.keyword()),
            ))
        }
    };
    let marker = |key: &str, value: &Option<Name>| -> Result<MarkerId, ModelFileError> {
        let name = ctx.required(value, element, element_span, key, &description)?;
        markers.resolve(name, &element.key(key), ctx.source)
    };
    let component = || -> Result<usize, ModelFileError> {
        let name = ctx.required(&m.component, element, element_span, "component", &description)?;
        ctx.keyword(name, &element.key("component"), "component", COMPONENTS)
    };
    Ok(match measure_type {
        MeasureType::JointAngle => MeasureKind::JointAngle(joint()?),
        MeasureType::JointRate => MeasureKind::JointRate(joint()?),
        MeasureType::JointDisplacement => MeasureKind::JointDisplacement(joint()?),
        MeasureType::JointVelocity => MeasureKind::JointVelocity(joint()?),
        MeasureType::Distance => MeasureKind::Distance(marker("i", &m.i)?, marker("j", &m.j)?),
        MeasureType::DistanceRate => MeasureKind::DistanceRate(marker("i", &m.i)?, marker("j", &m.j)?),
        MeasureType::Position => MeasureKind::Position(marker("marker", &m.marker)?, component()?),
        MeasureType::Velocity => MeasureKind::Velocity(marker("marker", &m.marker)?, component()?),
        MeasureType::Speed => MeasureKind::Speed(marker("marker", &m.marker)?),
    })
}
