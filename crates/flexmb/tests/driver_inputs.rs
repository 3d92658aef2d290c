//! Drivers as inputs of the state-space model (`NAME`, `NAME.rate`, `NAME.acceleration`): a mass on a
//! spring-damper whose base is driven and a pendulum on a driven cart against their closed-form
//! transfer functions, and a double pendulum with a driven shoulder against finite differences of the
//! forward dynamics with the driver's motion offset.

mod support;

use std::sync::Arc;

use flexmb::analysis::{linear_model, state_space, AccelerationSolver, OperatingPointChoice, StateSpace};
use flexmb::force::{ForceElement, ForceKind};
use flexmb::function::{TimeFunction, UserMotion};
use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::measure::{Measure, MeasureKind};
use flexmb::model::{BodyRef, Model, ModelBuilder};
use flexmb::Data;
use nalgebra::Complex;
use support::*;

fn zero() -> TimeFunction {
    TimeFunction::parse("0").unwrap()
}

/// The state-space model at the initial state for `inputs` and `outputs`.
fn linear_state_space(model: &Model, inputs: &[&str], outputs: &[&str]) -> StateSpace {
    let model = Arc::new(model.clone());
    let mut linear = linear_model(&model, OperatingPointChoice::Initial, &settings(1.0, 0.1, 1e-8)).unwrap();
    let names = |x: &[&str]| x.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let point = &mut linear.point;
    state_space(&model, &mut point.data, &point.state, &point.accelerations, &linear.reduced, &names(inputs), &names(outputs)).unwrap()
}

/// `y(s)/u(s)` of a one-degree-of-freedom state space whose three inputs are a driver's offset, rate and
/// acceleration (`u`, `s u`, `s² u`): `C (sI − A)⁻¹ (B_u + s B_u̇ + s² B_ü) + D_u + s D_u̇`.
fn driver_transfer(ss: &StateSpace, output: usize, s: Complex<f64>) -> Complex<f64> {
    assert_eq!(ss.a.nrows(), 2, "one degree of freedom");
    let b = |r: usize| ss.b[(r, 0)] + s * ss.b[(r, 1)] + s * s * ss.b[(r, 2)];
    let (a10, a11) = (ss.a[(1, 0)], ss.a[(1, 1)]);
    // ż = w + b0, ẇ = a10 z + a11 w + b1 with b0 = 0: z = b1 / (s² − a11 s − a10).
    assert!(b(0).norm() == 0.0);
    let z = b(1) / (s * s - a11 * s - a10);
    ss.c[(output, 0)] * z + ss.c[(output, 1)] * s * z + ss.d[(output, 0)] + s * ss.d[(output, 1)] + s * s * ss.d[(output, 2)]
}

/// A base on a translational joint to ground, its displacement driven (`base_drive`), and a mass on a
/// translational joint to the base, held by a spring-damper `(k, c)` from the base (all along global
/// z, no gravity): `m z̈ + c (ż − u̇) + k (z − u) = 0`, so that the mass's position follows the base by
/// `(c s + k) / (m s² + c s + k)` and the spring's stretch by `−m s² / (m s² + c s + k)` (errors relative to
/// the value, or to the unit static gain where the value is smaller: the stretch's is zero at 0 Hz).
#[test]
fn a_mass_on_a_driven_base_follows_the_closed_form_transfer_function() {
    let (m, mb, k, c, gap) = (2.0, 5.0, 800.0, 6.0, 0.5);
    let mut b = ModelBuilder::new("base-excited mass");
    let id = EulerParameters::identity();
    let inertia = Mat3::identity() * 0.01;
    let base = b.add_body(rigid("base", mb, Vec3::zeros(), inertia, Vec3::zeros(), id, None, None)).unwrap();
    let mass = b.add_body(rigid("mass", m, Vec3::zeros(), inertia, Vec3::new(0.0, 0.0, gap), id, None, None)).unwrap();
    let g0 = marker(&mut b, "g0", BodyRef::Ground, Vec3::zeros());
    let b0 = marker(&mut b, "b0", BodyRef::Body(base), Vec3::zeros());
    let m0 = marker(&mut b, "m0", BodyRef::Body(mass), Vec3::new(0.0, 0.0, -gap));
    let mc = marker(&mut b, "mc", BodyRef::Body(mass), Vec3::zeros());
    joint(&mut b, "rail", JointKind::Translational, g0, b0);
    joint(&mut b, "base_drive", JointKind::DisplacementDriver { function: zero() }, g0, b0);
    let slide = joint(&mut b, "slide", JointKind::Translational, b0, m0);
    let kind = ForceKind::TranslationalSpringDamper { marker_i: b0, marker_j: mc, stiffness: k, damping: c, free_length: gap, actuator: None };
    b.add_force(ForceElement { name: "mount".into(), kind }).unwrap();
    b.add_measure(Measure { name: "height".into(), kind: MeasureKind::Position(mc, 2) }).unwrap();
    b.add_measure(Measure { name: "stretch".into(), kind: MeasureKind::JointDisplacement(slide) }).unwrap();
    let model = b.build().unwrap();
    let ss = linear_state_space(&model, &["base_drive", "base_drive.rate", "base_drive.acceleration"], &["height", "stretch"]);
    let mut worst = 0.0_f64;
    for f in [0.0, 0.5, 2.0, 3.1, 3.2, 10.0, 50.0] {
        let s = Complex::new(0.0, std::f64::consts::TAU * f);
        let den = m * s * s + c * s + k;
        let exact = [(c * s + k) / den, -m * s * s / den];
        for (o, e) in exact.iter().enumerate() {
            let found = driver_transfer(&ss, o, s);
            worst = worst.max((found - e).norm() / e.norm().max(1.0));
        }
    }
    eprintln!("base-excited mass: largest error of the transfer functions {worst:.1e} (relative, or of the unit static gain where smaller)");
    assert!(worst < 1e-8, "{worst:.1e}");
}

