//! Static equilibrium against closed forms: a pendulum on a rotational spring, a spring-loaded slider,
//! a parallelogram four-bar under its weight held by a spring (virtual work), a spherical pendulum
//! released horizontal (the fallback, and a neutral spin); the joint reactions balance the weight; a
//! free motion is named.

use flexmb::analysis::{static_equilibrium, EquilibriumError, EquilibriumMethod, EquilibriumReport, EquilibriumSettings, State};
use flexmb::body::{InitialState, Marker, RigidBody};
use flexmb::force::{ForceElement, ForceFrame, ForceKind};
use flexmb::function::Expression;
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyId, BodyRef, JointId, MarkerId, Model, ModelBuilder};
use flexmb::Data;

const G: f64 = 9.81;

fn body(name: &str, mass: f64, center_of_mass: Vec3, position: Vec3, angle: f64) -> RigidBody {
    let orientation = EulerParameters::from_axis_angle(&Vec3::new(0.0, 0.0, 1.0), angle).unwrap();
    let initial = InitialState { position, orientation, velocity: None, angular_velocity: None };
    RigidBody { name: name.into(), mass, center_of_mass, inertia: Mat3::identity() * 0.01, initial }
}

fn marker(b: &mut ModelBuilder, name: &str, body: BodyRef, origin: Vec3, axes: Mat3) -> MarkerId {
    b.add_marker(Marker { name: name.into(), body, origin, axes }).unwrap()
}

fn joint(b: &mut ModelBuilder, name: &str, kind: JointKind, i: MarkerId, j: MarkerId) -> JointId {
    b.add_joint(Joint { name: name.into(), kind, marker_i: i, marker_j: j }).unwrap()
}

fn rotational_spring(b: &mut ModelBuilder, joint: JointId, stiffness: f64) {
    let kind = ForceKind::RotationalSpringDamper { joint, stiffness, damping: 0.0, free_angle: 0.0, actuator: None };
    b.add_force(ForceElement { name: "spring".into(), kind }).unwrap();
}

fn rot_z(angle: f64) -> Mat3 {
    EulerParameters::from_axis_angle(&Vec3::new(0.0, 0.0, 1.0), angle).unwrap().rotation_matrix()
}

fn solve(model: &Model) -> (State, EquilibriumReport, Data) {
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let report = static_equilibrium(model, &mut data, &mut state, 0.0, &EquilibriumSettings::default()).unwrap();
    (state, report, data)
}

fn origin(model: &Model, state: &State, b: BodyId) -> Vec3 {
    let qo = model.layout().q_range(b).unwrap().start;
    Vec3::new(state.q[qo], state.q[qo + 1], state.q[qo + 2])
}

/// The root of `f` by Newton's method with a numerical derivative (for the closed forms).
fn root(f: impl Fn(f64) -> f64, mut x: f64) -> f64 {
    for _ in 0..50 {
        let h = 1e-7;
        x -= f(x) / ((f(x + h) - f(x - h)) / (2.0 * h));
    }
    x
}

/// Sum over every joint side of the reaction forces plus the weights: zero at an equilibrium whose only
/// other loads are internal (springs between joints' bodies and ground act as torques here).
fn force_balance(model: &Model, report: &EquilibriumReport) -> Vec3 {
    let mut sum = model.bodies().iter().map(|b| model.gravity() * b.mass).sum::<Vec3>();
    for reaction in &report.reactions {
        for side in &reaction.sides {
            sum += Vec3::from(side.force);
        }
    }
    sum
}

/// A rod of 2 kg, centre of mass 0.6 m from a hinge about z, on a rotational spring of 40 N m/rad free
/// at the horizontal: it sags to `k θ + m g L cos θ = 0`.
#[test]
fn a_pendulum_on_a_rotational_spring_sags_to_the_closed_form_angle() {
    let (m, l, k) = (2.0, 0.6, 40.0);
    let mut b = ModelBuilder::new("spring pendulum").gravity(Vec3::new(0.0, -G, 0.0));
    let rod = b.add_body(body("rod", m, Vec3::new(l, 0.0, 0.0), Vec3::zeros(), 0.0)).unwrap();
    let pivot = marker(&mut b, "pivot", BodyRef::Ground, Vec3::zeros(), Mat3::identity());
    let hinge = marker(&mut b, "hinge", BodyRef::Body(rod), Vec3::zeros(), Mat3::identity());
    let j = joint(&mut b, "hinge", JointKind::Revolute, pivot, hinge);
    rotational_spring(&mut b, j, k);
    let model = b.build().unwrap();
    let (state, report, _) = solve(&model);
    let expected = root(|t| k * t + m * G * l * t.cos(), 0.0);
    let p = state.q[3..7].to_vec();
    let angle = 2.0 * p[3].atan2(p[0]);
    assert!((angle - expected).abs() < 1e-9, "angle {angle} rad, closed form {expected} rad");
    assert!(report.force_residual <= report.force_tolerance && report.iterations < 10, "{report:?}");
    assert_eq!((report.method, report.unstable_directions), (EquilibriumMethod::Newton, 0));
    assert!(force_balance(&model, &report).norm() < 1e-9);
}

