//! Each kind of bad input to [`ModelBuilder`] is refused when it is added, with an error that names the
//! element and says what was expected.

use nalgebra::{DMatrix, Matrix3xX};

use super::{BodyId, BodyRef, JointId, MarkerId, MeasureId, ModelBuilder, ModelError, OutputKind};
use crate::body::{InitialState, LumpedNode, Marker, ModalBody, ModalDamping, ModalError, RigidBody};
use crate::force::{ForceElement, ForceKind};
use crate::function::Expression;
use crate::joint::{Joint, JointKind};
use crate::math::{Mat3, Vec3};
use crate::measure::{Measure, MeasureKind};

fn body(name: &str) -> RigidBody {
    RigidBody {
        name: name.into(),
        mass: 2.0,
        center_of_mass: Vec3::zeros(),
        inertia: Mat3::from_diagonal(&Vec3::new(0.1, 0.2, 0.25)),
        initial: InitialState::default(),
    }
}

fn marker(name: &str, body: BodyRef) -> Marker {
    Marker { name: name.into(), body, origin: Vec3::zeros(), axes: Mat3::identity() }
}

/// A body on a spherical joint to ground; its markers are `ground_point` (0) and `body_point` (1).
fn ball_joint_builder() -> (ModelBuilder, BodyId, JointId) {
    let mut b = ModelBuilder::new("ball");
    let id = b.add_body(body("link")).unwrap();
    let g = b.add_marker(marker("ground_point", BodyRef::Ground)).unwrap();
    let m = b.add_marker(marker("body_point", BodyRef::Body(id))).unwrap();
    let joint = Joint { name: "ball".into(), kind: JointKind::Spherical, marker_i: g, marker_j: m };
    let j = b.add_joint(joint).unwrap();
    (b, id, j)
}

fn message(result: Result<impl std::fmt::Debug, ModelError>) -> String {
    result.unwrap_err().to_string()
}

#[test]
fn a_marker_on_an_unknown_body_is_refused() {
    let mut b = ModelBuilder::new("m");
    b.add_body(body("link")).unwrap();
    let error = b.add_marker(marker("tip", BodyRef::Body(BodyId(3)))).unwrap_err();
    assert_eq!(
        error,
        ModelError::UnknownId { element: "marker", name: "tip".into(), kind: "body", index: 3, count: 1 }
    );
    assert_eq!(error.to_string(), "marker 'tip': no body has id 3 (this builder has 1)");
}

#[test]
fn an_id_from_a_larger_builder_is_refused() {
    let (other, _, _) = ball_joint_builder();
    let far = other.find_marker("body_point").unwrap();
    let mut b = ModelBuilder::new("small");
    let g = b.add_marker(marker("only", BodyRef::Ground)).unwrap();
    let joint = Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: g, marker_j: far };
    assert_eq!(message(b.add_joint(joint)), "joint 'hinge': no marker has id 1 (this builder has 1)");
}

#[test]
fn lookups_of_unknown_ids_give_none() {
    let (b, id, _) = ball_joint_builder();
    assert!(b.joint(JointId(1)).is_none());
    assert!(b.marker(MarkerId(2)).is_none());
    assert!(b.modal_body(BodyId(9)).is_none());
    assert!(b.modal_body(id).is_none(), "a rigid body has no modal description");
    assert!(b.initial_distance(MarkerId(0), MarkerId(7)).is_none());
    assert_eq!(b.initial_distance(MarkerId(0), MarkerId(1)), Some(0.0));
}

#[test]
fn a_name_used_twice_is_refused() {
    let mut b = ModelBuilder::new("m");
    b.add_body(body("link")).unwrap();
    assert_eq!(message(b.add_body(body("link"))), "body name 'link' is used twice");
    b.add_marker(marker("link", BodyRef::Ground)).expect("names are unique per kind");
}

#[test]
fn non_finite_and_non_positive_masses_are_refused() {
    for mass in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let mut b = ModelBuilder::new("m");
        let error = b.add_body(RigidBody { mass, ..body("link") }).unwrap_err();
        assert_eq!(error.to_string(), format!("body 'link': mass must be positive and finite, got {mass}"));
    }
}

#[test]
fn an_inertia_that_is_not_positive_definite_is_refused() {
    let mut b = ModelBuilder::new("m");
    let inertia = Mat3::from_diagonal(&Vec3::new(0.1, 0.0, 0.1));
    assert_eq!(
        message(b.add_body(RigidBody { inertia, ..body("flat") })),
        "body 'flat': inertia must be positive definite; principal moments are 0.000000e0, 1.000000e-1, 1.000000e-1"
    );
    let inertia = Mat3::from_diagonal(&Vec3::new(0.1, 0.1, 0.3));
    assert_eq!(
        message(b.add_body(RigidBody { inertia, ..body("impossible") })),
        "body 'impossible': inertia principal moments 1.000000e-1, 1.000000e-1, 3.000000e-1 violate the triangle \
         inequality I1 + I2 >= I3"
    );
    let mut inertia = Mat3::from_diagonal(&Vec3::new(0.1, 0.2, 0.25));
    inertia[(0, 1)] = 0.01;
    assert!(message(b.add_body(RigidBody { inertia, ..body("skewed") })).starts_with("body 'skewed': inertia is not symmetric"));
}

