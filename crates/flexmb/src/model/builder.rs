//! Assembles and validates a [`Model`].

use std::collections::HashSet;

use super::{
    BodyId, BodyRef, ForceId, JointId, Layout, MarkerId, MeasureId, Model, ModelError, OutputKind,
    OutputRequest, ParameterId,
};
use crate::body::{InitialState, Marker, ModalBody, RigidBody};
use crate::force::{ForceElement, ForceKind};
use crate::joint::Joint;
use crate::math::{euler_parameters::rotation_matrix_defect, Mat3, Vec3};
use crate::measure::{Measure, MeasureKind, Parameter};

/// Collects the elements of a model; [`build`](Self::build) validates them and derives the layout.
#[derive(Clone, Debug, Default)]
#[must_use]
pub struct ModelBuilder {
    name: String,
    gravity: Vec3,
    bodies: Vec<RigidBody>,
    modal: Vec<Option<ModalBody>>,
    markers: Vec<Marker>,
    marker_node: Vec<Option<usize>>,
    joints: Vec<Joint>,
    forces: Vec<ForceElement>,
    measures: Vec<Measure>,
    parameters: Vec<Parameter>,
    outputs: Vec<OutputRequest>,
}

impl ModelBuilder {
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Default::default() }
    }

    /// Gravitational acceleration, global (m/s²). Default zero.
    pub fn gravity(mut self, g: Vec3) -> Self {
        self.gravity = g;
        self
    }

    pub fn set_gravity(&mut self, g: Vec3) {
        self.gravity = g;
    }

    pub fn add_body(&mut self, body: RigidBody) -> BodyId {
        self.bodies.push(body);
        self.modal.push(None);
        BodyId(self.bodies.len() - 1)
    }

    /// Adds a flexible body. Its rigid properties (mass, centre of mass, inertia about it) are those
    /// of the undeformed FE model, from the invariants.
    pub fn add_flexible_body(&mut self, name: impl Into<String>, initial: InitialState, modal: ModalBody) -> BodyId {
        let inv = &modal.invariants;
        let mass = inv.mass;
        let com = if mass > 0.0 { inv.c1 / mass } else { Vec3::zeros() };
        let inertia = inv.undeformed_inertia() - mass * (Mat3::identity() * com.norm_squared() - com * com.transpose());
        self.bodies.push(RigidBody { name: name.into(), mass, center_of_mass: com, inertia, initial });
        self.modal.push(Some(modal));
        BodyId(self.bodies.len() - 1)
    }

    pub fn add_marker(&mut self, marker: Marker) -> MarkerId {
        self.markers.push(marker);
        self.marker_node.push(None);
        MarkerId(self.markers.len() - 1)
    }

    /// Adds a marker at node `node` (index into the body's nodes) of flexible body `body`, with `axes`
    /// in the body frame. It moves and turns with the node's elastic deformation.
    pub fn add_node_marker(&mut self, name: impl Into<String>, body: BodyId, node: usize, axes: Mat3) -> MarkerId {
        let origin = self.modal[body.0]
            .as_ref()
            .and_then(|m| m.nodes.get(node))
            .map_or(Vec3::zeros(), |n| n.position);
        self.markers.push(Marker { name: name.into(), body: BodyRef::Body(body), origin, axes });
        self.marker_node.push(Some(node));
        MarkerId(self.markers.len() - 1)
    }

    /// The modal description of a flexible body added so far.
    pub fn modal_body(&self, body: BodyId) -> Option<&ModalBody> {
        self.modal[body.0].as_ref()
    }

    pub fn add_joint(&mut self, joint: Joint) -> JointId {
        self.joints.push(joint);
        JointId(self.joints.len() - 1)
    }

    pub fn add_force(&mut self, force: ForceElement) -> ForceId {
        self.forces.push(force);
        ForceId(self.forces.len() - 1)
    }

    pub fn add_measure(&mut self, measure: Measure) -> MeasureId {
        self.measures.push(measure);
        MeasureId(self.measures.len() - 1)
    }

    /// Declares a parameter of initial value `value`, changeable between the steps of a simulation
    /// ([`Simulation::set_parameter`](crate::analysis::Simulation::set_parameter)), and a measure of the
    /// same name through which expressions (a force law's actuator, an applied load) read its current
    /// value.
    pub fn add_parameter(&mut self, name: impl Into<String>, value: f64) -> MeasureId {
        let name = name.into();
        self.parameters.push(Parameter { name: name.clone(), value });
        self.add_measure(Measure { name, kind: MeasureKind::Parameter(ParameterId(self.parameters.len() - 1)) })
    }

    pub fn add_output(&mut self, name: impl Into<String>, kind: OutputKind) {
        self.outputs.push(OutputRequest { name: name.into(), kind });
    }

    pub fn find_body(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name).map(BodyId)
    }
    pub fn find_marker(&self, name: &str) -> Option<MarkerId> {
        self.markers.iter().position(|m| m.name == name).map(MarkerId)
    }
    pub fn find_joint(&self, name: &str) -> Option<JointId> {
        self.joints.iter().position(|j| j.name == name).map(JointId)
    }
    pub fn find_measure(&self, name: &str) -> Option<MeasureId> {
        self.measures.iter().position(|m| m.name == name).map(MeasureId)
    }
    pub fn joint(&self, id: JointId) -> &Joint {
        &self.joints[id.0]
    }
    pub fn marker(&self, id: MarkerId) -> &Marker {
        &self.markers[id.0]
    }

    /// Global position of a marker origin in the initial configuration given for its body.
    pub fn initial_marker_position(&self, m: MarkerId) -> Vec3 {
        let marker = &self.markers[m.0];
        match marker.body {
            BodyRef::Ground => marker.origin,
            BodyRef::Body(b) => {
                let init = &self.bodies[b.0].initial;
                let mut origin = marker.origin;
                if let (Some(node), Some(modal)) = (self.marker_node[m.0], &self.modal[b.0]) {
                    if let Some(n) = modal.nodes.get(node) {
                        origin = n.position + &n.psi * &modal.initial_coordinates;
                    }
                }
                init.position + init.orientation.rotation_matrix() * origin
            }
        }
    }

    /// Distance between two markers in the initial configuration (the default length of a distance joint).
    pub fn initial_distance(&self, i: MarkerId, j: MarkerId) -> f64 {
        (self.initial_marker_position(j) - self.initial_marker_position(i)).norm()
    }

    /// Validates every element and returns the immutable model.
    pub fn build(self) -> Result<Model, ModelError> {
        unique_names("body", self.bodies.iter().map(|b| b.name.as_str()))?;
        unique_names("marker", self.markers.iter().map(|m| m.name.as_str()))?;
        unique_names("joint", self.joints.iter().map(|j| j.name.as_str()))?;
        unique_names("force", self.forces.iter().map(|f| f.name.as_str()))?;
        unique_names("measure", self.measures.iter().map(|m| m.name.as_str()))?;
        unique_names("output", self.outputs.iter().map(|o| o.name.as_str()))?;
        for (b, modal) in self.bodies.iter().zip(&self.modal) {
            match modal {
                None => check_body(b)?,
                Some(modal) => super::flexible_checks::check_flexible_body(b, modal)?,
            }
        }
        for (k, m) in self.markers.iter().enumerate() {
            super::flexible_checks::check_marker_node(m, self.marker_node[k], &self.modal)?;
            check_frame(&format!("marker '{}'", m.name), &m.axes)?;
            if !m.origin.iter().all(|x| x.is_finite()) {
                return Err(ModelError::BadFrame {
                    what: format!("marker '{}'", m.name),
                    problem: "origin is not finite".into(),
                });
            }
        }
        for j in &self.joints {
            let (bi, bj) = (self.markers[j.marker_i.0].body, self.markers[j.marker_j.0].body);
            if bi == bj {
                let body = match bi {
                    BodyRef::Ground => "ground".to_string(),
                    BodyRef::Body(b) => format!("body '{}'", self.bodies[b.0].name),
                };
                return Err(ModelError::JointOnOneBody { joint: j.name.clone(), body });
            }
        }
        for f in &self.forces {
            if let ForceKind::RotationalSpringDamper { joint, .. } = &f.kind {
                self.require_rotation("rotational spring-damper", &f.name, *joint)?;
            }
            if let ForceKind::TranslationalSpringDamper { stiffness, damping, free_length, .. } = &f.kind {
                for (what, x) in [("stiffness", stiffness), ("damping", damping), ("free_length", free_length)] {
                    if !x.is_finite() || *x < 0.0 {
                        return Err(ModelError::BadValue {
                            element: "force",
                            name: f.name.clone(),
                            problem: format!("{what} must be finite and not negative, got {x}"),
                        });
                    }
                }
            }
        }
        for m in &self.measures {
            match m.kind {
                MeasureKind::JointAngle(j) | MeasureKind::JointRate(j) => {
                    self.require_rotation("measure", &m.name, j)?
                }
                MeasureKind::JointDisplacement(j) | MeasureKind::JointVelocity(j) => {
                    let joint = &self.joints[j.0];
                    if !joint.kind.has_translation_along_z() {
                        return Err(ModelError::WrongJointKind {
                            element: "measure",
                            name: m.name.clone(),
                            joint: joint.name.clone(),
                            kind: joint.kind.keyword(),
                            motion: "a translation along z_i",
                        });
                    }
                }
                _ => {}
            }
        }
        let equations: Vec<_> = self.joints.iter().map(|j| j.kind.equations()).collect();
        let modes: Vec<usize> = self.modal.iter().map(|m| m.as_ref().map_or(0, ModalBody::modes)).collect();
        let layout = Layout::new(&modes, &equations);
        Ok(Model {
            name: self.name,
            gravity: self.gravity,
            bodies: self.bodies,
            modal: self.modal,
            markers: self.markers,
            marker_node: self.marker_node,
            joints: self.joints,
            forces: self.forces,
            measures: self.measures,
            parameters: self.parameters,
            outputs: self.outputs,
            layout,
        })
    }

    fn require_rotation(&self, element: &'static str, name: &str, joint: JointId) -> Result<(), ModelError> {
        let j = &self.joints[joint.0];
        if j.kind.has_rotation_about_z() {
            Ok(())
        } else {
            Err(ModelError::WrongJointKind {
                element,
                name: name.to_string(),
                joint: j.name.clone(),
                kind: j.kind.keyword(),
                motion: "a rotation about z_i",
            })
        }
    }
}