/// A 3 kg slider on a vertical guide hangs on a 500 N/m spring of free length 0.2 m: it stretches by
/// `m g / k`.
#[test]
fn a_slider_on_a_spring_stretches_by_its_weight_over_the_stiffness() {
    let (m, k, free) = (3.0, 500.0, 0.2);
    let mut b = ModelBuilder::new("spring slider").gravity(Vec3::new(0.0, -G, 0.0));
    let slider = b.add_body(body("slider", m, Vec3::zeros(), Vec3::new(0.0, -free, 0.0), 0.0)).unwrap();
    let vertical = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0); // z_i along global y
    let guide = marker(&mut b, "guide", BodyRef::Ground, Vec3::zeros(), vertical);
    let carriage = marker(&mut b, "carriage", BodyRef::Body(slider), Vec3::zeros(), vertical);
    joint(&mut b, "guide", JointKind::Translational, guide, carriage);
    let kind = ForceKind::TranslationalSpringDamper { marker_i: guide, marker_j: carriage, stiffness: k, damping: 0.0, free_length: free, actuator: None };
    b.add_force(ForceElement { name: "spring".into(), kind }).unwrap();
    let model = b.build().unwrap();
    let (state, report, _) = solve(&model);
    let y = origin(&model, &state, slider).y;
    assert!((y + free + m * G / k).abs() < 1e-10, "y = {y} m, closed form {} m", -free - m * G / k);
    // The guide's reaction carries what the spring does not: nothing along the guide, the weight's
    // share across it is zero too.
    let spring = m * G;
    let reaction = Vec3::from(report.reactions[0].sides[0].force);
    assert!(reaction.norm() < 1e-9 * spring, "{reaction:?}");
}

/// A parallelogram four-bar (crank and rocker 0.4 m, 0.5 kg each; coupler 0.8 m, 2 kg) with a
/// rotational spring of 30 N m/rad at the crank, free at 60°: by virtual work the coupler translates
/// with the crank's tip, so `k (θ − 60°) + (M + m) g a cos θ = 0`; the reactions at the two ground
/// pivots carry the whole weight.
#[test]
fn a_parallelogram_four_bar_settles_where_virtual_work_says() {
    let (a, d, m, big_m, k) = (0.4, 0.8, 0.5, 2.0, 30.0);
    let start = 60f64.to_radians();
    let mut b = ModelBuilder::new("four-bar").gravity(Vec3::new(0.0, -G, 0.0));
    let tip = Vec3::new(a * start.cos(), a * start.sin(), 0.0);
    let crank = b.add_body(body("crank", m, Vec3::new(a / 2.0, 0.0, 0.0), Vec3::zeros(), start)).unwrap();
    let coupler = b.add_body(body("coupler", big_m, Vec3::new(0.3, 0.0, 0.0), tip, 0.0)).unwrap();
    let rocker = b.add_body(body("rocker", m, Vec3::new(a / 2.0, 0.0, 0.0), Vec3::new(d, 0.0, 0.0), start)).unwrap();
    let i = Mat3::identity();
    let ga = marker(&mut b, "ga", BodyRef::Ground, Vec3::zeros(), i);
    let ca = marker(&mut b, "ca", BodyRef::Body(crank), Vec3::zeros(), rot_z(-start));
    let cb = marker(&mut b, "cb", BodyRef::Body(crank), Vec3::new(a, 0.0, 0.0), i);
    let kb = marker(&mut b, "kb", BodyRef::Body(coupler), Vec3::zeros(), i);
    let kc = marker(&mut b, "kc", BodyRef::Body(coupler), Vec3::new(d, 0.0, 0.0), i);
    let rc = marker(&mut b, "rc", BodyRef::Body(rocker), Vec3::new(a, 0.0, 0.0), i);
    let rd = marker(&mut b, "rd", BodyRef::Body(rocker), Vec3::zeros(), i);
    let gd = marker(&mut b, "gd", BodyRef::Ground, Vec3::new(d, 0.0, 0.0), i);
    let pivot = joint(&mut b, "A", JointKind::Revolute, ga, ca);
    joint(&mut b, "B", JointKind::Revolute, cb, kb);
    joint(&mut b, "C", JointKind::Revolute, kc, rc);
    joint(&mut b, "D", JointKind::Revolute, gd, rd);
    rotational_spring(&mut b, pivot, k);
    let model = b.build().unwrap();
    let (state, report, _) = solve(&model);
    let weight = (big_m + m) * G;
    let expected = root(|t| k * (t - start) + weight * a * t.cos(), start);
    let b_point = origin(&model, &state, coupler);
    let angle = b_point.y.atan2(b_point.x);
    assert!((angle - expected).abs() < 1e-9, "crank at {angle} rad, virtual work {expected} rad");
    assert_eq!(report.assembly.redundant.len(), 3);
    let balance = force_balance(&model, &report);
    assert!(balance.norm() < 1e-9 * weight, "reactions + weight = {balance:?}");
}

