//! Assembles a [`Model`], checking each element as it is added.

use std::collections::HashSet;

use super::flexible_checks::{check_flexible_body, check_marker_node};
use super::references::{self, Counts, Reference};
use super::rigid_checks::{check_body, check_frame};
use super::{
    BodyId, BodyRef, ForceId, JointId, Layout, MarkerId, MeasureId, Model, ModelError, OutputKind,
    OutputRequest, ParameterId, UserOutput,
};
use crate::body::{InitialState, Marker, ModalBody, RigidBody};
use crate::force::{ForceElement, ForceKind};
use crate::joint::Joint;
use crate::math::{Mat3, Vec3};
use crate::measure::{Measure, MeasureKind, Parameter};

/// Collects the elements of a model, checking each as it is added; [`build`](Self::build) derives
/// the coordinate layout and returns the immutable [`Model`].
///
/// Every `add_*` method returns an error at once for a bad element: a name used twice, an id this
/// builder did not hand out, a value out of its range (mass, inertia, frame, stiffness, …). A model
/// written in code thus fails at the line that adds the faulty element, and a builder only ever holds
/// valid elements.
///
/// A pendulum: a 1 kg body on a revolute joint to ground about the global y axis, under gravity.
///
/// ```
/// use flexmb::body::{InitialState, Marker, RigidBody};
/// use flexmb::joint::{Joint, JointKind};
/// use flexmb::math::{Mat3, Vec3};
/// use flexmb::model::BodyRef;
/// use flexmb::ModelBuilder;
///
/// # fn main() -> Result<(), flexmb::model::ModelError> {
/// let mut builder = ModelBuilder::new("pendulum").gravity(Vec3::new(0.0, 0.0, -9.81));
/// let bob = builder.add_body(RigidBody {
///     name: "bob".into(),
///     mass: 1.0,
///     center_of_mass: Vec3::zeros(),
///     inertia: Mat3::identity() * 1e-3,
///     initial: InitialState { position: Vec3::new(1.0, 0.0, 0.0), ..Default::default() },
/// })?;
/// // The hinge axis is the markers' z axis: turn z onto the global y axis.
/// let axes = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
/// let pivot = builder.add_marker(Marker { name: "pivot".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes })?;
/// let end = builder.add_marker(Marker {
///     name: "rod end".into(),
///     body: BodyRef::Body(bob),
///     origin: Vec3::new(-1.0, 0.0, 0.0),
///     axes,
/// })?;
/// builder.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: pivot, marker_j: end })?;
/// let model = builder.build()?;
/// assert_eq!(model.layout().nq, 7); // R and p of one body
/// assert_eq!(model.layout().nc, 5); // a revolute joint takes five freedoms
///
/// // A mistake is reported where it is made, naming the element:
/// let mut builder = ModelBuilder::new("wrong");
/// let error = builder
///     .add_marker(Marker { name: "tip".into(), body: BodyRef::Body(bob), origin: Vec3::zeros(), axes })
///     .unwrap_err();
/// assert_eq!(error.to_string(), "marker 'tip': no body has id 0 (this builder has 0)");
/// # Ok(())
/// # }
/// ```
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
    output_expressions: Vec<UserOutput>,
    /// `(kind, name)` of every element added, for unique names per kind.
    names: HashSet<(&'static str, String)>,
}

