//! The immutable model: bodies, markers, joints, forces, measures and output requests, with the
//! coordinate layout derived from them. Build one with [`ModelBuilder`].

mod builder;
#[cfg(test)]
mod builder_tests;
mod coordinate_names;
mod coupling;
mod error;
mod flexible_checks;
mod ids;
mod layout;
mod output;
mod references;
mod rigid_checks;
mod size_mismatch;
mod user_laws;

pub use builder::ModelBuilder;
pub(crate) use coupling::{bodies_under_force_elements, Coupling};
pub use error::ModelError;
pub use ids::{BodyId, BodyRef, ForceId, JointId, MarkerId, MeasureId, ParameterId};
pub use layout::Layout;
pub use output::{JointCoordinateSet, OrientationForm, OutputAxes, OutputKind, RotatingFrame, UserOutput};
pub use size_mismatch::SizeMismatch;
pub use user_laws::UserLawError;
pub(crate) use size_mismatch::SizeCheck;

use crate::body::{Marker, ModalBody, RigidBody};
use crate::force::ForceElement;
use crate::joint::Joint;
use crate::math::Vec3;
use crate::measure::{Measure, Parameter};

/// A named output request.
#[derive(Clone, Debug)]
pub struct OutputRequest {
    /// The name, the prefix of its columns.
    pub name: String,
    /// What it reports.
    pub kind: OutputKind,
}

/// A mechanism, ready to analyse. Immutable: all scratch state lives in [`Data`](crate::Data).
#[derive(Clone, Debug)]
pub struct Model {
    pub(crate) name: String,
    pub(crate) gravity: Vec3,
    /// Every body's rigid properties and initial state; for a flexible body, those of its undeformed
    /// FE model.
    pub(crate) bodies: Vec<RigidBody>,
    /// The modal description of each flexible body (`None` for a rigid body), by body index.
    pub(crate) modal: Vec<Option<ModalBody>>,
    pub(crate) markers: Vec<Marker>,
    /// The node a marker of a flexible body sits at (`None` for markers on rigid bodies and ground).
    pub(crate) marker_node: Vec<Option<usize>>,
    pub(crate) joints: Vec<Joint>,
    pub(crate) forces: Vec<ForceElement>,
    pub(crate) measures: Vec<Measure>,
    /// The parameters, with their initial values (their current values live in [`Data`](crate::Data)).
    pub(crate) parameters: Vec<Parameter>,
    pub(crate) outputs: Vec<OutputRequest>,
    /// The expressions of the [`OutputKind::UserExpression`] outputs.
    pub(crate) output_expressions: Vec<UserOutput>,
    pub(crate) layout: Layout,
    /// The gauge inertia of each body in its angular-velocity block (body frame; zero but for a flexible
    /// body whose massless spin no joint holds: [`massless_gauges`](crate::analysis::massless_gauges)).
    pub(crate) massless_gauges: Vec<crate::math::Mat3>,
}

impl Model {
    /// The model's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Gravitational acceleration, global (m/s²).
    pub fn gravity(&self) -> Vec3 {
        self.gravity
    }
    /// Every body, rigid or flexible, in the order added; a [`BodyId`] indexes it.
    pub fn bodies(&self) -> &[RigidBody] {
        &self.bodies
    }
    /// Every marker; a [`MarkerId`] indexes it.
    pub fn markers(&self) -> &[Marker] {
        &self.markers
    }
    /// Every joint and driver; a [`JointId`] indexes it.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }
    /// Every force element; a [`ForceId`] indexes it.
    pub fn forces(&self) -> &[ForceElement] {
        &self.forces
    }
    /// Every measure; a [`MeasureId`] indexes it.
    pub fn measures(&self) -> &[Measure] {
        &self.measures
    }
    /// The parameters that may be changed between the steps of a simulation, with their initial values.
    pub fn parameters(&self) -> &[Parameter] {
        &self.parameters
    }
    /// The parameter named `name`.
    pub fn find_parameter(&self, name: &str) -> Option<ParameterId> {
        self.parameters.iter().position(|p| p.name == name).map(ParameterId)
    }
    /// The output requests, in the order of their columns.
    pub fn outputs(&self) -> &[OutputRequest] {
        &self.outputs
    }
    /// The expressions of the user outputs ([`OutputKind::UserExpression`]).
    pub fn output_expressions(&self) -> &[UserOutput] {
        &self.output_expressions
    }
    /// Where each body's coordinates and each joint's equations sit in the global vectors.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
    /// A body of this model; `None` for an id that is not one of its bodies (an id from another builder).
    pub fn body(&self, id: BodyId) -> Option<&RigidBody> {
        self.bodies.get(id.0)
    }
    /// The modal description of a flexible body; `None` for a rigid body or an id that is not one of this
    /// model's bodies.
    pub fn modal_body(&self, id: BodyId) -> Option<&ModalBody> {
        self.modal.get(id.0).and_then(Option::as_ref)
    }
    /// The node of a flexible body a marker sits at; `None` for a marker on a rigid body or ground, or an
    /// id that is not one of this model's markers.
    pub fn marker_node(&self, id: MarkerId) -> Option<usize> {
        self.marker_node.get(id.0).copied().flatten()
    }
    /// A marker of this model; `None` for an id that is not one of its markers.
    pub fn marker(&self, id: MarkerId) -> Option<&Marker> {
        self.markers.get(id.0)
    }
    /// A joint or driver of this model; `None` for an id that is not one of its joints.
    pub fn joint(&self, id: JointId) -> Option<&Joint> {
        self.joints.get(id.0)
    }

    /// Name of a body reference (`ground` for ground); `None` for a body that is not one of this model's.
    pub fn body_name(&self, b: BodyRef) -> Option<&str> {
        match b {
            BodyRef::Ground => Some("ground"),
            BodyRef::Body(id) => self.bodies.get(id.0).map(|body| body.name.as_str()),
        }
    }

    /// The bodies a joint connects (0, 1 or 2 moving bodies).
    pub(crate) fn joint_bodies(&self, j: &Joint) -> [Option<BodyId>; 2] {
        [self.markers[j.marker_i.0].body.body(), self.markers[j.marker_j.0].body.body()]
    }

    /// A human-readable description of the equation of velocity coordinate `k`: the equations of motion of
    /// a body, or the modal equation of one of its modes (for `k` beyond [`Layout::nv`], says so).
    pub fn describe_velocity_row(&self, k: usize) -> String {
        if k >= self.layout.nv {
            return format!("velocity coordinate {k}, which this model does not have (it has {})", self.layout.nv);
        }
        let b = BodyId(self.layout.velocity_body(k));
        let local = k - self.layout.v_offset[b.0];
        let name = &self.bodies[b.0].name;
        match (&self.modal[b.0], local.checked_sub(6)) {
            (Some(m), Some(mode)) => format!("the modal equation of mode {} of body '{name}'", m.mode_labels[mode]),
            _ => format!("the equations of motion of body '{name}'"),
        }
    }

    /// A human-readable description of constraint row `row`: joint name, kind and equation (for `row`
    /// beyond [`Layout::nc`], says so).
    pub fn describe_constraint_row(&self, row: usize) -> String {
        if row >= self.layout.nc {
            return format!("constraint row {row}, which this model does not have (it has {})", self.layout.nc);
        }
        let (joint, eq) = self.layout.equations[row];
        let j = &self.joints[joint.0];
        let k = row - self.layout.joint_rows[joint.0].start;
        format!("joint '{}' ({}), equation {}: {}", j.name, j.kind.keyword(), k + 1, eq.label())
    }
}
