//! Small models for the crate's unit tests and its integration tests (hidden: not part of the API).

use super::{assemble, velocity_analysis, AccelerationSolver, Accelerations, State};
use crate::body::{InitialState, Marker, RigidBody};
use crate::force::{ForceElement, ForceKind};
use crate::function::Expression;
use crate::joint::{Joint, JointKind};
use crate::math::{EulerParameters, Mat3, Vec3};
use crate::measure::{Measure, MeasureKind};
use crate::model::{BodyRef, Model, ModelBuilder, OutputKind};
use crate::Data;

/// A flexible strip of two lumped nodes (1 kg each, rotary inertia 1e-3 kg m², at x = 0 and 1 m) whose
/// one mode moves the far node by 1 m along z and turns both by 1 rad about −y: modal mass 1 + 2e-3,
/// modal stiffness `stiffness`.
pub fn two_node_strip(stiffness: f64) -> crate::body::ModalBody {
    use nalgebra::{DMatrix, Matrix3xX};
    let node = |x: f64| crate::body::LumpedNode {
        position: Vec3::new(x, 0.0, 0.0),
        mass: 1.0,
        rotary_inertia: Mat3::identity() * 1e-3,
        psi: Matrix3xX::from_column_slice(&[0.0, 0.0, x]),
        theta: Matrix3xX::from_column_slice(&[0.0, -1.0, 0.0]),
    };
    crate::body::ModalBody::from_lumped_nodes(&[node(0.0), node(1.0)], DMatrix::from_element(1, 1, stiffness)).unwrap()
}

/// `model` assembled, its velocities moved off zero (by `0.1 sin k`) and made consistent, with the
/// accelerations and multipliers there: a state at which every term of the equations of motion is
/// alive, for finite-difference tests.
pub fn moving_state(model: &Model) -> (Data, State, Accelerations) {
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    assemble(model, &mut data, &mut state, Default::default()).unwrap();
    state.v.iter_mut().enumerate().for_each(|(k, v)| *v += 0.1 * (k as f64).sin());
    velocity_analysis(model, &mut data, &mut state).unwrap();
    let acc = AccelerationSolver::new(model).solve_at(model, &mut data, 0.0, &state.q, &state.v, &state.active).unwrap().clone();
    (data, state, acc)
}

/// A spatial double pendulum (spherical, then revolute) with an offset centre of mass, gravity, and a
/// spring–damper between the second link and ground whose actuator reads the hinge's rate: every coupling
/// path of the Jacobian pattern (joints, forces, measures) is exercised.
pub fn double_pendulum_with_spring() -> Model {
    let mut b = ModelBuilder::new("test double pendulum").gravity(Vec3::new(0.0, -9.81, 0.0));
    let tilt = EulerParameters::from_axis_angle(&Vec3::new(0.3, 0.2, 1.0), 0.7).unwrap();
    let link = |name: &str, position: Vec3| RigidBody {
        name: name.into(),
        mass: 1.3,
        center_of_mass: Vec3::new(0.02, -0.25, 0.01),
        inertia: Mat3::new(0.03, 0.001, 0.0, 0.001, 0.004, 0.0005, 0.0, 0.0005, 0.03),
        initial: InitialState { position, orientation: tilt, velocity: None, angular_velocity: None },
    };
    let a = tilt.rotation_matrix();
    let l1 = b.add_body(link("link1", Vec3::zeros())).unwrap();
    let l2 = b.add_body(link("link2", a * Vec3::new(0.0, -0.5, 0.0))).unwrap();
    let mk = |b: &mut ModelBuilder, name: &str, body, origin| {
        b.add_marker(Marker { name: name.into(), body, origin, axes: Mat3::identity() }).unwrap()
    };
    let g0 = mk(&mut b, "g0", BodyRef::Ground, Vec3::zeros());
    let a1 = mk(&mut b, "a1", BodyRef::Body(l1), Vec3::zeros());
    let e1 = mk(&mut b, "e1", BodyRef::Body(l1), Vec3::new(0.0, -0.5, 0.0));
    let a2 = mk(&mut b, "a2", BodyRef::Body(l2), Vec3::zeros());
    let tip = mk(&mut b, "tip", BodyRef::Body(l2), Vec3::new(0.0, -0.5, 0.0));
    let anchor = mk(&mut b, "anchor", BodyRef::Ground, Vec3::new(0.4, -0.2, 0.1));
    b.add_joint(Joint { name: "ball".into(), kind: JointKind::Spherical, marker_i: g0, marker_j: a1 }).unwrap();
    let hinge = b.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: e1, marker_j: a2 }).unwrap();
    let rate = b.add_measure(Measure { name: "hinge_rate".into(), kind: MeasureKind::JointRate(hinge) }).unwrap();
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
    }).unwrap();
    b.build().unwrap()
}

