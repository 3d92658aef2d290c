//! The model file as TOML: one struct per table, every value that is checked after parsing kept with
//! its span so that errors can name its line. See `docs/model-file.md` for the meaning of each key.

use std::collections::BTreeMap;
use std::ops::Range;

use serde::Deserialize;
use toml::Spanned;

use super::value::{InertiaInput, NumberOrExpression};
use crate::fe_model_file::node_ref::NodeRef;

/// A number or an expression, with its span.
pub(crate) type Number = Spanned<NumberOrExpression>;
/// An array of numbers or expressions, with its span; most are 3-vectors.
pub(crate) type Vector = Spanned<Vec<Number>>;
/// A name or keyword, with its span.
pub(crate) type Name = Spanned<String>;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ModelFile {
    pub model: Option<Spanned<ModelSection>>,
    pub simulation: Option<Spanned<SimulationSection>>,
    #[serde(default)]
    pub parameters: BTreeMap<Name, Number>,
    #[serde(default)]
    pub body: Vec<Spanned<BodySection>>,
    #[serde(default)]
    pub flexible_body: Vec<Spanned<FlexibleBodySection>>,
    #[serde(default)]
    pub marker: Vec<Spanned<MarkerSection>>,
    #[serde(default)]
    pub joint: Vec<Spanned<JointSection>>,
    #[serde(default)]
    pub driver: Vec<Spanned<DriverSection>>,
    #[serde(default)]
    pub measure: Vec<Spanned<MeasureSection>>,
    #[serde(default)]
    pub force: Vec<Spanned<ForceSection>>,
    #[serde(default)]
    pub output: Vec<Spanned<OutputSection>>,
}

/// `[model]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ModelSection {
    pub name: Option<Name>,
    pub gravity: Option<Vector>,
}

/// `[simulation]`: defaults for a simulation run.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SimulationSection {
    pub t_end: Option<Number>,
    pub output_step: Option<Number>,
    pub rtol: Option<Number>,
    pub atol: Option<Number>,
    pub tolerance_span: Option<Number>,
    pub modal_assembly: Option<Name>,
    pub start: Option<Name>,
    pub integrator: Option<Name>,
    pub spectral_radius: Option<Number>,
    pub max_order: Option<Number>,
    pub max_step: Option<Number>,
    pub fixed_step: Option<Number>,
    pub vtk_step: Option<Number>,
    pub max_output_rows: Option<Number>,
    pub max_vtk_frames: Option<Number>,
    pub elastic_deflection_warning: Option<Number>,
    pub elastic_deflection_limit: Option<Number>,
    pub energy_balance_warning: Option<Number>,
    pub energy_balance_limit: Option<Number>,
    pub divergence_check: Option<bool>,
    pub global_error_estimate: Option<bool>,
    pub global_error_control: Option<bool>,
}

/// `[[body]]`: a rigid body.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BodySection {
    pub name: Name,
    pub mass: Number,
    pub inertia: Spanned<InertiaInput>,
    pub center_of_mass: Option<Vector>,
    pub position: Option<Vector>,
    pub orientation: Option<Spanned<OrientationSection>>,
    pub velocity: Option<Vector>,
    pub angular_velocity: Option<Vector>,
    pub shape: Option<Spanned<ShapeSection>>,
}

/// A rigid body's `shape`, drawn by the ParaView output: one of `box`, `cylinder`, `sphere`, `mesh`,
/// `frame`, placed in the body frame by `origin` and `orientation` (like a marker).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ShapeSection {
    #[serde(rename = "box")]
    pub cuboid: Option<Vector>,
    pub cylinder: Option<Spanned<CylinderSection>>,
    pub sphere: Option<Number>,
    pub mesh: Option<Name>,
    pub frame: Option<Number>,
    pub scale: Option<Number>,
    pub origin: Option<Vector>,
    pub orientation: Option<Spanned<OrientationSection>>,
}

/// `cylinder = { radius = r, length = l, axis = "z" }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CylinderSection {
    pub radius: Number,
    pub length: Number,
    pub axis: Option<Name>,
}

/// `[[flexible_body]]`: a flexible body reduced from an FE model file, or read from a flexible-body
/// file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FlexibleBodySection {
    pub name: Name,
    pub fe_model: Option<Name>,
    pub body_file: Option<Name>,
    pub modes: Option<Name>,
    pub basis: Option<Name>,
    pub damping: Option<Spanned<DampingSection>>,
    pub high_mode_damping: Option<Spanned<HighModeDampingSection>>,
    pub geometric_stiffening: Option<bool>,
    pub stresses: Option<Spanned<bool>>,
    pub position: Option<Vector>,
    pub orientation: Option<Spanned<OrientationSection>>,
    pub velocity: Option<Vector>,
    pub angular_velocity: Option<Vector>,
    pub modal_coordinates: Option<Vector>,
    pub modal_rates: Option<Vector>,
}

/// The modal damping of a flexible body: one ratio for all modes, one per mode, or Rayleigh's.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct DampingSection {
    pub ratio: Option<Number>,
    pub ratios: Option<Vector>,
    pub rayleigh: Option<Vector>,
}

