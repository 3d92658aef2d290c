//! The promise of the tolerances (docs/accuracy.md): the global error of a run, against a tight
//! reference, stays within 10 tolerances and falls in proportion to them; tolerances finer than double
//! precision allows are raised to the finest attainable, with a warning.

mod support;

use flexmb::analysis::{SimulationSettings, WarningKind};
use flexmb::force::{ForceElement, ForceKind};
use flexmb::integrate::{AdamsConfig, Method, ToleranceSpan, Tolerances};
use flexmb::math::Vec3;
use flexmb::model::{BodyRef, Model, ModelBuilder, OutputKind};

/// A pendulum released at 1 rad (swinging through ±1 rad, period 2.2 s), its bob's position an output.
fn swinging_pendulum() -> Model {
    let mut b = support::pendulum(1.0, 1.0, 1e-3, 1.0, 9.81);
    let bob = b.find_marker("bob_centre").unwrap();
    b.add_output("bob", OutputKind::MarkerPosition(bob)).unwrap();
    b.build().unwrap()
}

/// The global error of docs/accuracy.md: the largest distance of the bob from the reference's over the
/// output times, over the largest distance of the reference's bob from the origin.
fn global_error(run: &support::Run, reference: &support::Run) -> f64 {
    let (mut worst, mut scale) = (0.0_f64, 0.0_f64);
    for (a, b) in run.rows.iter().zip(&reference.rows) {
        for k in 0..3 {
            worst = worst.max((a[k] - b[k]).abs());
            scale = scale.max(b[k].abs());
        }
    }
    worst / scale
}

/// Error per unit step over the run with `method` at rtol = atol = `tol`.
fn settings(method: Method, tol: f64) -> SimulationSettings {
    let mut settings = SimulationSettings { method, ..support::settings(3.0, 0.01, tol) };
    settings.tolerances.span = ToleranceSpan::Run;
    settings
}

/// The global errors of `method` at each tolerance against `reference`; asserts that each is within 10
/// tolerances and that from the first to the last tolerance the error falls at least as `tol^0.75`.
fn assert_proportional(name: &str, model: &Model, method: Method, tolerances: &[f64], reference: &support::Run) {
    let errors: Vec<(f64, f64)> =
        tolerances.iter().map(|&tol| (tol, global_error(&support::run(model, &settings(method, tol)), reference))).collect();
    assert_within_and_falling(name, &errors);
}

/// Each `(tolerance, global error)` within 10 tolerances, and from the first to the last the error
/// falling at least as `tol^0.75`.
fn assert_within_and_falling(name: &str, errors: &[(f64, f64)]) {
    eprintln!("{name}: (tolerance, global error) {errors:?}");
    for &(tol, error) in errors {
        assert!(error <= 10.0 * tol, "{name} at {tol:e}: global error {error:e}");
    }
    let ((tol_0, error_0), (tol_1, error_1)) = (errors[0], errors[errors.len() - 1]);
    let slope = (error_0 / error_1).log10() / (tol_0 / tol_1).log10();
    assert!(slope >= 0.75, "{name}: the error falls as tol^{slope:.2}");
}