/// A pendulum whose bob slides along the rod on a translational joint, held by a stiff, critically
/// damped spring (1e7 N/m): a fast mode along a joint's free direction.
pub fn pendulum_with_stiff_slider() -> Model {
    pendulum_with_stiff_slider_of(1e7)
}

/// [`pendulum_with_stiff_slider`] with a spring of `stiffness` (N/m), still critically damped: the
/// fast eigenvalue is a double `−√(k/m)` (m = 1 kg). Its output `bob` is the bob's position.
pub fn pendulum_with_stiff_slider_of(stiffness: f64) -> Model {
    let (l, mass) = (1.0, 1.0);
    let mut b = ModelBuilder::new("pendulum with a stiff slider").gravity(Vec3::new(0.0, -9.81, 0.0));
    let theta0 = 1.0_f64;
    let pose = EulerParameters::from_axis_angle(&Vec3::z(), theta0).unwrap();
    let down = Vec3::new(theta0.sin(), -theta0.cos(), 0.0);
    let body = |name: &str, m: f64, com: Vec3, inertia: Vec3, position: Vec3| RigidBody {
        name: name.into(),
        mass: m,
        center_of_mass: com,
        inertia: Mat3::from_diagonal(&inertia),
        initial: InitialState { position, orientation: pose, velocity: None, angular_velocity: None },
    };
    let rod = b.add_body(body("rod", 0.5, Vec3::new(0.0, -0.5 * l, 0.0), Vec3::new(0.05, 1e-3, 0.05), Vec3::zeros())).unwrap();
    let bob = b.add_body(body("bob", mass, Vec3::zeros(), Vec3::new(1e-3, 1e-3, 1e-3), l * down)).unwrap();
    let mk = |b: &mut ModelBuilder, name: &str, body, origin, axes| b.add_marker(Marker { name: name.into(), body, origin, axes }).unwrap();
    let pivot_ground = mk(&mut b, "pivot_ground", BodyRef::Ground, Vec3::zeros(), Mat3::identity());
    let pivot = mk(&mut b, "pivot", BodyRef::Body(rod), Vec3::zeros(), Mat3::identity());
    b.add_joint(Joint { name: "pivot".into(), kind: JointKind::Revolute, marker_i: pivot_ground, marker_j: pivot }).unwrap();
    // z along the rod (body y): x = body z, y = body x, z = body y.
    let along = Mat3::new(0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0);
    let guide = mk(&mut b, "guide", BodyRef::Body(rod), Vec3::new(0.0, -l, 0.0), along);
    let slider = mk(&mut b, "slider", BodyRef::Body(bob), Vec3::zeros(), along);
    b.add_joint(Joint { name: "slide".into(), kind: JointKind::Translational, marker_i: guide, marker_j: slider }).unwrap();
    let spring_end = mk(&mut b, "spring_end", BodyRef::Body(rod), Vec3::zeros(), Mat3::identity());
    let bob_centre = mk(&mut b, "bob_centre", BodyRef::Body(bob), Vec3::zeros(), Mat3::identity());
    b.add_force(ForceElement {
        name: "spring".into(),
        kind: ForceKind::TranslationalSpringDamper {
            marker_i: spring_end,
            marker_j: bob_centre,
            stiffness,
            damping: 2.0 * (stiffness * mass).sqrt(),
            free_length: l,
            actuator: None,
        },
    }).unwrap();
    b.add_output("bob", OutputKind::MarkerPosition(bob_centre)).unwrap();
    b.build().unwrap()
}

/// `n` rods of 1 kg and 0.5 m along x on spherical joints, the first to ground: the chain of the
/// scaling measurements.
pub fn spherical_chain(n: usize) -> Model {
    rods_on_spherical_joints(n, true, None)
}

/// `n` independent spherical pendulums, rods of 1 kg and 0.5 m each on a spherical joint to ground, 1 m
/// apart.
pub fn spherical_pendulums(n: usize) -> Model {
    rods_on_spherical_joints(n, false, None)
}

/// [`spherical_pendulums`] where every `every`-th pendulum (from the first) is hung a second time, by an
/// identical spherical joint `s{i}_again` after all the others, whose 3 rows repeat the first's.
pub fn spherical_pendulums_hung_twice(n: usize, every: usize) -> Model {
    rods_on_spherical_joints(n, false, Some(every))
}

