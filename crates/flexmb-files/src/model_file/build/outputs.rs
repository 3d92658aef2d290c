//! `[[output]]` → output requests. An output without a name is named after its element and type, e.g.
//! `crank_pin.position`, `pivot.reaction`, `energy`, `beam.modal_coordinates`, `beam.node21.position`.

use flexmb::math::EulerSequence;
use flexmb::model::{
    BodyId, JointCoordinateSet, JointId, MarkerId, MeasureId, OrientationForm, OutputAxes, OutputKind, RotatingFrame,
};
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
    EulerParameters,
    RotationMatrix,
    EulerAngles,
    AngularVelocity,
    AngularAcceleration,
    JointMultipliers,
    JointCoordinates,
    KineticEnergy,
    LinearMomentum,
    AngularMomentum,
    SystemMomentum,
    EulerParameterNormError,
    Expression,
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
    ("euler_parameters", OutputType::EulerParameters),
    ("rotation_matrix", OutputType::RotationMatrix),
    ("euler_angles", OutputType::EulerAngles),
    ("angular_velocity", OutputType::AngularVelocity),
    ("angular_acceleration", OutputType::AngularAcceleration),
    ("joint_multipliers", OutputType::JointMultipliers),
    ("joint_coordinates", OutputType::JointCoordinates),
    ("kinetic_energy", OutputType::KineticEnergy),
    ("linear_momentum", OutputType::LinearMomentum),
    ("angular_momentum", OutputType::AngularMomentum),
    ("system_momentum", OutputType::SystemMomentum),
    ("euler_parameter_norm_error", OutputType::EulerParameterNormError),
    ("expression", OutputType::Expression),
];

/// The sequence of `euler_angles` when the output gives none (the z-x-z sequence of Haug's text).
const DEFAULT_SEQUENCE: &str = "313";

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
        if ctx.keyword(&o.kind, &element.key("type"), "output type", OUTPUT_TYPES)? == OutputType::Expression {
            add_expression_output(ctx, o, builder, names, &element, &section.span(), index)?;
            continue;
        }
        let (kind, default_name) = output_kind(ctx, o, references, builder, &element, &section.span())?;
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

/// A user output: `expression` of `t`, parameters, measures and the columns of the outputs before it,
/// written in `unit` (`-` if not given); its `name` is required.
fn add_expression_output(
    ctx: &Context,
    o: &OutputSection,
    builder: &mut ModelBuilder,
    names: &mut NameTable<usize>,
    element: &KeyPath,
    element_span: &std::ops::Range<usize>,
    index: usize,
) -> Result<(), ModelFileError> {
    let description = "an expression output";
    ctx.reject_unused_keys(element, description, &o.optional_keys(), &["expression", "unit"])?;
    let name = o.name.as_ref().ok_or_else(|| {
        ctx.source.error(
            ErrorKind::Schema,
            element_span,
            &element.key("name"),
            "missing required key `name` for an expression output: the name of its column".to_string(),
        )
    })?;
    let text = ctx.required(&o.expression, element, element_span, "expression", description)?;
    let columns: Vec<String> = builder.output_columns().into_iter().map(|c| c.name).collect();
    let expression = ctx.output_expression(text, &element.key("expression"), &columns)?;
    let unit = o.unit.as_ref().map_or("-".to_string(), |u| u.get_ref().clone());
    names.check_new(name, element, ctx.source)?;
    builder
        .add_output_expression(name.get_ref().clone(), expression, unit)
        .map_err(engine_errors::at(ctx.source, &name.span(), element))?;
    names.define(name, element, index);
    Ok(())
}

