//! `[[output]]` → output requests. An output without a name is named after its element and type, e.g.
//! `crank_pin.position`, `pivot.reaction`, `energy`, `beam.modal_coordinates`, `beam.node21.position`.

use flexmb::model::{BodyId, JointId, MarkerId, MeasureId, OutputKind};
use flexmb::ModelBuilder;
use toml::Spanned;

use super::context::Context;
use super::engine_errors;
use super::names::NameTable;
use super::nodes::{resolve_node, BodyNodes, FlexibleNodes};
use crate::model_file::error::{ErrorKind, ModelFileError};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{Name, OutputSection};

#[derive(Clone, Copy, PartialEq, Eq)]
enum OutputType {
    MarkerPosition,
    MarkerVelocity,
    MarkerAcceleration,
    MarkerAngularVelocity,
    JointReaction,
    Measure,
    Energy,
    ConstraintResidual,
    ModalCoordinates,
    NodePosition,
    NodeVelocity,
    NodeAcceleration,
    NodeDeformation,
    StrainEnergy,
}

const OUTPUT_TYPES: &[(&str, OutputType)] = &[
    ("marker_position", OutputType::MarkerPosition),
    ("marker_velocity", OutputType::MarkerVelocity),
    ("marker_acceleration", OutputType::MarkerAcceleration),
    ("marker_angular_velocity", OutputType::MarkerAngularVelocity),
    ("joint_reaction", OutputType::JointReaction),
    ("measure", OutputType::Measure),
    ("energy", OutputType::Energy),
    ("constraint_residual", OutputType::ConstraintResidual),
    ("modal_coordinates", OutputType::ModalCoordinates),
    ("node_position", OutputType::NodePosition),
    ("node_velocity", OutputType::NodeVelocity),
    ("node_acceleration", OutputType::NodeAcceleration),
    ("node_deformation", OutputType::NodeDeformation),
    ("strain_energy", OutputType::StrainEnergy),
];

/// The names an output refers to.
pub(crate) struct OutputReferences<'a> {
    pub markers: &'a NameTable<MarkerId>,
    pub joints: &'a NameTable<JointId>,
    pub measures: &'a NameTable<MeasureId>,
    pub bodies: &'a NameTable<BodyId>,
    pub flexible: &'a FlexibleNodes,
}

pub(crate) fn add_outputs(
    ctx: &Context,
    sections: &[Spanned<OutputSection>],
    references: &OutputReferences,
    builder: &mut ModelBuilder,
    names: &mut NameTable<usize>,
) -> Result<(), ModelFileError> {
    for (index, section) in sections.iter().enumerate() {
        let element = KeyPath::root().key("output").index(index);
        let o = section.get_ref();
        let (kind, default_name) = output_kind(ctx, o, references, &element, &section.span())?;
        let name = match &o.name {
            Some(name) => name.clone(),
            None => Spanned::new(o.kind.span(), default_name),
        };
        names.check_new(&name, &element, ctx.source).map_err(|mut e| {
            if o.name.is_none() {
                e.message.push_str("; give this output its own `name`");
            }
            e
        })?;
        builder.add_output(name.get_ref().clone(), kind).map_err(engine_errors::at(ctx.source, &name.span(), &element))?;
        names.define(&name, &element, index);
    }
    Ok(())
}