fn rods_on_spherical_joints(n: usize, chained: bool, repeated_every: Option<usize>) -> Model {
    let mut b = ModelBuilder::new(if chained { "chain" } else { "pendulums" }).gravity(Vec3::new(0.0, 0.0, -9.81));
    let length = 0.5;
    let mut previous_end = None;
    let mut joints = Vec::with_capacity(n);
    for i in 0..n {
        let (x, y) = if chained { ((i as f64 + 0.5) * length, 0.0) } else { (0.5 * length, i as f64) };
        let rod = b
            .add_body(RigidBody {
                name: format!("rod{i}"),
                mass: 1.0,
                center_of_mass: Vec3::zeros(),
                inertia: Mat3::from_diagonal(&Vec3::new(1e-4, length * length / 12.0, length * length / 12.0)),
                initial: InitialState {
                    position: Vec3::new(x, y, 0.0),
                    orientation: EulerParameters::identity(),
                    velocity: None,
                    angular_velocity: None,
                },
            })
            .unwrap();
        let marker = |b: &mut ModelBuilder, name: String, body, origin| {
            b.add_marker(Marker { name, body, origin, axes: Mat3::identity() }).unwrap()
        };
        let pivot = match previous_end {
            Some(end) if chained => end,
            _ => marker(&mut b, format!("pivot{i}"), BodyRef::Ground, Vec3::new(0.0, y, 0.0)),
        };
        let start = marker(&mut b, format!("rod{i}_start"), BodyRef::Body(rod), Vec3::new(-0.5 * length, 0.0, 0.0));
        previous_end = Some(marker(&mut b, format!("rod{i}_end"), BodyRef::Body(rod), Vec3::new(0.5 * length, 0.0, 0.0)));
        b.add_joint(Joint { name: format!("s{i}"), kind: JointKind::Spherical, marker_i: pivot, marker_j: start }).unwrap();
        joints.push((pivot, start));
    }
    for i in repeated_every.map(|every| (0..n).step_by(every)).into_iter().flatten() {
        let (marker_i, marker_j) = joints[i];
        b.add_joint(Joint { name: format!("s{i}_again"), kind: JointKind::Spherical, marker_i, marker_j }).unwrap();
    }
    b.build().unwrap()
}

/// A spatial triple pendulum of tilted links with offset centres of mass under gravity, on a spherical
/// joint to ground, a revolute joint and a universal joint, and no force element: every body's
/// Jacobian columns are analytic.
pub fn spatial_triple_pendulum() -> Model {
    let mut b = ModelBuilder::new("test triple pendulum").gravity(Vec3::new(0.0, -9.81, 0.0));
    let tilt = EulerParameters::from_axis_angle(&Vec3::new(0.3, 0.2, 1.0), 0.7).unwrap();
    let a = tilt.rotation_matrix();
    let mut previous = (BodyRef::Ground, Vec3::zeros());
    let cross_pin = EulerParameters::from_axis_angle(&Vec3::x(), std::f64::consts::FRAC_PI_2).unwrap().rotation_matrix();
    for (i, kind) in [JointKind::Spherical, JointKind::Revolute, JointKind::Universal].into_iter().enumerate() {
        let link = b
            .add_body(RigidBody {
                name: format!("link{i}"),
                mass: 1.3 - 0.2 * i as f64,
                center_of_mass: Vec3::new(0.02, -0.25, 0.01),
                inertia: Mat3::new(0.03, 0.001, 0.0, 0.001, 0.004, 0.0005, 0.0, 0.0005, 0.03),
                initial: InitialState {
                    position: a * Vec3::new(0.0, -0.5 * i as f64, 0.0),
                    orientation: tilt,
                    velocity: None,
                    angular_velocity: None,
                },
            })
            .unwrap();
        let axes = if matches!(kind, JointKind::Universal) { cross_pin } else { Mat3::identity() };
        let marker = |b: &mut ModelBuilder, name: String, body, origin, axes| {
            b.add_marker(Marker { name, body, origin, axes }).unwrap()
        };
        let pivot = marker(&mut b, format!("pivot{i}"), previous.0, previous.1, Mat3::identity());
        let start = marker(&mut b, format!("link{i}_start"), BodyRef::Body(link), Vec3::zeros(), axes);
        b.add_joint(Joint { name: format!("j{i}"), kind, marker_i: pivot, marker_j: start }).unwrap();
        previous = (BodyRef::Body(link), Vec3::new(0.0, -0.5, 0.0));
    }
    b.build().unwrap()
}