#[test]
fn marker_axes_with_a_zero_length_axis_are_refused() {
    let mut b = ModelBuilder::new("m");
    let axes = Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 0.0));
    let error = b.add_marker(Marker { axes, ..marker("flat", BodyRef::Ground) }).unwrap_err();
    assert!(
        error.to_string().starts_with("marker 'flat': axes are not a proper orthonormal frame (defect"),
        "{error}"
    );
    let origin = Vec3::new(0.0, f64::NAN, 0.0);
    assert_eq!(message(b.add_marker(Marker { origin, ..marker("lost", BodyRef::Ground) })), "marker 'lost': origin is not finite");
}

#[test]
fn a_joint_with_both_markers_on_one_body_is_refused() {
    let (mut b, id, _) = ball_joint_builder();
    let other = b.add_marker(marker("body_point_2", BodyRef::Body(id))).unwrap();
    let body_point = b.find_marker("body_point").unwrap();
    let joint = Joint { name: "self".into(), kind: JointKind::Fixed, marker_i: body_point, marker_j: other };
    assert_eq!(message(b.add_joint(joint)), "joint 'self': both markers are on body 'link'");
}

#[test]
fn a_rotational_spring_on_a_spherical_joint_is_refused() {
    let (mut b, _, ball) = ball_joint_builder();
    let kind = ForceKind::RotationalSpringDamper { joint: ball, stiffness: 1.0, damping: 0.0, free_angle: 0.0, actuator: None };
    assert_eq!(
        message(b.add_force(ForceElement { name: "torsion".into(), kind })),
        "rotational spring-damper 'torsion' needs a joint that allows a rotation about z_i, but 'ball' is a spherical joint"
    );
}

#[test]
fn a_negative_or_non_finite_spring_constant_is_refused() {
    let (mut b, _, _) = ball_joint_builder();
    let spring = |stiffness: f64, damping: f64| ForceKind::TranslationalSpringDamper {
        marker_i: MarkerId(0),
        marker_j: MarkerId(1),
        stiffness,
        damping,
        free_length: 0.0,
        actuator: None,
    };
    let error = b.add_force(ForceElement { name: "spring".into(), kind: spring(-5.0, 0.0) }).unwrap_err();
    assert_eq!(error.to_string(), "force 'spring': stiffness must be finite and not negative, got -5");
    let error = b.add_force(ForceElement { name: "spring".into(), kind: spring(5.0, f64::INFINITY) }).unwrap_err();
    assert_eq!(error.to_string(), "force 'spring': damping must be finite and not negative, got inf");
}

#[test]
fn an_expression_reading_an_unknown_measure_is_refused() {
    let (mut b, _, _) = ball_joint_builder();
    let push = Expression::parse("2*speed", &|_| Some(MeasureId(0))).unwrap();
    let zero = Expression::constant(0.0);
    let kind = ForceKind::AppliedForce {
        marker: MarkerId(1),
        components: [push, zero.clone(), zero],
        frame: crate::force::ForceFrame::Global,
    };
    assert_eq!(
        message(b.add_force(ForceElement { name: "push".into(), kind })),
        "force 'push': no measure has id 0 (this builder has 0)"
    );
}

#[test]
fn a_measure_needs_a_joint_of_the_right_kind_and_a_component_0_to_2() {
    let (mut b, _, ball) = ball_joint_builder();
    let angle = Measure { name: "angle".into(), kind: MeasureKind::JointDisplacement(ball) };
    assert_eq!(
        message(b.add_measure(angle)),
        "measure 'angle' needs a joint that allows a translation along z_i, but 'ball' is a spherical joint"
    );
    let w = Measure { name: "w".into(), kind: MeasureKind::Velocity(MarkerId(1), 3) };
    assert_eq!(message(b.add_measure(w)), "measure 'w': component 3 of a vector; expected 0 (x), 1 (y) or 2 (z)");
}

/// A flexible body of two lumped nodes and one mode.
fn strip() -> ModalBody {
    crate::analysis::test_models::two_node_strip(100.0)
}