/// A slider-crank (a closed loop) whose crank starts spinning at 12 rad/s, its slider on a spring, under
/// gravity, over 2 s: the slider pin's position is the output.
fn spinning_slider_crank() -> Model {
    let mut b = ModelBuilder::new("spinning slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    let linkage = support::slider_crank_linkage(&mut b, 0.1, 0.3, Some(Vec3::new(0.0, 0.0, 12.0)));
    let anchor = support::marker(&mut b, "anchor", BodyRef::Ground, Vec3::new(0.8, 0.0, 0.0));
    b.add_force(ForceElement {
        name: "spring".into(),
        kind: ForceKind::TranslationalSpringDamper {
            marker_i: anchor,
            marker_j: linkage.slider_pin,
            stiffness: 100.0,
            damping: 0.0,
            free_length: 0.4,
            actuator: None,
        },
    }).unwrap();
    b.add_output("pin", OutputKind::MarkerPosition(linkage.slider_pin)).unwrap();
    b.build().unwrap()
}

/// Over the run's span, BDF and Adams on the pendulum over three periods, rtol = atol from 1e-3
/// to 1e-10: the error stays within 10 tolerances at every one, and from the first to the last it falls
/// at least as `tol^0.75` (the classical error per step gave 0.8 on the 3-D slider-crank, with a
/// constant of 10³ to 10⁴). At 1e-9 and 1e-10 the BDF's steps are held by the floor of a step's share,
/// 1e-13 of the solution (docs/accuracy.md; with the 1e-12 floor of the other methods its error stopped
/// at about `N · 1e-12` below 1e-8).
#[test]
fn the_global_error_falls_in_proportion_to_the_tolerance() {
    let model = swinging_pendulum();
    let reference = support::run(&model, &settings(Method::Adams(AdamsConfig::default()), 1e-12));
    assert_proportional("bdf", &model, Method::default(), &[1e-3, 1e-4, 1e-6, 1e-8, 1e-9, 1e-10], &reference);
    let adams = Method::Adams(AdamsConfig::default());
    assert_proportional("adams", &model, adams, &[1e-3, 1e-4, 1e-6, 1e-8, 1e-10], &reference);
}

/// The same promise on a closed loop, the spinning slider-crank over 2 s, BDF and Adams 1e-3 to 1e-10:
/// within 10 tolerances, falling at least as `tol^0.75`.
#[test]
fn the_global_error_of_a_closed_loop_falls_in_proportion_to_the_tolerance() {
    let model = spinning_slider_crank();
    let on = |method: Method, tol: f64| SimulationSettings { t_end: 2.0, ..settings(method, tol) };
    let adams = Method::Adams(AdamsConfig::default());
    let reference = support::run(&model, &on(adams, 1e-12));
    for (name, method, tolerances) in
        [("bdf", Method::default(), &[1e-3, 1e-5, 1e-8, 1e-10][..]), ("adams", adams, &[1e-3, 1e-5, 1e-8, 1e-10][..])]
    {
        let errors: Vec<(f64, f64)> =
            tolerances.iter().map(|&tol| (tol, global_error(&support::run(&model, &on(method, tol)), &reference))).collect();
        assert_within_and_falling(&format!("slider-crank, {name}"), &errors);
    }
}

/// The generalized-α method, second order, holds the same promise on the pendulum from 1e-3 to 1e-6.
#[test]
fn the_generalized_alpha_methods_error_falls_in_proportion_too() {
    let model = swinging_pendulum();
    let reference = support::run(&model, &settings(Method::Adams(AdamsConfig::default()), 1e-12));
    assert_proportional("gen-alpha", &model, Method::generalized_alpha(0.9), &[1e-3, 1e-4, 1e-5, 1e-6], &reference);
}

/// A tolerance below what double precision delivers is raised to `Tolerances::FINEST`, the run says so
/// in a warning at its start, and it completes; one at the finest is taken as it is, silently. The same
/// for every method (generalized-α with each step the whole tolerance: over the run's span it raises a
/// tolerance below 1e-7 further, the next test).
#[test]
fn a_tolerance_below_double_precision_is_raised_with_a_warning() {
    let model = swinging_pendulum();
    for method in [Method::default(), Method::Adams(AdamsConfig::default()), Method::generalized_alpha(0.9)] {
        let short = |tol: f64| {
            let mut short = SimulationSettings { t_end: 0.2, ..settings(method, tol) };
            if matches!(method, Method::GeneralizedAlpha(_)) {
                short.tolerances.span = ToleranceSpan::Step;
            }
            short
        };
        let raised = support::run(&model, &short(1e-15));
        let warning = raised.report.warnings.iter().find(|w| w.kind == WarningKind::Tolerance).expect("a tolerance warning");
        assert_eq!(warning.t, 0.0);
        assert!(warning.message.contains("rtol 1e-15 raised to 1e-12"), "{method:?}: {}", warning.message);
        assert!(warning.message.contains("atol 1e-15 raised to 1e-12"), "{method:?}: {}", warning.message);
        let finest = support::run(&model, &short(Tolerances::FINEST));
        // Nothing raised; the BDF says that its steps, each held to the floor (1e-13 of the solution, or
        // three times its estimate's measured noise down to 1.5e-14), add up to more
        // than 1e-12 (`share_floor`), once they do.
        let floor_held = |w: &&flexmb::analysis::SimulationWarning| w.message.contains("held to what one step resolves");
        let (floor, others): (Vec<_>, Vec<_>) = finest.report.warnings.iter().partition(floor_held);
        assert!(others.is_empty(), "{method:?}: {others:?}");
        assert_eq!(floor.len(), usize::from(matches!(method, Method::Bdf(_))), "{method:?}: {floor:?}");
        // Raised, the run is the run at the finest tolerance.
        assert_eq!(raised.rows, finest.rows, "{method:?}");
        assert_eq!(raised.report.stats.steps, finest.report.stats.steps, "{method:?}");
    }
}

/// Over the run's span generalized-α keeps no tolerance finer than `GeneralizedAlpha::FINEST_OVER_RUN`
/// (1e-7; below it its steps are held to what one step resolves and its error stops falling,
/// docs/accuracy.md): a finer one is raised to it with a warning at the start, the run is the run at
/// 1e-7, and its error is within 10 of those tolerances of the Adams method at 1e-12. With the span given
/// explicitly the tolerance is taken as given. 1 s of swinging, about 1 s in release.
#[test]
fn generalized_alpha_raises_a_tolerance_finer_than_it_keeps_over_the_run() {
    let model = swinging_pendulum();
    let over_one_second = |method: Method, tol: f64| SimulationSettings { t_end: 1.0, ..settings(method, tol) };
    let method = Method::generalized_alpha(0.9);
    let reference = support::run(&model, &over_one_second(Method::Adams(AdamsConfig::default()), 1e-12));
    let raised = support::run(&model, &over_one_second(method, 1e-10));
    let warning = raised.report.warnings.iter().find(|w| w.kind == WarningKind::Tolerance).expect("a tolerance warning");
    assert_eq!(warning.t, 0.0);
    assert!(warning.message.contains("rtol 1e-10 raised to 1e-7, atol 1e-10 raised to 1e-7"), "{}", warning.message);
    assert_eq!(flexmb::integrate::GeneralizedAlpha::FINEST_OVER_RUN, 1e-7);
    let finest = support::run(&model, &over_one_second(method, 1e-7));
    assert!(finest.report.warnings.is_empty(), "{:?}", finest.report.warnings);
    assert_eq!(raised.rows, finest.rows, "raised, the run is the run at 1e-7");
    assert_eq!(raised.report.stats.steps, finest.report.stats.steps);
    let error = global_error(&finest, &reference);
    eprintln!("generalized-α at 1e-7 over 1 s: {} steps, global error {error:.2e}", finest.report.stats.steps);
    assert!(error <= 10.0 * 1e-7, "global error {error:e}");
    let mut explicit = over_one_second(method, 1e-10);
    explicit.tolerances.span = ToleranceSpan::Seconds(1.0);
    let given = support::run(&model, &explicit);
    assert!(given.report.warnings.iter().all(|w| w.kind != WarningKind::Tolerance), "{:?}", given.report.warnings);
    assert!(given.report.stats.steps > finest.report.stats.steps, "taken as given: {} steps", given.report.stats.steps);
}
