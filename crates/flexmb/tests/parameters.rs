//! Parameters: a value declared on the model, read by a force law's expression, changed between the
//! steps of a running simulation; the motion follows the new value from the step it was changed at,
//! and the change travels with a checkpoint.

mod support;

use std::sync::Arc;

use flexmb::analysis::{OutputTable, Simulation, SimulationFailure};
use flexmb::force::{ForceElement, ForceFrame, ForceKind};
use flexmb::function::Expression;
use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, Model, ModelBuilder, OutputKind};
use support::{frame_with_z, joint, marker, marker_with_axes, rigid, settings};

/// A 1 kg slider on a translational joint along global x, no gravity, pushed along x by an applied
/// force equal to the parameter `push` (initially 0 N); its position and velocity as outputs.
fn pushed_slider() -> Model {
    let mut b = ModelBuilder::new("pushed slider");
    let slider = b.add_body(rigid(
        "slider",
        1.0,
        Vec3::zeros(),
        Mat3::identity() * 1e-2,
        Vec3::zeros(),
        EulerParameters::identity(),
        None,
        None,
    ))
    .unwrap();
    let guide = marker_with_axes(&mut b, "guide", BodyRef::Ground, Vec3::zeros(), frame_with_z(Vec3::x()));
    let runner = marker_with_axes(&mut b, "runner", BodyRef::Body(slider), Vec3::zeros(), frame_with_z(Vec3::x()));
    joint(&mut b, "slide", JointKind::Translational, guide, runner);
    let push = b.add_parameter("push", 0.0).unwrap();
    let center = marker(&mut b, "center", BodyRef::Body(slider), Vec3::zeros());
    let component = |text: &str| Expression::parse(text, &|n| (n == "push").then_some(push)).unwrap();
    b.add_force(ForceElement {
        name: "push".into(),
        kind: ForceKind::AppliedForce {
            marker: center,
            components: [component("push"), component("0"), component("0")],
            frame: ForceFrame::Global,
        },
    })
    .unwrap();
    b.add_output("slider", OutputKind::MarkerPosition(center)).unwrap();
    b.add_output("speed", OutputKind::MarkerVelocity(center)).unwrap();
    b.build().unwrap()
}

/// At rest until the push is set to 2 N at `t_s`, then `x = (t − t_s)²`, `ẋ = 2 (t − t_s)`.
#[test]
fn a_force_follows_its_parameter_changed_during_the_run() {
    let model = Arc::new(pushed_slider());
    let mut simulation = Simulation::new(model.clone(), settings(1.0, 0.05, 1e-9)).unwrap();
    let mut table = OutputTable::new(&model);
    assert_eq!(simulation.parameter("push"), Some(0.0));
    simulation.advance_to(0.5, &mut table).unwrap();
    let t_s = simulation.time();
    simulation.set_parameter("push", 2.0).unwrap();
    assert_eq!(simulation.parameter("push"), Some(2.0));
    simulation.advance_to(1.0, &mut table).unwrap();
    assert!(simulation.is_finished());
    let (t, x, v) = (table.column("t").unwrap(), table.column("slider.x").unwrap(), table.column("speed.x").unwrap());
    assert_eq!(t.len(), 21);
    for i in 0..t.len() {
        let elapsed = (t[i] - t_s).max(0.0);
        let (x_exact, v_exact) = (elapsed * elapsed, 2.0 * elapsed);
        assert!((x[i] - x_exact).abs() < 1e-6 && (v[i] - v_exact).abs() < 1e-6, "t = {}: x {} v {}", t[i], x[i], v[i]);
    }
    let q = simulation.positions();
    assert!((q[0] - (1.0 - t_s).powi(2)).abs() < 1e-7, "x(1) = {}", q[0]);
}

/// A run whose parameter was changed, checkpointed later and resumed, goes on with the changed value:
/// it ends where the run that was never stopped ends.
#[test]
fn a_changed_parameter_travels_with_the_checkpoint() {
    let model = Arc::new(pushed_slider());
    let s = settings(1.0, 0.05, 1e-9);
    let sink = &mut |_: &flexmb::analysis::OutputFrame| {};
    let mut reference = Simulation::new(model.clone(), s).unwrap();
    reference.advance_to(0.5, sink).unwrap();
    reference.set_parameter("push", 2.0).unwrap();
    reference.advance_to(1.0, sink).unwrap();

    let mut first = Simulation::new(model.clone(), s).unwrap();
    first.advance_to(0.5, sink).unwrap();
    first.set_parameter("push", 2.0).unwrap();
    first.advance_to(0.7, sink).unwrap();
    let checkpoint = first.checkpoint().unwrap();
    assert_eq!(checkpoint.parameters, vec![2.0]);
    let mut second = Simulation::resume(model, s, &checkpoint).unwrap();
    assert_eq!(second.parameter("push"), Some(2.0));
    second.advance_to(1.0, sink).unwrap();
    assert_eq!(second.positions(), reference.positions());
    assert_eq!(second.velocities(), reference.velocities());
    assert_eq!(second.stats(), reference.stats());
}

/// An unknown parameter or a non-finite value is refused with a message that names what the model has.
#[test]
fn unknown_parameters_and_non_finite_values_are_refused() {
    let model = Arc::new(pushed_slider());
    let mut simulation = Simulation::new(model, settings(1.0, 0.05, 1e-9)).unwrap();
    let error = simulation.set_parameter("pull", 1.0).unwrap_err();
    assert_eq!(error, SimulationFailure::Invalid("the model has no parameter 'pull': it has push".into()));
    let error = simulation.set_parameter("push", f64::NAN).unwrap_err();
    assert_eq!(error.to_string(), "parameter 'push' must be finite, got NaN");
    assert_eq!(simulation.parameter("push"), Some(0.0));
}