#[test]
fn outputs_and_node_markers_of_flexible_bodies_check_the_body_and_node() {
    let (mut b, link, _) = ball_joint_builder();
    let flexible = b.add_flexible_body("strip", InitialState::default(), strip()).unwrap();
    assert_eq!(
        message(b.add_output("modes", OutputKind::ModalCoordinates(link))),
        "output 'modes': body 'link' is rigid; this output needs a flexible body"
    );
    assert_eq!(
        message(b.add_output("far", OutputKind::NodePosition(flexible, 2))),
        "output 'far': node index 2 is beyond the 2 nodes of body 'strip'"
    );
    b.add_output("tip", OutputKind::NodePosition(flexible, 1)).unwrap();
    assert_eq!(
        message(b.add_node_marker("far", flexible, 5, Mat3::identity())),
        "marker 'far': node index 5 is beyond the body's 2 nodes"
    );
    assert_eq!(
        message(b.add_node_marker("rigid", link, 0, Mat3::identity())),
        "marker 'rigid': names a node, but its body is rigid"
    );
    assert_eq!(
        message(b.add_marker(marker("loose", BodyRef::Body(flexible)))),
        "marker 'loose': is on a flexible body: it must sit at one of the body's nodes"
    );
}

#[test]
fn a_flexible_body_with_sizes_that_disagree_is_refused() {
    let mut modal = strip();
    modal.mode_labels.push("extra".into());
    let mut b = ModelBuilder::new("m");
    assert_eq!(
        message(b.add_flexible_body("strip", InitialState::default(), modal)),
        "body 'strip': mode labels: 2, expected 1 (one per mode)"
    );
}

#[test]
fn lumped_nodes_whose_mode_shapes_do_not_match_the_modes_are_refused() {
    let node = LumpedNode {
        position: Vec3::zeros(),
        mass: 1.0,
        rotary_inertia: Mat3::zeros(),
        psi: Matrix3xX::zeros(2),
        theta: Matrix3xX::zeros(1),
    };
    let one_mode = DMatrix::from_element(1, 1, 100.0);
    assert_eq!(
        ModalBody::from_lumped_nodes(std::slice::from_ref(&node), one_mode).unwrap_err().to_string(),
        "lumped node 0: psi has 2 columns, expected 1 (one per mode)"
    );
    assert_eq!(
        ModalBody::from_lumped_nodes(&[node], DMatrix::zeros(2, 1)).unwrap_err(),
        ModalError::StiffnessSize { rows: 2, columns: 1, modes: 2 }
    );
}

#[test]
fn damping_that_does_not_fit_the_modes_is_refused() {
    let body = strip();
    assert_eq!(
        body.damping_matrix(&ModalDamping::Ratios(vec![0.01, 0.02])).unwrap_err().to_string(),
        "2 damping ratios for 1 modes; give one for all or one per mode"
    );
    let mut massless = strip();
    massless.invariants.c9[(0, 0)] = 0.0;
    massless.invariants.rotary_modal_mass[(0, 0)] = 0.0;
    assert_eq!(massless.damping_matrix(&ModalDamping::Ratios(vec![0.01])), Err(ModalError::MassNotPositiveDefinite));
    let mut wrong = strip();
    wrong.stiffness = DMatrix::zeros(2, 2);
    assert_eq!(
        wrong.damping_matrix(&ModalDamping::Rayleigh { alpha: 0.1, beta: 0.0 }).unwrap_err().to_string(),
        "the modal stiffness is 2×2; expected 1×1, one row and column per mode"
    );
}

#[test]
fn a_rejected_element_leaves_the_builder_as_it_was() {
    let (mut b, _, _) = ball_joint_builder();
    b.add_body(RigidBody { mass: -1.0, ..body("bad") }).unwrap_err();
    b.add_body(body("good")).expect("the name of a refused body is free");
    let model = b.build().unwrap();
    assert_eq!(model.bodies().len(), 2);
}

#[test]
fn gravity_that_is_not_finite_is_refused_by_build() {
    let b = ModelBuilder::new("space").gravity(Vec3::new(0.0, f64::NAN, 0.0));
    assert_eq!(message(b.build()), "model 'space': gravity must be finite, got [0.0, NaN, 0.0]");
}

#[test]
fn a_parameter_needs_a_finite_value_and_a_measure_name_of_its_own() {
    let (mut b, _, _) = ball_joint_builder();
    let e = message(b.add_parameter("push", f64::NAN));
    assert!(e.contains("parameter 'push'") && e.contains("must be finite, got NaN"), "{e}");
    b.add_parameter("push", 2.0).unwrap();
    let e = message(b.add_parameter("push", 3.0));
    assert!(e.contains("push"), "{e}");
    // The refused second declaration left the first one alone.
    let model = b.build().unwrap();
    assert_eq!(model.parameters().len(), 1);
    assert_eq!(model.parameters()[0].value, 2.0);
    // A measure that reads a parameter this builder did not declare is refused.
    let (mut b, _, _) = ball_joint_builder();
    let e = message(b.add_measure(Measure { name: "p".into(), kind: MeasureKind::Parameter(crate::model::ParameterId(0)) }));
    assert!(e.contains("no parameter has id 0"), "{e}");
}
