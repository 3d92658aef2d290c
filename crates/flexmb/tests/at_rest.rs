//! A body held at rest by a fixed joint in a skewed pose, with nothing acting on it: every method steps
//! to the end. The BDF and the generalized-α method rejected every step down to h = 1e-307 before:
//! their Newton increments were round-off (4e-8 of the tolerance) whose ratio, above 1, read as
//! divergence (a model the fuzz test generated).

mod support;

use flexmb::analysis::SimulationSettings;
use flexmb::integrate::{AdamsConfig, Method};
use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3, Vec3, Vec4};
use flexmb::model::{BodyRef, Model, ModelBuilder};
use support::*;

fn axes(axis: Vec3, angle: f64) -> Mat3 {
    EulerParameters::from_axis_angle(&axis, angle).unwrap().rotation_matrix()
}

fn fixed_body() -> Model {
    let mut b = ModelBuilder::new("fixed body");
    let p = Vec4::new(-0.3781722610911133, -0.5671838013291985, 0.6904452907070933, -0.24201978636341367);
    let body = b.add_body(rigid(
        "b0",
        0.2384204050316397,
        Vec3::zeros(),
        Mat3::from_diagonal(&Vec3::new(0.005168228502918822, 0.010880919438851512, 0.007705092118374803)),
        Vec3::new(0.3283822650601671, 0.6095749067782232, 0.09115114459885776),
        EulerParameters(p.normalize()),
        None,
        None,
    )).unwrap();
    let on_ground = marker_with_axes(
        &mut b,
        "k0",
        BodyRef::Ground,
        Vec3::new(0.5450740618857665, 0.15584613915113488, 0.2928470536238055),
        axes(Vec3::new(-0.08357037319576369, -0.993359692195889, -0.0790728439124927), 2.0548389197616252),
    );
    let on_body = marker_with_axes(
        &mut b,
        "k1",
        BodyRef::Body(body),
        Vec3::new(0.41772232765833983, -0.2989140872487471, 0.17223470765571627),
        axes(Vec3::new(-0.8325062974177718, 0.02085579506551589, 0.5536228866041736), 1.5176438499700737),
    );
    joint(&mut b, "j0", JointKind::Fixed, on_ground, on_body);
    b.build().unwrap()
}

#[test]
fn a_body_at_rest_on_a_fixed_joint_steps_to_the_end_with_every_method() {
    let model = fixed_body();
    for method in [Method::default(), Method::generalized_alpha(0.9), Method::Adams(AdamsConfig::default())] {
        let settings = SimulationSettings { method, ..settings(0.05, 0.01, 1e-6) };
        let run = try_run(&model, &settings).unwrap_or_else(|(e, _)| panic!("{method:?}: {e}"));
        assert_eq!(run.report.t_reached, 0.05, "{method:?}");
        assert!(run.report.stats.steps <= 20 && run.report.stats.rejected_steps() == 0, "{method:?}: {:?}", run.report.stats);
    }
}
