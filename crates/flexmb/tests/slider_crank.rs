//! Slider-crank driven at constant crank speed: a fully constrained mechanism whose slider position and
//! velocity have a closed form,
//!
//! ```text
//! x(θ) = r cos θ + sqrt(l² − r² sin² θ),   ẋ = −ω r sin θ (1 + r cos θ / sqrt(l² − r² sin² θ)),   θ = ω t.
//! ```
//!
//! Joints as in `models/slider_crank.toml`, chosen so that the 3D loop has no redundant equations:
//! revolute crank–ground (5) + angle driver (1) + spherical crank–rod (3) + universal rod–slider (4) +
//! translational slider–ground (5) = 18 = 3 bodies × 6, so 0 degrees of freedom.

mod support;

use flexmb::function::TimeFunction;
use flexmb::joint::JointKind;
use flexmb::math::Vec3;
use flexmb::measure::{Measure, MeasureKind};
use flexmb::model::{Model, ModelBuilder, OutputKind};
use std::f64::consts::PI;
use support::*;

const CRANK: f64 = 0.1; // m, r
const ROD: f64 = 0.3; // m, l
const SPEED: f64 = 2.0 * PI; // rad/s, ω (1 rev/s)

fn slider_crank() -> Model {
    let mut b = ModelBuilder::new("slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    let SliderCrank { crank_joint, slide, pivot_ground, pivot, slider_pin, .. } =
        slider_crank_linkage(&mut b, CRANK, ROD, None);
    joint(
        &mut b,
        "crank_motion",
        JointKind::AngleDriver { function: TimeFunction::parse("2*PI*t").unwrap() },
        pivot_ground,
        pivot,
    );
    let x = b.add_measure(Measure { name: "slider_position".into(), kind: MeasureKind::JointDisplacement(slide) }).unwrap();
    let v = b.add_measure(Measure { name: "slider_velocity".into(), kind: MeasureKind::JointVelocity(slide) }).unwrap();
    let angle = b.add_measure(Measure { name: "crank_angle".into(), kind: MeasureKind::JointAngle(crank_joint) }).unwrap();
    b.add_output("x", OutputKind::Measure(x)).unwrap();
    b.add_output("v", OutputKind::Measure(v)).unwrap();
    b.add_output("angle", OutputKind::Measure(angle)).unwrap();
    b.add_output("pin", OutputKind::MarkerPosition(slider_pin)).unwrap();
    b.build().unwrap()
}

fn exact_position(theta: f64) -> f64 {
    CRANK * theta.cos() + (ROD * ROD - (CRANK * theta.sin()).powi(2)).sqrt()
}

fn exact_velocity(theta: f64) -> f64 {
    let root = (ROD * ROD - (CRANK * theta.sin()).powi(2)).sqrt();
    -SPEED * CRANK * theta.sin() * (1.0 + CRANK * theta.cos() / root)
}

#[test]
fn slider_follows_the_closed_form_over_two_revolutions() {
    let model = slider_crank();
    let run = run(&model, &settings(2.0, 0.002, 1e-8));
    let assembly = run.report.assembly.as_ref().unwrap();
    assert!(assembly.redundant.is_empty(), "no redundant equations expected, got {:?}", assembly.redundant);
    assert_eq!(assembly.degrees_of_freedom, 0, "a driven slider-crank has 0 degrees of freedom");

    let (x, v, angle, pin) = (run.col("x"), run.col("v"), run.col("angle"), run.vec3("pin"));
    let n = run.t.len();
    assert_eq!(n, 1001, "one frame every 2 ms over 2 s, both ends included");
    let theta: Vec<f64> = run.t.iter().map(|t| SPEED * t).collect();
    let angle_err = max_over(n, |k| (angle[k] - theta[k]).abs());
    let pos_err = max_over(n, |k| (x[k] - exact_position(theta[k])).abs());
    let pin_err = max_over(n, |k| (pin[k] - Vec3::new(exact_position(theta[k]), 0.0, 0.0)).norm());
    let vel_err = max_over(n, |k| (v[k] - exact_velocity(theta[k])).abs());
    eprintln!(
        "slider-crank: max |θ − ωt| {angle_err:.2e} rad, max |x − x(θ)| {pos_err:.2e} m, pin {pin_err:.2e} m, \
         max |ẋ − ẋ(θ)| {vel_err:.2e} m/s over {n} frames ({} steps)",
        run.report.stats.steps
    );
    assert!(angle_err < 1e-8, "crank angle departs from the driver 2πt by {angle_err:e} rad");
    assert!(pos_err < 1e-6 * ROD, "slider position departs from the closed form by {pos_err:e} m > 1e-6 l");
    assert!(pin_err < 1e-6 * ROD, "slider pin leaves (x(θ), 0, 0) by {pin_err:e} m > 1e-6 l");
    assert!(
        vel_err < 1e-6 * ROD * SPEED,
        "slider velocity departs from the derivative of the closed form by {vel_err:e} m/s > 1e-6 l ω"
    );
}