/// The request and its default name.
fn output_kind<'a>(
    ctx: &Context,
    o: &'a OutputSection,
    references: &OutputReferences,
    builder: &ModelBuilder,
    element: &KeyPath,
    element_span: &std::ops::Range<usize>,
) -> Result<(OutputKind, String), ModelFileError> {
    let output_type = ctx.keyword(&o.kind, &element.key("type"), "output type", OUTPUT_TYPES)?;
    let description = format!("a {} output", o.kind.get_ref());
    let used: &[&str] = match output_type {
        OutputType::MarkerPosition | OutputType::MarkerVelocity | OutputType::MarkerAcceleration => &["marker"],
        OutputType::MarkerAngularVelocity => &["marker", "axes", "frame"],
        OutputType::JointReaction => &["joint", "frame"],
        OutputType::JointMultipliers | OutputType::JointCoordinates => &["joint"],
        OutputType::Measure => &["measure"],
        OutputType::Energy | OutputType::ConstraintResidual | OutputType::SystemMomentum => &[],
        OutputType::ModalCoordinates | OutputType::StrainEnergy => &["body"],
        OutputType::KineticEnergy
        | OutputType::LinearMomentum
        | OutputType::AngularMomentum
        | OutputType::EulerParameterNormError => &["body"],
        OutputType::EulerParameters | OutputType::RotationMatrix => &["body", "marker"],
        OutputType::EulerAngles => &["body", "marker", "sequence"],
        OutputType::AngularVelocity | OutputType::AngularAcceleration => &["body", "marker", "axes", "frame"],
        OutputType::Expression => &["expression", "unit"],
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
    let any_body = || -> Result<(BodyId, String), ModelFileError> {
        let name = reference(&o.body, "body")?;
        Ok((references.bodies.resolve(name, &element.key("body"), ctx.source)?, name.get_ref().clone()))
    };
    // The body or marker whose rotation an output reads: exactly one of the two keys.
    let rotating_frame = || -> Result<(RotatingFrame, String), ModelFileError> {
        match (&o.body, &o.marker) {
            (Some(_), None) => any_body().map(|(b, name)| (RotatingFrame::Body(b), name)),
            (None, Some(_)) => marker().map(|(m, name)| (RotatingFrame::Marker(m), name)),
            (Some(body), Some(_)) => Err(ctx.invalid(
                &body.span(),
                &element.key("body"),
                format!("{description} reads a body or a marker, not both: give `body` or `marker`"),
            )),
            (None, None) => Err(ctx.source.error(
                ErrorKind::Schema,
                element_span,
                &element.key("body"),
                format!("missing required key `body` or `marker` for {description}"),
            )),
        }
    };
    // The axes of a vector: `axes = "global" | "body"` or `frame = "<marker>"`, with the suffix of the
    // default name.
    let output_axes = || -> Result<(OutputAxes, String), ModelFileError> {
        match (&o.axes, &o.frame) {
            (Some(axes), Some(_)) => Err(ctx.invalid(
                &axes.span(),
                &element.key("axes"),
                "give `axes` (\"global\" or \"body\") or `frame` (a marker whose axes resolve the vector), not both",
            )),
            (Some(axes), None) => {
                let choices = [("global", OutputAxes::Global), ("body", OutputAxes::Body)];
                let chosen = ctx.keyword(axes, &element.key("axes"), "axes", &choices)?;
                Ok((chosen, if chosen == OutputAxes::Body { "_body".to_string() } else { String::new() }))
            }
            (None, Some(frame)) => {
                let m = references.markers.resolve(frame, &element.key("frame"), ctx.source)?;
                Ok((OutputAxes::Marker(m), format!("_in_{}", frame.get_ref())))
            }
            (None, None) => Ok((OutputAxes::Global, String::new())),
        }
    };
    let joint = || -> Result<(JointId, String), ModelFileError> {
        let name = reference(&o.joint, "joint")?;
        Ok((references.joints.resolve(name, &element.key("joint"), ctx.source)?, name.get_ref().clone()))
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
            match output_axes()? {
                (OutputAxes::Global, _) => (OutputKind::MarkerAngularVelocity(m), format!("{name}.angular_velocity")),
                (axes, suffix) => {
                    (OutputKind::AngularVelocity(RotatingFrame::Marker(m), axes), format!("{name}.angular_velocity{suffix}"))
                }
            }
        }
        OutputType::JointReaction => {
            let (id, name) = joint()?;
            match &o.frame {
                None => (OutputKind::JointReaction(id), format!("{name}.reaction")),
                Some(frame) => {
                    let m = references.markers.resolve(frame, &element.key("frame"), ctx.source)?;
                    (OutputKind::JointReactionIn(id, m), format!("{name}.reaction_in_{}", frame.get_ref()))
                }
            }
        }
        OutputType::JointMultipliers => {
            let (id, name) = joint()?;
            (OutputKind::JointMultipliers(id), format!("{name}.multipliers"))
        }
        OutputType::JointCoordinates => {
            let (id, name) = joint()?;
            let kind = &builder.joint(id).expect("a joint the builder handed out").kind;
            let set = match (kind.has_rotation_about_z(), kind.has_translation_along_z()) {
                (true, true) => JointCoordinateSet::AngleAndDisplacement,
                (true, false) => JointCoordinateSet::Angle,
                (false, true) => JointCoordinateSet::Displacement,
                (false, false) => JointCoordinateSet::RelativeRotation,
            };
            (OutputKind::JointCoordinates(id, set), format!("{name}.coordinates"))
        }
        OutputType::EulerParameters => {
            let (frame, name) = rotating_frame()?;
            (OutputKind::Orientation(frame, OrientationForm::EulerParameters), format!("{name}.euler_parameters"))
        }
        OutputType::RotationMatrix => {
            let (frame, name) = rotating_frame()?;
            (OutputKind::Orientation(frame, OrientationForm::RotationMatrix), format!("{name}.rotation_matrix"))
        }
        OutputType::EulerAngles => {
            let (frame, name) = rotating_frame()?;
            let sequence = match &o.sequence {
                None => EulerSequence::parse(DEFAULT_SEQUENCE).expect("a valid sequence"),
                Some(text) => EulerSequence::parse(text.get_ref()).ok_or_else(|| {
                    ctx.invalid(
                        &text.span(),
                        &element.key("sequence"),
                        format!(
                            "`{}` is not a sequence of rotation axes: give three of the digits 1, 2, 3 (x, y, z) \
                             with no two neighbours equal, e.g. \"313\", \"123\" or \"321\"",
                            text.get_ref()
                        ),
                    )
                })?,
            };
            (OutputKind::Orientation(frame, OrientationForm::Angles(sequence)), format!("{name}.angles_{}", sequence.digits()))
        }
        OutputType::AngularVelocity => {
            let (frame, name) = rotating_frame()?;
            let (axes, suffix) = output_axes()?;
            (OutputKind::AngularVelocity(frame, axes), format!("{name}.angular_velocity{suffix}"))
        }
        OutputType::AngularAcceleration => {
            let (frame, name) = rotating_frame()?;
            let (axes, suffix) = output_axes()?;
            (OutputKind::AngularAcceleration(frame, axes), format!("{name}.angular_acceleration{suffix}"))
        }
        OutputType::KineticEnergy => {
            let (b, name) = any_body()?;
            (OutputKind::KineticEnergy(b), format!("{name}.kinetic_energy"))
        }
        OutputType::LinearMomentum => {
            let (b, name) = any_body()?;
            (OutputKind::LinearMomentum(b), format!("{name}.linear_momentum"))
        }
        OutputType::AngularMomentum => {
            let (b, name) = any_body()?;
            (OutputKind::AngularMomentum(b), format!("{name}.angular_momentum"))
        }
        OutputType::SystemMomentum => (OutputKind::SystemMomentum, "momentum".to_string()),
        OutputType::EulerParameterNormError => match &o.body {
            None => (OutputKind::EulerParameterNormError(None), "euler_parameter_norm_error".to_string()),
            Some(_) => {
                let (b, name) = any_body()?;
                (OutputKind::EulerParameterNormError(Some(b)), format!("{name}.euler_parameter_norm_error"))
            }
        },
        OutputType::Expression => unreachable!("expression outputs are added by `add_expression_output`"),
        OutputType::Measure => {
            let name = reference(&o.measure, "measure")?;
            let id = references.measures.resolve(name, &element.key("measure"), ctx.source)?;
            (OutputKind::Measure(id), name.get_ref().clone())
        }
        OutputType::Energy => (OutputKind::Energy, "energy".to_string()),
        OutputType::ConstraintResidual => (OutputKind::ConstraintResidual, "constraint_residual".to_string()),
    })
}