impl ModelBuilder {
    /// An empty model named `name`, without gravity.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Default::default() }
    }

    /// Gravitational acceleration, global (m/s²). Default zero; checked to be finite by
    /// [`build`](Self::build).
    pub fn gravity(mut self, g: Vec3) -> Self {
        self.gravity = g;
        self
    }

    /// Sets the gravitational acceleration, global (m/s²), of a builder held by reference.
    pub fn set_gravity(&mut self, g: Vec3) {
        self.gravity = g;
    }

    /// Adds a rigid body: positive finite mass, a physical inertia tensor (symmetric, positive
    /// definite, obeying the triangle inequality), a proper initial orientation, finite values.
    pub fn add_body(&mut self, body: RigidBody) -> Result<BodyId, ModelError> {
        self.check_new_name("body", &body.name)?;
        check_body(&body)?;
        self.names.insert(("body", body.name.clone()));
        self.bodies.push(body);
        self.modal.push(None);
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Adds a flexible body. Its rigid properties (mass, centre of mass, inertia about it) are those
    /// of the undeformed FE model, from the invariants. The sizes of the modal description must agree
    /// with its number of modes, its values be finite and its modal mass positive definite; a motion
    /// of its frame without mass (a straight beam's spin about its axis, without rotary inertia) is
    /// allowed here and must be held by the joints, which the assembly checks
    /// ([`ModalBody::massless_motions`]).
    pub fn add_flexible_body(
        &mut self,
        name: impl Into<String>,
        initial: InitialState,
        modal: ModalBody,
    ) -> Result<BodyId, ModelError> {
        let name = name.into();
        self.check_new_name("body", &name)?;
        let inv = &modal.invariants;
        let mass = inv.mass;
        let com = if mass > 0.0 { inv.c1 / mass } else { Vec3::zeros() };
        let inertia = inv.undeformed_inertia() - mass * (Mat3::identity() * com.norm_squared() - com * com.transpose());
        let body = RigidBody { name, mass, center_of_mass: com, inertia, initial };
        check_flexible_body(&body, &modal)?;
        self.names.insert(("body", body.name.clone()));
        self.bodies.push(body);
        self.modal.push(Some(modal));
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Adds a marker on ground or on a rigid body (a marker on a flexible body sits at a node: see
    /// [`add_node_marker`](Self::add_node_marker)). Its axes must be a proper orthonormal frame and
    /// its origin finite.
    pub fn add_marker(&mut self, marker: Marker) -> Result<MarkerId, ModelError> {
        self.check_new_name("marker", &marker.name)?;
        self.counts().check_all("marker", &marker.name, references::of_body_ref(marker.body))?;
        self.check_marker(&marker, None)?;
        Ok(self.push_marker(marker, None))
    }

    /// Adds a marker at node `node` (index into the body's nodes) of flexible body `body`, with `axes`
    /// in the body frame. It moves and turns with the node's elastic deformation.
    pub fn add_node_marker(
        &mut self,
        name: impl Into<String>,
        body: BodyId,
        node: usize,
        axes: Mat3,
    ) -> Result<MarkerId, ModelError> {
        let name = name.into();
        self.check_new_name("marker", &name)?;
        self.counts().check("marker", &name, Reference::Body(body))?;
        let origin = self.modal[body.0]
            .as_ref()
            .and_then(|m| m.nodes.get(node))
            .map_or(Vec3::zeros(), |n| n.position);
        let marker = Marker { name, body: BodyRef::Body(body), origin, axes };
        self.check_marker(&marker, Some(node))?;
        Ok(self.push_marker(marker, Some(node)))
    }

    /// Adds a joint or driver between two markers of this builder, on two different bodies (or a body
    /// and ground).
    pub fn add_joint(&mut self, joint: Joint) -> Result<JointId, ModelError> {
        self.check_new_name("joint", &joint.name)?;
        let refs = [Reference::Marker(joint.marker_i), Reference::Marker(joint.marker_j)];
        self.counts().check_all("joint", &joint.name, refs)?;
        let (bi, bj) = (self.markers[joint.marker_i.0].body, self.markers[joint.marker_j.0].body);
        if bi == bj {
            let body = match bi {
                BodyRef::Ground => "ground".to_string(),
                BodyRef::Body(b) => format!("body '{}'", self.bodies[b.0].name),
            };
            return Err(ModelError::JointOnOneBody { joint: joint.name.clone(), body });
        }
        self.names.insert(("joint", joint.name.clone()));
        self.joints.push(joint);
        Ok(JointId(self.joints.len() - 1))
    }

    /// Adds a force element. Its markers, joint and the measures its expressions read must be this
    /// builder's; a rotational spring-damper needs a joint that turns about `z_i`; a translational
    /// one a finite, non-negative stiffness, damping and free length.
    pub fn add_force(&mut self, force: ForceElement) -> Result<ForceId, ModelError> {
        self.check_new_name("force", &force.name)?;
        self.counts().check_all("force", &force.name, references::of_force(&force.kind))?;
        if let ForceKind::RotationalSpringDamper { joint, .. } = &force.kind {
            self.require_rotation("rotational spring-damper", &force.name, *joint)?;
        }
        if let ForceKind::TranslationalSpringDamper { stiffness, damping, free_length, .. } = &force.kind {
            for (what, x) in [("stiffness", stiffness), ("damping", damping), ("free_length", free_length)] {
                if !x.is_finite() || *x < 0.0 {
                    return Err(ModelError::BadValue {
                        element: "force",
                        name: force.name.clone(),
                        problem: format!("{what} must be finite and not negative, got {x}"),
                    });
                }
            }
        }
        self.names.insert(("force", force.name.clone()));
        self.forces.push(force);
        Ok(ForceId(self.forces.len() - 1))
    }

    /// Adds a measure. A joint angle or rate needs a joint that turns about `z_i`, a joint
    /// displacement or velocity one that slides along `z_i`; a position or velocity component is 0, 1
    /// or 2.
    pub fn add_measure(&mut self, measure: Measure) -> Result<MeasureId, ModelError> {
        self.check_new_name("measure", &measure.name)?;
        self.counts().check_all("measure", &measure.name, references::of_measure(&measure.kind))?;
        self.check_measure_kind(&measure)?;
        self.names.insert(("measure", measure.name.clone()));
        self.measures.push(measure);
        Ok(MeasureId(self.measures.len() - 1))
    }

    /// Declares a parameter of initial value `value`, changeable between the steps of a simulation
    /// ([`Simulation::set_parameter`](crate::analysis::Simulation::set_parameter)), and a measure of the
    /// same name through which expressions (a force law's actuator, an applied load) read its current
    /// value. The value must be finite and the name not used by another measure.
    pub fn add_parameter(&mut self, name: impl Into<String>, value: f64) -> Result<MeasureId, ModelError> {
        let name = name.into();
        if !value.is_finite() {
            return Err(ModelError::BadValue {
                element: "parameter",
                name,
                problem: format!("the value must be finite, got {value}"),
            });
        }
        let id = ParameterId(self.parameters.len());
        self.parameters.push(Parameter { name: name.clone(), value });
        let measure = self.add_measure(Measure { name, kind: MeasureKind::Parameter(id) });
        if measure.is_err() {
            self.parameters.pop();
        }
        measure
    }

    /// Adds an output request. What it reports must be this builder's; modal coordinates, node
    /// motions and strain energy need a flexible body and a node index within its nodes.
    pub fn add_output(&mut self, name: impl Into<String>, kind: OutputKind) -> Result<(), ModelError> {
        let name = name.into();
        self.check_new_name("output", &name)?;
        self.counts().check_all("output", &name, references::of_output(&kind))?;
        self.check_output_body(&name, &kind)?;
        self.check_output_joint(&name, &kind)?;
        if matches!(kind, OutputKind::UserExpression(_)) {
            return Err(ModelError::BadValue {
                element: "output",
                name,
                problem: "a user output is added with `add_output_expression`".into(),
            });
        }
        self.names.insert(("output", name.clone()));
        self.outputs.push(OutputRequest { name, kind });
        Ok(())
    }

    /// Adds a user output: one column `name` holding `expression` of `t`, measures and the columns of
    /// the outputs added before it ([`Variable::OutputColumn`](crate::function::Variable::OutputColumn),
    /// by index among the model's output columns), written in `unit`. A column the expression reads
    /// that is not before its own is an error of [`build`](Self::build).
    pub fn add_output_expression(
        &mut self,
        name: impl Into<String>,
        expression: crate::function::Expression,
        unit: impl Into<String>,
    ) -> Result<(), ModelError> {
        let name = name.into();
        self.check_new_name("output", &name)?;
        let measures: Vec<Reference> = expression.measures().map(Reference::Measure).collect();
        self.counts().check_all("output", &name, measures)?;
        self.names.insert(("output", name.clone()));
        self.outputs.push(OutputRequest { name, kind: OutputKind::UserExpression(self.output_expressions.len()) });
        self.output_expressions.push(UserOutput { expression, unit: unit.into() });
        Ok(())
    }

    /// The columns of the outputs added so far, in order (time not included): those a user output
    /// may read ([`add_output_expression`](Self::add_output_expression)).
    pub fn output_columns(&self) -> Vec<crate::analysis::OutputColumn> {
        let sources = crate::analysis::ColumnSources {
            modal: &self.modal,
            joints: &self.joints,
            measures: &self.measures,
            output_expressions: &self.output_expressions,
        };
        self.outputs.iter().flat_map(|o| crate::analysis::columns_of_output(&sources, o)).collect()
    }

    /// The body named `name`.
    pub fn find_body(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name).map(BodyId)
    }
    /// The marker named `name`.
    pub fn find_marker(&self, name: &str) -> Option<MarkerId> {
        self.markers.iter().position(|m| m.name == name).map(MarkerId)
    }
    /// The joint or driver named `name`.
    pub fn find_joint(&self, name: &str) -> Option<JointId> {
        self.joints.iter().position(|j| j.name == name).map(JointId)
    }
    /// The measure named `name`.
    pub fn find_measure(&self, name: &str) -> Option<MeasureId> {
        self.measures.iter().position(|m| m.name == name).map(MeasureId)
    }
    /// A joint added so far; `None` for an id this builder did not hand out.
    pub fn joint(&self, id: JointId) -> Option<&Joint> {
        self.joints.get(id.0)
    }
    /// A marker added so far; `None` for an id this builder did not hand out.
    pub fn marker(&self, id: MarkerId) -> Option<&Marker> {
        self.markers.get(id.0)
    }
    /// The modal description of a flexible body added so far; `None` for a rigid body or an id this
    /// builder did not hand out.
    pub fn modal_body(&self, body: BodyId) -> Option<&ModalBody> {
        self.modal.get(body.0).and_then(Option::as_ref)
    }

    /// Global position of a marker origin in the initial configuration given for its body; `None`
    /// for an id this builder did not hand out.
    pub fn initial_marker_position(&self, m: MarkerId) -> Option<Vec3> {
        let marker = self.markers.get(m.0)?;
        Some(match marker.body {
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
        })
    }

    /// Distance between two markers in the initial configuration (the default length of a distance
    /// joint); `None` if either id is not this builder's.
    pub fn initial_distance(&self, i: MarkerId, j: MarkerId) -> Option<f64> {
        Some((self.initial_marker_position(j)? - self.initial_marker_position(i)?).norm())
    }

    /// Returns the immutable model with its coordinate layout. The elements were checked as they were
    /// added; what is left is the model's own data: gravity must be finite.
    pub fn build(self) -> Result<Model, ModelError> {
        if !self.gravity.iter().all(|g| g.is_finite()) {
            return Err(ModelError::BadValue {
                element: "model",
                name: self.name,
                problem: format!("gravity must be finite, got {:?}", self.gravity.as_slice()),
            });
        }
        let equations: Vec<_> = self.joints.iter().map(|j| j.kind.equations()).collect();
        let modes: Vec<usize> = self.modal.iter().map(|m| m.as_ref().map_or(0, ModalBody::modes)).collect();
        let layout = Layout::new(&modes, &equations);
        let bodies = self.bodies.len();
        let mut model = Model {
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
            output_expressions: self.output_expressions,
            layout,
            massless_gauges: vec![crate::math::Mat3::zeros(); bodies],
        };
        model.massless_gauges = crate::analysis::massless_gauges(&model);
        model.with_checked_output_expressions()
    }

    fn counts(&self) -> Counts {
        Counts {
            bodies: self.bodies.len(),
            markers: self.markers.len(),
            joints: self.joints.len(),
            measures: self.measures.len(),
            parameters: self.parameters.len(),
        }
    }

    fn check_new_name(&self, kind: &'static str, name: &str) -> Result<(), ModelError> {
        if self.names.contains(&(kind, name.to_string())) {
            return Err(ModelError::DuplicateName { kind, name: name.to_string() });
        }
        Ok(())
    }

    /// The node (on flexible bodies only, within their nodes), a proper frame, a finite origin.
    fn check_marker(&self, marker: &Marker, node: Option<usize>) -> Result<(), ModelError> {
        check_marker_node(marker, node, &self.modal)?;
        check_frame(&format!("marker '{}'", marker.name), &marker.axes)?;
        if !marker.origin.iter().all(|x| x.is_finite()) {
            return Err(ModelError::BadFrame {
                what: format!("marker '{}'", marker.name),
                problem: "origin is not finite".into(),
            });
        }
        Ok(())
    }

    fn push_marker(&mut self, marker: Marker, node: Option<usize>) -> MarkerId {
        self.names.insert(("marker", marker.name.clone()));
        self.markers.push(marker);
        self.marker_node.push(node);
        MarkerId(self.markers.len() - 1)
    }

    fn check_measure_kind(&self, m: &Measure) -> Result<(), ModelError> {
        match m.kind {
            MeasureKind::JointAngle(j) | MeasureKind::JointRate(j) => self.require_rotation("measure", &m.name, j),
            MeasureKind::JointDisplacement(j) | MeasureKind::JointVelocity(j) => {
                let joint = &self.joints[j.0];
                if joint.kind.has_translation_along_z() {
                    return Ok(());
                }
                Err(ModelError::WrongJointKind {
                    element: "measure",
                    name: m.name.clone(),
                    joint: joint.name.clone(),
                    kind: joint.kind.keyword(),
                    motion: "a translation along z_i",
                })
            }
            MeasureKind::Position(_, c) | MeasureKind::Velocity(_, c) if c > 2 => Err(ModelError::BadValue {
                element: "measure",
                name: m.name.clone(),
                problem: format!("component {c} of a vector; expected 0 (x), 1 (y) or 2 (z)"),
            }),
            _ => Ok(()),
        }
    }

    /// Outputs of flexible bodies: the body is flexible and the node one of its nodes.
    fn check_output_body(&self, name: &str, kind: &OutputKind) -> Result<(), ModelError> {
        let (body, node) = match *kind {
            OutputKind::ModalCoordinates(b) | OutputKind::StrainEnergy(b) => (b, None),
            OutputKind::NodePosition(b, n)
            | OutputKind::NodeVelocity(b, n)
            | OutputKind::NodeAcceleration(b, n)
            | OutputKind::NodeDeformation(b, n) => (b, Some(n)),
            _ => return Ok(()),
        };
        let problem = |problem: String| Err(ModelError::BadValue { element: "output", name: name.to_string(), problem });
        let body_name = &self.bodies[body.0].name;
        match (&self.modal[body.0], node) {
            (None, _) => problem(format!("body '{body_name}' is rigid; this output needs a flexible body")),
            (Some(m), Some(n)) if n >= m.nodes.len() => {
                problem(format!("node index {n} is beyond the {} nodes of body '{body_name}'", m.nodes.len()))
            }
            _ => Ok(()),
        }
    }

    fn check_output_joint(&self, name: &str, kind: &OutputKind) -> Result<(), ModelError> {
        use super::JointCoordinateSet as Set;
        let OutputKind::JointCoordinates(j, set) = *kind else { return Ok(()) };
        let joint = &self.joints[j.0];
        let fits = match set {
            Set::Angle => joint.kind.has_rotation_about_z(),
            Set::Displacement => joint.kind.has_translation_along_z(),
            Set::AngleAndDisplacement => joint.kind.has_rotation_about_z() && joint.kind.has_translation_along_z(),
            Set::RelativeRotation => true,
        };
        if fits {
            return Ok(());
        }
        Err(ModelError::BadValue {
            element: "output",
            name: name.to_string(),
            problem: format!("joint '{}' ({}) has no {set:?} coordinates", joint.name, joint.kind.keyword()),
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
