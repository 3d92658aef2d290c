//! `[[force]]` → [`ForceElement`]: spring-damper-actuators and applied forces and torques. Their
//! expressions may read any measure, whatever the order of the file.

use flexmb::force::{ForceElement, ForceFrame, ForceKind};
use flexmb::function::Expression;
use flexmb::model::{ForceId, JointId, MarkerId};
use flexmb::ModelBuilder;
use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::context::Context;
use super::engine_errors;
use super::names::NameTable;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{ForceSection, Name};

#[derive(Clone, Copy, PartialEq, Eq)]
enum ForceType {
    RotationalSpringDamper,
    TranslationalSpringDamper,
    Force,
    Torque,
}

const FORCE_TYPES: &[(&str, ForceType)] = &[
    ("rotational_spring_damper", ForceType::RotationalSpringDamper),
    ("translational_spring_damper", ForceType::TranslationalSpringDamper),
    ("force", ForceType::Force),
    ("torque", ForceType::Torque),
];

const FRAMES: &[(&str, ForceFrame)] =
    &[("global", ForceFrame::Global), ("body", ForceFrame::Body), ("marker", ForceFrame::Marker)];

/// The names a force refers to.
pub(crate) struct ForceReferences<'a> {
    pub joints: &'a NameTable<JointId>,
    pub markers: &'a NameTable<MarkerId>,
}

pub(crate) fn add_forces(
    ctx: &Context,
    sections: &[Spanned<ForceSection>],
    references: &ForceReferences,
    builder: &mut ModelBuilder,
    names: &mut NameTable<ForceId>,
) -> Result<(), ModelFileError> {
    for (index, section) in sections.iter().enumerate() {
        let element = KeyPath::root().key("force").index(index);
        let f = section.get_ref();
        names.check_new(&f.name, &element, ctx.source)?;
        let kind = ForceBuild { ctx, f, element: &element, span: section.span(), references, builder }.kind()?;
        let id = builder
            .add_force(ForceElement { name: f.name.get_ref().clone(), kind })
            .map_err(engine_errors::at(ctx.source, &f.name.span(), &element))?;
        names.define(&f.name, &element, id);
    }
    Ok(())
}

/// One force section being turned into a [`ForceKind`].
struct ForceBuild<'a> {
    ctx: &'a Context<'a>,
    f: &'a ForceSection,
    element: &'a KeyPath,
    span: std::ops::Range<usize>,
    references: &'a ForceReferences<'a>,
    builder: &'a ModelBuilder,
}

impl ForceBuild<'_> {
    fn kind(&self) -> Result<ForceKind, ModelFileError> {
        let (ctx, f, element) = (self.ctx, self.f, self.element);
        let force_type = ctx.keyword(&f.kind, &element.key("type"), "force type", FORCE_TYPES)?;
        let description = format!("a {} force", f.kind.get_ref());
        let used: &[&str] = match force_type {
            ForceType::RotationalSpringDamper => &["joint", "stiffness", "damping", "free_angle", "actuator"],
            ForceType::TranslationalSpringDamper => &["i", "j", "stiffness", "damping", "free_length", "actuator"],
            ForceType::Force | ForceType::Torque => &["marker", "frame", "components"],
        };
        ctx.reject_unused_keys(element, &description, &f.optional_keys(), used)?;
        Ok(match force_type {
            ForceType::RotationalSpringDamper => ForceKind::RotationalSpringDamper {
                joint: self.rotating_joint(&description)?,
                stiffness: ctx.non_negative_or(&f.stiffness, &element.key("stiffness"), 0.0, Quantity::Stiffness)?,
                damping: ctx.non_negative_or(&f.damping, &element.key("damping"), 0.0, Quantity::Damping)?,
                free_angle: ctx.number_or(&f.free_angle, &element.key("free_angle"), 0.0)?,
                actuator: self.actuator()?,
            },
            ForceType::TranslationalSpringDamper => {
                let marker_i = self.marker(&f.i, "i", &description)?;
                let marker_j = self.marker(&f.j, "j", &description)?;
                let initial_length = self.builder.initial_distance(marker_i, marker_j).unwrap_or(0.0);
                ForceKind::TranslationalSpringDamper {
                    marker_i,
                    marker_j,
                    stiffness: ctx.non_negative_or(&f.stiffness, &element.key("stiffness"), 0.0, Quantity::Stiffness)?,
                    damping: ctx.non_negative_or(&f.damping, &element.key("damping"), 0.0, Quantity::Damping)?,
                    free_length: ctx.non_negative_or(&f.free_length, &element.key("free_length"), initial_length, Quantity::Length)?,
                    actuator: self.actuator()?,
                }
            }
            ForceType::Force | ForceType::Torque => {
                let marker = self.marker(&f.marker, "marker", &description)?;
                let frame = match &f.frame {
                    Some(frame) => ctx.keyword(frame, &element.key("frame"), "frame", FRAMES)?,
                    None => ForceFrame::Global,
                };
                let components = self.components(&description)?;
                match force_type {
                    ForceType::Force => ForceKind::AppliedForce { marker, components, frame },
                    _ => ForceKind::AppliedTorque { marker, components, frame },
                }
            }
        })
    }

    fn rotating_joint(&self, description: &str) -> Result<JointId, ModelFileError> {
        let name = self.ctx.required(&self.f.joint, self.element, &self.span, "joint", description)?;
        let key = self.element.key("joint");
        let id = self.references.joints.resolve(name, &key, self.ctx.source)?;
        let kind = &self.builder.joint(id).ok_or_else(|| self.references.joints.unknown(name, &key, self.ctx.source, &[]))?.kind;
        if kind.has_rotation_about_z() {
            Ok(id)
        } else {
            Err(self.ctx.invalid(
                &name.span(),
                &key,
                format!(
                    "{description} acts about z_i of a revolute, cylindrical or angle-driven joint, but `{}` is {}",
                    name.get_ref(),
                    kind.keyword()
                ),
            ))
        }
    }

    fn marker(&self, value: &Option<Name>, key: &str, description: &str) -> Result<MarkerId, ModelFileError> {
        let name = self.ctx.required(value, self.element, &self.span, key, description)?;
        self.references.markers.resolve(name, &self.element.key(key), self.ctx.source)
    }

    fn actuator(&self) -> Result<Option<Expression>, ModelFileError> {
        self.f.actuator.as_ref().map(|a| self.ctx.expression(a, &self.element.key("actuator"))).transpose()
    }

    fn components(&self, description: &str) -> Result<[Expression; 3], ModelFileError> {
        let value = self.ctx.required(&self.f.components, self.element, &self.span, "components", description)?;
        let key = self.element.key("components");
        let items = value.get_ref();
        let [x, y, z] = items.as_slice() else {
            return Err(self.ctx.invalid(
                &value.span(),
                &key,
                format!("expected 3 components [x, y, z] (numbers or expressions), got {} component(s)", items.len()),
            ));
        };
        Ok([
            self.ctx.expression(x, &key.index(0))?,
            self.ctx.expression(y, &key.index(1))?,
            self.ctx.expression(z, &key.index(2))?,
        ])
    }
}