/// `high_mode_damping = { above = f, ratio = ζ }`: damping ratio ζ on the natural modes above f Hz.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct HighModeDampingSection {
    pub above: Number,
    pub ratio: Option<Number>,
}

/// An orientation: axis and angle, a rotation matrix, or Euler parameters.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct OrientationSection {
    pub axis: Option<Vector>,
    pub angle: Option<Number>,
    pub angle_deg: Option<Number>,
    pub matrix: Option<Spanned<Vec<Vector>>>,
    pub euler_parameters: Option<Vector>,
}

/// `[[marker]]`: a frame fixed on a body or on ground.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MarkerSection {
    pub name: Name,
    pub body: Name,
    pub node: Option<Spanned<NodeRef>>,
    pub origin: Option<Vector>,
    pub orientation: Option<Spanned<OrientationSection>>,
    pub z_axis: Option<Vector>,
    pub x_axis: Option<Vector>,
}

/// `[[joint]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct JointSection {
    pub name: Name,
    #[serde(rename = "type")]
    pub kind: Name,
    pub i: Name,
    pub j: Name,
    pub length: Option<Number>,
    pub axis_i: Option<Name>,
    pub axis_j: Option<Name>,
}

/// `[[driver]]`: a prescribed motion of an existing joint.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct DriverSection {
    pub name: Name,
    pub joint: Name,
    #[serde(rename = "type")]
    pub kind: Option<Name>,
    pub function: Number,
}

/// `[[measure]]`: a named scalar that expressions and outputs read.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MeasureSection {
    pub name: Name,
    #[serde(rename = "type")]
    pub kind: Name,
    pub joint: Option<Name>,
    pub i: Option<Name>,
    pub j: Option<Name>,
    pub marker: Option<Name>,
    pub component: Option<Name>,
}

/// `[[force]]`: a spring-damper-actuator or an applied force or torque.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ForceSection {
    pub name: Name,
    #[serde(rename = "type")]
    pub kind: Name,
    pub joint: Option<Name>,
    pub i: Option<Name>,
    pub j: Option<Name>,
    pub marker: Option<Name>,
    pub stiffness: Option<Number>,
    pub damping: Option<Number>,
    pub free_angle: Option<Number>,
    pub free_length: Option<Number>,
    pub actuator: Option<Number>,
    pub frame: Option<Name>,
    pub components: Option<Vector>,
}

/// `[[output]]`: one requested output.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct OutputSection {
    pub name: Option<Name>,
    #[serde(rename = "type")]
    pub kind: Name,
    pub marker: Option<Name>,
    pub joint: Option<Name>,
    pub measure: Option<Name>,
    pub body: Option<Name>,
    pub node: Option<Spanned<NodeRef>>,
    pub sequence: Option<Name>,
    pub axes: Option<Name>,
    pub frame: Option<Name>,
    pub expression: Option<Name>,
    pub unit: Option<Name>,
}

/// The span of an optional value, if present.
pub(crate) fn span_of<T>(value: &Option<Spanned<T>>) -> Option<Range<usize>> {
    value.as_ref().map(Spanned::span)
}

impl MeasureSection {
    /// The optional keys present, for rejecting those a measure type does not use.
    pub(crate) fn optional_keys(&self) -> [(&'static str, Option<Range<usize>>); 5] {
        [
            ("joint", span_of(&self.joint)),
            ("i", span_of(&self.i)),
            ("j", span_of(&self.j)),
            ("marker", span_of(&self.marker)),
            ("component", span_of(&self.component)),
        ]
    }
}

impl ForceSection {
    /// The optional keys present, for rejecting those a force type does not use.
    pub(crate) fn optional_keys(&self) -> [(&'static str, Option<Range<usize>>); 11] {
        [
            ("joint", span_of(&self.joint)),
            ("i", span_of(&self.i)),
            ("j", span_of(&self.j)),
            ("marker", span_of(&self.marker)),
            ("stiffness", span_of(&self.stiffness)),
            ("damping", span_of(&self.damping)),
            ("free_angle", span_of(&self.free_angle)),
            ("free_length", span_of(&self.free_length)),
            ("actuator", span_of(&self.actuator)),
            ("frame", span_of(&self.frame)),
            ("components", span_of(&self.components)),
        ]
    }
}

impl OutputSection {
    /// The optional element keys present, for rejecting those an output type does not use.
    pub(crate) fn optional_keys(&self) -> [(&'static str, Option<Range<usize>>); 10] {
        [
            ("marker", span_of(&self.marker)),
            ("joint", span_of(&self.joint)),
            ("measure", span_of(&self.measure)),
            ("body", span_of(&self.body)),
            ("node", span_of(&self.node)),
            ("sequence", span_of(&self.sequence)),
            ("axes", span_of(&self.axes)),
            ("frame", span_of(&self.frame)),
            ("expression", span_of(&self.expression)),
            ("unit", span_of(&self.unit)),
        ]
    }
}

impl JointSection {
    /// The optional keys present, for rejecting those a joint type does not use.
    pub(crate) fn optional_keys(&self) -> [(&'static str, Option<Range<usize>>); 3] {
        [("length", span_of(&self.length)), ("axis_i", span_of(&self.axis_i)), ("axis_j", span_of(&self.axis_j))]
    }
}