/// A pendulum (`L`, `m`, `I` about its centre) hanging from a cart whose position along global x is
/// driven: `(I + m L²) θ̈ + m g L θ = −m L ü`, so that the joint angle follows the cart by
/// `−m L s² / ((I + m L²) s² + m g L)`; the cart's offset and rate have no term at rest.
#[test]
fn a_pendulum_on_a_driven_cart_follows_the_closed_form_transfer_function() {
    let (l, m, ic, g) = (0.8, 1.5, 0.02, 9.81);
    let mut b = ModelBuilder::new("pendulum on a cart").gravity(Vec3::new(0.0, -g, 0.0));
    let id = EulerParameters::identity();
    let cart = b.add_body(rigid("cart", 4.0, Vec3::zeros(), Mat3::identity() * 0.1, Vec3::zeros(), id, None, None)).unwrap();
    let bob = b.add_body(rigid("bob", m, Vec3::zeros(), Mat3::identity() * ic, Vec3::new(0.0, -l, 0.0), id, None, None)).unwrap();
    let along_x = frame_with_z(Vec3::x());
    let g0 = marker_with_axes(&mut b, "g0", BodyRef::Ground, Vec3::zeros(), along_x);
    let c0 = marker_with_axes(&mut b, "c0", BodyRef::Body(cart), Vec3::zeros(), along_x);
    let pivot_cart = marker(&mut b, "pivot_cart", BodyRef::Body(cart), Vec3::zeros());
    let pivot_bob = marker(&mut b, "pivot_bob", BodyRef::Body(bob), Vec3::new(0.0, l, 0.0));
    joint(&mut b, "rail", JointKind::Translational, g0, c0);
    joint(&mut b, "cart_drive", JointKind::DisplacementDriver { function: zero() }, g0, c0);
    let pivot = joint(&mut b, "pivot", JointKind::Revolute, pivot_cart, pivot_bob);
    b.add_measure(Measure { name: "swing".into(), kind: MeasureKind::JointAngle(pivot) }).unwrap();
    let model = b.build().unwrap();
    let ss = linear_state_space(&model, &["cart_drive", "cart_drive.rate", "cart_drive.acceleration"], &["swing"]);
    let mut worst = 0.0_f64;
    for f in [0.1, 0.5, 0.7, 2.0, 20.0] {
        let s = Complex::new(0.0, std::f64::consts::TAU * f);
        let exact = -m * l * s * s / ((ic + m * l * l) * s * s + m * g * l);
        worst = worst.max((driver_transfer(&ss, 0, s) - exact).norm() / exact.norm());
    }
    eprintln!("pendulum on a driven cart: largest relative error of the transfer function {worst:.1e}");
    assert!(worst < 1e-8, "{worst:.1e}");
}

