//! Small models for the crate's unit tests.

use crate::body::{InitialState, Marker, RigidBody};
use crate::force::{ForceElement, ForceKind};
use crate::function::Expression;
use crate::joint::{Joint, JointKind};
use crate::math::{EulerParameters, Mat3, Vec3};
use crate::measure::{Measure, MeasureKind};
use crate::model::{BodyRef, Model, ModelBuilder};

/// A spatial double pendulum (spherical, then revolute) with an offset centre of mass, gravity, and a
/// spring–damper between the second link and ground whose actuator reads the hinge's rate: every coupling
/// path of the Jacobian pattern (joints, forces, measures) is exercised.
pub(crate) fn double_pendulum_with_spring() -> Model {
    let mut b = ModelBuilder::new("test double pendulum").gravity(Vec3::new(0.0, -9.81, 0.0));
    let tilt = EulerParameters::from_axis_angle(&Vec3::new(0.3, 0.2, 1.0), 0.7);
    let link = |name: &str, position: Vec3| RigidBody {
        name: name.into(),
        mass: 1.3,
        center_of_mass: Vec3::new(0.02, -0.25, 0.01),
        inertia: Mat3::new(0.03, 0.001, 0.0, 0.001, 0.004, 0.0005, 0.0, 0.0005, 0.03),
        initial: InitialState { position, orientation: tilt, velocity: None, angular_velocity: None },
    };
    let a = tilt.rotation_matrix();
    let l1 = b.add_body(link("link1", Vec3::zeros()));
    let l2 = b.add_body(link("link2", a * Vec3::new(0.0, -0.5, 0.0)));
    let mk = |b: &mut ModelBuilder, name: &str, body, origin| {
        b.add_marker(Marker { name: name.into(), body, origin, axes: Mat3::identity() })
    };
    let g0 = mk(&mut b, "g0", BodyRef::Ground, Vec3::zeros());
    let a1 = mk(&mut b, "a1", BodyRef::Body(l1), Vec3::zeros());
    let e1 = mk(&mut b, "e1", BodyRef::Body(l1), Vec3::new(0.0, -0.5, 0.0));
    let a2 = mk(&mut b, "a2", BodyRef::Body(l2), Vec3::zeros());
    let tip = mk(&mut b, "tip", BodyRef::Body(l2), Vec3::new(0.0, -0.5, 0.0));
    let anchor = mk(&mut b, "anchor", BodyRef::Ground, Vec3::new(0.4, -0.2, 0.1));
    b.add_joint(Joint { name: "ball".into(), kind: JointKind::Spherical, marker_i: g0, marker_j: a1 });
    let hinge = b.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: e1, marker_j: a2 });
    let rate = b.add_measure(Measure { name: "hinge_rate".into(), kind: MeasureKind::JointRate(hinge) });
    let actuator = Expression::parse("0.5*sin(3*t) - 0.2*hinge_rate", &|n| (n == "hinge_rate").then_some(rate)).unwrap();
    b.add_force(ForceElement {
        name: "spring".into(),
        kind: ForceKind::TranslationalSpringDamper {
            marker_i: anchor,
            marker_j: tip,
            stiffness: 50.0,
            damping: 0.7,
            free_length: 0.3,
            actuator: Some(actuator),
        },
    });
    b.build().unwrap()
}