/// A spherical pendulum released horizontal: gravity has no stiffness there, so Newton's method cannot
/// start and the relaxation brings it down; it hangs straight below the pivot, its spin about the rod
/// is neutral (no load along it), and the pivot carries its weight.
#[test]
fn a_spherical_pendulum_released_horizontal_hangs_below_its_pivot() {
    let (m, l) = (1.5, 0.8);
    let mut b = ModelBuilder::new("spherical pendulum").gravity(Vec3::new(0.0, -G, 0.0));
    let bob = b.add_body(body("bob", m, Vec3::zeros(), Vec3::new(l, 0.0, 0.0), 0.0)).unwrap();
    let pivot = marker(&mut b, "pivot", BodyRef::Ground, Vec3::zeros(), Mat3::identity());
    let socket = marker(&mut b, "socket", BodyRef::Body(bob), Vec3::new(-l, 0.0, 0.0), Mat3::identity());
    joint(&mut b, "ball", JointKind::Spherical, pivot, socket);
    let model = b.build().unwrap();
    let (state, report, _) = solve(&model);
    let r = origin(&model, &state, bob);
    assert!((r - Vec3::new(0.0, -l, 0.0)).norm() < 1e-9, "bob at {r:?}");
    assert_eq!(report.method, EquilibriumMethod::Relaxation);
    assert_eq!((report.neutral_directions, report.unstable_directions), (1, 0), "{report:?}");
    let pull = Vec3::from(report.reactions[0].sides[0].force);
    assert!((pull - Vec3::new(0.0, m * G, 0.0)).norm() < 1e-9 * m * G, "{pull:?}");
    assert!(state.v.iter().all(|v| *v == 0.0));
}

/// A slider on a horizontal guide pushed by a constant 5 N along the guide, and a free body under
/// gravity, have no equilibrium: the error names the body and the direction.
#[test]
fn a_free_motion_under_load_is_named_with_its_body_and_direction() {
    let mut b = ModelBuilder::new("pushed slider").gravity(Vec3::new(0.0, -G, 0.0));
    let slider = b.add_body(body("slider", 2.0, Vec3::zeros(), Vec3::zeros(), 0.0)).unwrap();
    let along_x = Mat3::new(0.0, 0.0, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0); // z_i along global x
    let guide = marker(&mut b, "guide", BodyRef::Ground, Vec3::zeros(), along_x);
    let carriage = marker(&mut b, "carriage", BodyRef::Body(slider), Vec3::zeros(), along_x);
    joint(&mut b, "guide", JointKind::Translational, guide, carriage);
    let components = [Expression::constant(5.0), Expression::constant(0.0), Expression::constant(0.0)];
    let kind = ForceKind::AppliedForce { marker: carriage, components, frame: ForceFrame::Global };
    b.add_force(ForceElement { name: "push".into(), kind }).unwrap();
    let model = b.build().unwrap();
    let message = equilibrium_error(&model);
    assert!(message.contains("body 'slider': translation along +x"), "{message}");
    assert!(message.contains("unbalanced generalized force 5.000e0"), "{message}");

    let mut b = ModelBuilder::new("falling ball").gravity(Vec3::new(0.0, 0.0, -G));
    b.add_body(body("ball", 0.5, Vec3::zeros(), Vec3::zeros(), 0.3)).unwrap();
    let message = equilibrium_error(&b.build().unwrap());
    assert!(message.contains("body 'ball': translation along -z"), "{message}");
    assert!(!message.contains("rotation"), "{message}");
}

fn equilibrium_error(model: &Model) -> String {
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let err = static_equilibrium(model, &mut data, &mut state, 0.0, &EquilibriumSettings::default()).unwrap_err();
    assert!(matches!(err, EquilibriumError::FreeMotion { .. }), "{err}");
    err.to_string()
}