fn unique_names<'a>(kind: &'static str, names: impl Iterator<Item = &'a str>) -> Result<(), ModelError> {
    let mut seen = HashSet::new();
    for n in names {
        if !seen.insert(n) {
            return Err(ModelError::DuplicateName { kind, name: n.to_string() });
        }
    }
    Ok(())
}

pub(super) fn check_body(b: &RigidBody) -> Result<(), ModelError> {
    if !(b.mass.is_finite() && b.mass > 0.0) {
        return Err(ModelError::NonPositiveMass { body: b.name.clone(), mass: b.mass });
    }
    check_inertia(&b.inertia).map_err(|problem| ModelError::BadInertia { body: b.name.clone(), problem })?;
    check_frame(&format!("body '{}' initial orientation", b.name), &b.initial.orientation.rotation_matrix())?;
    let finite = |v: &Vec3| v.iter().all(|x| x.is_finite());
    let vel_ok = b.initial.velocity.as_ref().is_none_or(finite)
        && b.initial.angular_velocity.as_ref().is_none_or(finite);
    if !finite(&b.initial.position) || !finite(&b.center_of_mass) || !vel_ok {
        return Err(ModelError::BadValue {
            element: "body",
            name: b.name.clone(),
            problem: "position, centre of mass and velocities must be finite".into(),
        });
    }
    Ok(())
}

