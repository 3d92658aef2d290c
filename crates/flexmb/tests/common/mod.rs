//! Model builders shared by the physics tests.
#![allow(dead_code)]

use flexmb::body::{InitialState, Marker, RigidBody};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, MarkerId, ModelBuilder};

pub fn body(name: &str, mass: f64, inertia: Vec3, position: Vec3, orientation: EulerParameters) -> RigidBody {
    RigidBody {
        name: name.into(),
        mass,
        center_of_mass: Vec3::zeros(),
        inertia: Mat3::from_diagonal(&inertia),
        initial: InitialState { position, orientation, velocity: None, angular_velocity: None },
    }
}

pub fn marker(b: &mut ModelBuilder, name: &str, body: BodyRef, origin: Vec3) -> MarkerId {
    b.add_marker(Marker { name: name.into(), body, origin, axes: Mat3::identity() })
}

pub fn joint(b: &mut ModelBuilder, name: &str, kind: JointKind, i: MarkerId, j: MarkerId) {
    b.add_joint(Joint { name: name.into(), kind, marker_i: i, marker_j: j });
}

/// A pendulum of length `l` swinging about the global z axis through the origin, bob (mass `m`,
/// inertia `ic` about its centre) released at rest `theta0` from the hanging position; gravity −y.
pub fn pendulum(l: f64, m: f64, ic: f64, theta0: f64, g: f64) -> ModelBuilder {
    let mut b = ModelBuilder::new("pendulum").gravity(Vec3::new(0.0, -g, 0.0));
    let pose = EulerParameters::from_axis_angle(&Vec3::z(), theta0);
    let bob = b.add_body(body("bob", m, Vec3::new(ic, ic, ic), Vec3::new(l * theta0.sin(), -l * theta0.cos(), 0.0), pose));
    let gm = marker(&mut b, "pivot_ground", BodyRef::Ground, Vec3::zeros());
    let bm = marker(&mut b, "pivot_bob", BodyRef::Body(bob), Vec3::new(0.0, l, 0.0));
    marker(&mut b, "bob_centre", BodyRef::Body(bob), Vec3::zeros());
    joint(&mut b, "pivot", JointKind::Revolute, gm, bm);
    b
}

/// Complete elliptic integral of the first kind `K(k)` by the arithmetic–geometric mean.
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut g) = (1.0_f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        let an = 0.5 * (a + g);
        g = (a * g).sqrt();
        a = an;
    }
    std::f64::consts::PI / (2.0 * a)
}