/// The request and its default name.
fn output_kind<'a>(
    ctx: &Context,
    o: &'a OutputSection,
    references: &OutputReferences,
    element: &KeyPath,
    element_span: &std::ops::Range<usize>,
) -> Result<(OutputKind, String), ModelFileError> {
    let output_type = ctx.keyword(&o.kind, &element.key("type"), "output type", OUTPUT_TYPES)?;
    let description = format!("a {} output", o.kind.get_ref());
    let used: &[&str] = match output_type {
        OutputType::MarkerPosition
        | OutputType::MarkerVelocity
        | OutputType::MarkerAcceleration
        | OutputType::MarkerAngularVelocity => &["marker"],
        OutputType::JointReaction => &["joint"],
        OutputType::Measure => &["measure"],
        OutputType::Energy | OutputType::ConstraintResidual => &[],
        OutputType::ModalCoordinates | OutputType::StrainEnergy => &["body"],
        OutputType::NodePosition
        | OutputType::NodeVelocity
        | OutputType::NodeAcceleration
        | OutputType::NodeDeformation => &["body", "node"],
    };
    ctx.reject_unused_keys(element, &description, &o.optional_keys(), used)?;
    let reference = |value: &'a Option<Name>, key: &str| -> Result<&'a Name, ModelFileError> {
        ctx.required(value, element, element_span, key, &description)
    };
    let marker = || -> Result<(MarkerId, String), ModelFileError> {
        let name = reference(&o.marker, "marker")?;
        Ok((references.markers.resolve(name, &element.key("marker"), ctx.source)?, name.get_ref().clone()))
    };
    let flexible_body = || -> Result<(BodyId, &BodyNodes), ModelFileError> {
        let name = reference(&o.body, "body")?;
        let key = element.key("body");
        let id = references.bodies.resolve(name, &key, ctx.source)?;
        let nodes = references.flexible.get(id).ok_or_else(|| {
            ctx.invalid(
                &name.span(),
                &key,
                format!(
                    "`{}` is a rigid body; {description} reads a flexible body ([[flexible_body]])",
                    name.get_ref()
                ),
            )
        })?;
        Ok((id, nodes))
    };
    let node = || -> Result<(BodyId, usize, String), ModelFileError> {
        let (id, nodes) = flexible_body()?;
        let node = o.node.as_ref().ok_or_else(|| {
            ctx.source.error(
                ErrorKind::Schema,
                element_span,
                &element.key("node"),
                format!("missing required key `node` for {description}: a node label, or a position [x, y, z]"),
            )
        })?;
        let node = resolve_node(ctx, nodes, node, &element.key("node"))?;
        Ok((id, node.index, format!("{}.node{}", nodes.body, node.label)))
    };
    Ok(match output_type {
        OutputType::ModalCoordinates => {
            let (id, nodes) = flexible_body()?;
            (OutputKind::ModalCoordinates(id), format!("{}.modal_coordinates", nodes.body))
        }
        OutputType::StrainEnergy => {
            let (id, nodes) = flexible_body()?;
            (OutputKind::StrainEnergy(id), format!("{}.strain_energy", nodes.body))
        }
        OutputType::NodePosition => {
            let (id, index, base) = node()?;
            (OutputKind::NodePosition(id, index), format!("{base}.position"))
        }
        OutputType::NodeVelocity => {
            let (id, index, base) = node()?;
            (OutputKind::NodeVelocity(id, index), format!("{base}.velocity"))
        }
        OutputType::NodeAcceleration => {
            let (id, index, base) = node()?;
            (OutputKind::NodeAcceleration(id, index), format!("{base}.acceleration"))
        }
        OutputType::NodeDeformation => {
            let (id, index, base) = node()?;
            (OutputKind::NodeDeformation(id, index), format!("{base}.deformation"))
        }
        OutputType::MarkerPosition => {
            let (m, name) = marker()?;
            (OutputKind::MarkerPosition(m), format!("{name}.position"))
        }
        OutputType::MarkerVelocity => {
            let (m, name) = marker()?;
            (OutputKind::MarkerVelocity(m), format!("{name}.velocity"))
        }
        OutputType::MarkerAcceleration => {
            let (m, name) = marker()?;
            (OutputKind::MarkerAcceleration(m), format!("{name}.acceleration"))
        }
        OutputType::MarkerAngularVelocity => {
            let (m, name) = marker()?;
            (OutputKind::MarkerAngularVelocity(m), format!("{name}.angular_velocity"))
        }
        OutputType::JointReaction => {
            let name = reference(&o.joint, "joint")?;
            let id = references.joints.resolve(name, &element.key("joint"), ctx.source)?;
            (OutputKind::JointReaction(id), format!("{}.reaction", name.get_ref()))
        }
        OutputType::Measure => {
            let name = reference(&o.measure, "measure")?;
            let id = references.measures.resolve(name, &element.key("measure"), ctx.source)?;
            (OutputKind::Measure(id), name.get_ref().clone())
        }
        OutputType::Energy => (OutputKind::Energy, "energy".to_string()),
        OutputType::ConstraintResidual => (OutputKind::ConstraintResidual, "constraint_residual".to_string()),
    })
}