/// A planar double pendulum hanging at rest, its shoulder angle driven and its elbow held by a
/// rotational spring-damper: the columns of `B` for the driver's offset, rate and acceleration against
/// central differences of the forward dynamics `v̇(q, v)` with the driver's prescribed motion offset by
/// `±h` in its value, rate or acceleration (the positions and velocities moved with it along the
/// particular motion, the independent coordinates held).
#[test]
fn driver_input_columns_match_finite_differences_of_the_forward_dynamics() {
    let (g, l1) = (9.81, 0.6);
    let mut b = ModelBuilder::new("driven double pendulum").gravity(Vec3::new(0.0, -g, 0.0));
    let id = EulerParameters::identity();
    let link1 = b.add_body(rigid("link1", 1.2, Vec3::zeros(), Mat3::identity() * 0.03, Vec3::new(0.0, -0.25, 0.0), id, None, None)).unwrap();
    let link2 = b.add_body(rigid("link2", 0.7, Vec3::zeros(), Mat3::identity() * 0.015, Vec3::new(0.0, -l1 - 0.3, 0.0), id, None, None)).unwrap();
    let o = marker(&mut b, "o", BodyRef::Ground, Vec3::zeros());
    let top1 = marker(&mut b, "top1", BodyRef::Body(link1), Vec3::new(0.0, 0.25, 0.0));
    let end1 = marker(&mut b, "end1", BodyRef::Body(link1), Vec3::new(0.0, 0.25 - l1, 0.0));
    let top2 = marker(&mut b, "top2", BodyRef::Body(link2), Vec3::new(0.0, 0.3, 0.0));
    joint(&mut b, "shoulder", JointKind::Revolute, o, top1);
    joint(&mut b, "shoulder_drive", JointKind::AngleDriver { function: zero() }, o, top1);
    let elbow = joint(&mut b, "elbow", JointKind::Revolute, end1, top2);
    let kind = ForceKind::RotationalSpringDamper { joint: elbow, stiffness: 3.0, damping: 0.4, free_angle: 0.0, actuator: None };
    b.add_force(ForceElement { name: "elbow_spring".into(), kind }).unwrap();
    let model = b.build().unwrap();
    let ss = linear_state_space(&model, &["shoulder_drive", "shoulder_drive.rate", "shoulder_drive.acceleration"], &[]);
    let arc = Arc::new(model.clone());
    let mut linear = linear_model(&arc, OperatingPointChoice::Initial, &settings(1.0, 0.1, 1e-8)).unwrap();
    let point = &mut linear.point;
    let lin = flexmb::analysis::linearize(&model, &mut point.data, &point.state, &point.accelerations).unwrap();
    let names = vec!["shoulder_drive".to_string()];
    let (reduced, drivers) = flexmb::analysis::driver_inputs(&model, &mut point.data, &point.state, &point.accelerations, &lin, &names).unwrap();
    let n = reduced.degrees_of_freedom();
    let state = &point.state;
    let h = 1e-6;
    let scale = (0..2 * n).flat_map(|i| (0..3).map(move |j| (i, j))).map(|(i, j)| ss.b[(i, j)].abs()).fold(0.0, f64::max);
    let mut worst = 0.0_f64;
    for derivative in 0..3 {
        let zdd = |sign: f64| -> Vec<f64> {
            let mut law = [0.0; 3];
            law[derivative] = sign * h;
            let mut moved = model.clone();
            moved.set_driver_motion("shoulder_drive", UserMotion::new("offset", Arc::new(move |_t: f64| Ok(law)))).unwrap();
            let p: Vec<f64> = (0..model.layout().nv).map(|r| drivers.motion[(r, 0)] * sign * h).collect();
            let q = if derivative == 0 { flexmb::analysis::displaced_positions(&model, &state.q, &p).unwrap() } else { state.q.clone() };
            let v = if derivative == 1 { p.clone() } else { state.v.clone() };
            let mut data = Data::new(&moved);
            let mut solver = AccelerationSolver::new(&moved);
            let acc = solver.solve(&moved, &mut data, state.t, &q, &v, &state.active).unwrap();
            // Planar: the rotations are about z in body and global axes alike.
            reduced.independent.coordinates.iter().map(|&c| acc.vdot[c]).collect()
        };
        let (plus, minus) = (zdd(1.0), zdd(-1.0));
        for i in 0..n {
            let fd = (plus[i] - minus[i]) / (2.0 * h);
            worst = worst.max((fd - ss.b[(n + i, derivative)]).abs() / scale);
        }
    }
    eprintln!("driver inputs against finite differences of the forward dynamics: largest difference {worst:.1e} of B's largest entry");
    assert!(worst < 1e-6, "{worst:.1e}");
    assert!((0..3).all(|j| ss.b[(2 * n - 1, j)].abs() > 1e-3 * scale), "every input acts: {:?}", ss.b);
}