/// A physical inertia tensor: symmetric, positive definite, principal moments obeying the triangle
/// inequality `I₁ + I₂ ≥ I₃`.
pub(crate) fn check_inertia(j: &Mat3) -> Result<(), String> {
    if !j.iter().all(|x| x.is_finite()) {
        return Err("has a value that is not finite".into());
    }
    let scale = j.abs().max().max(f64::MIN_POSITIVE);
    if (j - j.transpose()).abs().max() > 1e-9 * scale {
        return Err(format!("is not symmetric: {j}"));
    }
    let eig = j.symmetric_eigenvalues();
    let mut m = [eig[0], eig[1], eig[2]];
    m.sort_by(f64::total_cmp);
    if m[0] <= 0.0 {
        return Err(format!("must be positive definite; principal moments are {:.6e}, {:.6e}, {:.6e}", m[0], m[1], m[2]));
    }
    if m[0] + m[1] < m[2] * (1.0 - 1e-9) {
        return Err(format!(
            "principal moments {:.6e}, {:.6e}, {:.6e} violate the triangle inequality I1 + I2 >= I3",
            m[0], m[1], m[2]
        ));
    }
    Ok(())
}

pub(super) fn check_frame(what: &str, a: &Mat3) -> Result<(), ModelError> {
    let defect = rotation_matrix_defect(a);
    if defect.is_nan() || defect >= 1e-6 {
        return Err(ModelError::BadFrame {
            what: what.to_string(),
            problem: format!("axes are not a proper orthonormal frame (defect {defect:.2e})"),
        });
    }
    Ok(())
}
