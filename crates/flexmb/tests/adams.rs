//! The Adams method (Shampine–Gordon PECE, orders 1–12, projection onto the constraints) on mechanisms:
//! closed-form references (pendulum period, driven slider-crank), agreement with the BDF (free
//! slider-crank, heavy top, flexible pendulum), constraint residuals and the drift the projection
//! removes, step counts against the BDF on non-stiff models, and the stiffness signature on a pendulum
//! carrying a stiff spring. Run with `--nocapture` for the numbers.

mod support;

use std::sync::Arc;
use flexmb::analysis::test_models::pendulum_with_stiff_slider_of;
use flexmb::analysis::{SimulationReport, SimulationSettings};
use flexmb::force::{ForceElement, ForceKind};
use flexmb::function::TimeFunction;
use flexmb::integrate::adams::ConstraintHandling;
use flexmb::integrate::{Adams, AdamsConfig, BdfConfig, IntegrationError, Method, ToleranceSpan, Tolerances};
use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::measure::{Measure, MeasureKind};
use flexmb::model::{BodyRef, Model, ModelBuilder, OutputKind};
use std::f64::consts::PI;
use support::*;

fn with_adams(s: SimulationSettings) -> SimulationSettings {
    SimulationSettings { method: Method::Adams(AdamsConfig::default()), ..s }
}

fn with_partitioning(s: SimulationSettings) -> SimulationSettings {
    let config = AdamsConfig { constraints: ConstraintHandling::Partitioning, ..Default::default() };
    SimulationSettings { method: Method::Adams(config), ..s }
}

/// One line of solver statistics for the reports.
fn summary(name: &str, r: &SimulationReport) -> String {
    let s = &r.stats;
    let orders: Vec<String> =
        s.order_counts.iter().enumerate().filter(|(_, c)| **c > 0).map(|(k, c)| format!("{k}:{c}")).collect();
    format!(
        "{name:>6}: {:6} steps, {:4} rejected, {:6} f/residual evaluations, {:6} factorizations, RMS h {:.3e} s, \
         residuals {:.1e} (position) {:.1e} (velocity), orders {}",
        s.steps,
        s.rejected_steps(),
        s.residual_evaluations,
        s.factorizations,
        s.rms_step(),
        r.max_position_residual,
        r.max_velocity_residual,
        orders.join(" ")
    )
}

/// Physical pendulum released at 1 rad: the period against `4 √(I_O/(m g l)) K(sin(θ₀/2))` over ten
/// periods from the zero crossings of the interpolated outputs; energy and constraints held.
#[test]
fn pendulum_period_matches_the_elliptic_integral() {
    let (l, m, ic, g, theta0) = (1.0, 1.0, 1e-3, 9.81, 1.0_f64);
    let mut b = pendulum(l, m, ic, theta0, g);
    let bob = b.find_marker("bob_centre").unwrap();
    b.add_output("bob", OutputKind::MarkerPosition(bob)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    let model = b.build().unwrap();
    let period = 4.0 * ((ic + m * l * l) / (m * g * l)).sqrt() * elliptic_k((theta0 / 2.0).sin());
    let s = settings(10.0 * period, 1e-3, 1e-9);
    let adams = run(&model, &with_adams(s));
    let bdf = run(&model, &s);
    let (t, x, e) = (&adams.t, adams.col("bob.x"), adams.col("energy.total"));
    let mut crossings = Vec::new();
    for k in 1..t.len() {
        if x[k - 1] < 0.0 && x[k] >= 0.0 {
            let s = x[k - 1] / (x[k - 1] - x[k]);
            crossings.push(t[k - 1] + s * (t[k] - t[k - 1]));
        }
    }
    assert!(crossings.len() >= 9, "crossings: {crossings:?}");
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let rel = (measured - period).abs() / period;
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / (m * g * l);
    eprintln!("pendulum, 10 periods at tol 1e-9: period {measured:.12} s vs {period:.12} s (rel {rel:.1e}), energy drift {drift:.1e} m g l");
    eprintln!("{}\n{}", summary("adams", &adams.report), summary("bdf", &bdf.report));
    assert_eq!(adams.report.method, "adams");
    assert!(rel < 1e-6, "period {measured} vs {period}: rel {rel:e}");
    assert!(drift < 1e-6, "energy drift {drift:e}");
    assert!(adams.report.max_position_residual < 1e-10, "{:e}", adams.report.max_position_residual);
    assert!(adams.report.max_velocity_residual < 1e-10, "{:e}", adams.report.max_velocity_residual);
    assert!(adams.report.max_normalization_error < 1e-14, "{:e}", adams.report.max_normalization_error);
}

const CRANK: f64 = 0.1; // m
const ROD: f64 = 0.3; // m

/// Slider-crank driven at one revolution per second (no degree of freedom): the slider position and
/// velocity at every output time (from the interpolant) against the closed form.
#[test]
fn driven_slider_crank_follows_the_closed_form() {
    let speed = 2.0 * PI;
    let mut b = ModelBuilder::new("slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    let SliderCrank { slide, pivot_ground, pivot, .. } = slider_crank_linkage(&mut b, CRANK, ROD, None);
    let driver = JointKind::AngleDriver { function: TimeFunction::parse("2*PI*t").unwrap() };
    joint(&mut b, "crank_motion", driver, pivot_ground, pivot);
    let x = b.add_measure(Measure { name: "x".into(), kind: MeasureKind::JointDisplacement(slide) }).unwrap();
    let v = b.add_measure(Measure { name: "v".into(), kind: MeasureKind::JointVelocity(slide) }).unwrap();
    b.add_output("x", OutputKind::Measure(x)).unwrap();
    b.add_output("v", OutputKind::Measure(v)).unwrap();
    let model = b.build().unwrap();
    let run = run(&model, &with_adams(settings(2.0, 0.002, 1e-8)));
    let (xs, vs) = (run.col("x"), run.col("v"));
    let mut worst = (0.0_f64, 0.0_f64);
    for (k, &t) in run.t.iter().enumerate() {
        let th = speed * t;
        let root = (ROD * ROD - (CRANK * th.sin()).powi(2)).sqrt();
        let x_exact = CRANK * th.cos() + root;
        let v_exact = -speed * CRANK * th.sin() * (1.0 + CRANK * th.cos() / root);
        worst.0 = worst.0.max((xs[k] - x_exact).abs());
        worst.1 = worst.1.max((vs[k] - v_exact).abs());
    }
    eprintln!(
        "driven slider-crank, 2 revolutions at tol 1e-8: largest error {:.1e} m, {:.1e} m/s at {} output times\n{}",
        worst.0,
        worst.1,
        run.t.len(),
        summary("adams", &run.report)
    );
    assert!(worst.0 < 1e-7 && worst.1 < 1e-6, "{worst:?}");
    assert!(run.report.max_position_residual < 1e-10, "{:e}", run.report.max_position_residual);
}

/// A free slider-crank (one degree of freedom) spun up and loaded by gravity and a spring on the slider.
fn free_slider_crank() -> Model {
    let mut b = ModelBuilder::new("free slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    let SliderCrank { slider_pin, .. } = slider_crank_linkage(&mut b, CRANK, ROD, Some(Vec3::new(0.0, 0.0, 12.0)));
    let anchor = marker(&mut b, "anchor", BodyRef::Ground, Vec3::new(0.8, 0.0, 0.0));
    b.add_force(ForceElement {
        name: "spring".into(),
        kind: ForceKind::TranslationalSpringDamper {
            marker_i: anchor,
            marker_j: slider_pin,
            stiffness: 100.0,
            damping: 0.0,
            free_length: 0.4,
            actuator: None,
        },
    }).unwrap();
    b.add_output("pin", OutputKind::MarkerPosition(slider_pin)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    b.build().unwrap()
}

/// Largest distance between the `name` marker trajectories of two runs with the same output times.
fn largest_distance(a: &Run, b: &Run, name: &str) -> f64 {
    let (pa, pb) = (a.vec3(name), b.vec3(name));
    assert_eq!(pa.len(), pb.len());
    pa.iter().zip(&pb).map(|(x, y)| (x - y).norm()).fold(0.0, f64::max)
}

/// Adams and BDF at the same tolerance agree with a tight BDF reference; Adams takes fewer steps than
/// the BDF on this smooth, non-stiff mechanism.
#[test]
fn free_slider_crank_agrees_with_the_bdf() {
    let model = free_slider_crank();
    let reference = run(&model, &settings(2.0, 0.01, 1e-11));
    eprintln!("free slider-crank, 2 s:");
    for tol in [1e-6, 1e-8] {
        let adams = run(&model, &with_adams(settings(2.0, 0.01, tol)));
        let bdf = run(&model, &settings(2.0, 0.01, tol));
        let (ea, eb) = (largest_distance(&adams, &reference, "pin"), largest_distance(&bdf, &reference, "pin"));
        eprintln!("  tol {tol:.0e}: distance to the reference: adams {ea:.2e} m, bdf {eb:.2e} m");
        eprintln!("  {}\n  {}", summary("adams", &adams.report), summary("bdf", &bdf.report));
        assert!(ea < 300.0 * tol, "tol {tol:e}: Adams is {ea:e} m from the reference");
        // The projection stops at 1 % of atol (Newton converges quadratically, usually far below).
        assert!(adams.report.max_position_residual <= 1e-2 * tol, "{:e}", adams.report.max_position_residual);
        assert!(adams.report.max_velocity_residual < 1e-13, "{:e}", adams.report.max_velocity_residual);
        let e = adams.col("energy.total");
        let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
        assert!(drift < 1e3 * tol, "energy drift {drift:e} J");
        // Competitive: no more steps than the BDF (each costs two evaluations, see the report).
        assert!(
            adams.report.stats.steps <= bdf.report.stats.steps,
            "adams {} vs bdf {}",
            adams.report.stats.steps,
            bdf.report.stats.steps
        );
    }
}

const TOP_M: f64 = 0.5;
const TOP_R: f64 = 0.1;

/// Heavy symmetric top on a spherical joint at its tip, axis 0.4 rad from the vertical, spinning at
/// 200 rad/s with no initial precession: it nutates.
fn heavy_top() -> Model {
    let theta0 = 0.4_f64;
    let mut b = ModelBuilder::new("heavy top").gravity(Vec3::new(0.0, 0.0, -9.81));
    let axis = Vec3::new(theta0.sin(), 0.0, theta0.cos());
    let body = b.add_body(rigid(
        "top",
        TOP_M,
        Vec3::new(0.0, 0.0, TOP_R),
        Mat3::from_diagonal(&Vec3::new(3.5e-4, 3.5e-4, 6.25e-4)),
        Vec3::zeros(),
        EulerParameters::from_axis_angle(&Vec3::y(), theta0).unwrap(),
        Some(Vec3::zeros()),
        Some(200.0 * axis),
    )).unwrap();
    let support = marker(&mut b, "support", BodyRef::Ground, Vec3::zeros());
    let tip = marker(&mut b, "tip", BodyRef::Body(body), Vec3::zeros());
    let center = marker(&mut b, "center_marker", BodyRef::Body(body), Vec3::new(0.0, 0.0, TOP_R));
    joint(&mut b, "tip", JointKind::Spherical, support, tip);
    b.add_output("center", OutputKind::MarkerPosition(center)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    b.build().unwrap()
}

#[test]
fn heavy_top_agrees_with_the_bdf() {
    let model = heavy_top();
    let t_end = 2.0;
    let reference = run(&model, &settings(t_end, 0.005, 1e-12));
    let tol = 1e-9;
    let adams = run(&model, &with_adams(settings(t_end, 0.005, tol)));
    let bdf = run(&model, &settings(t_end, 0.005, tol));
    let (ea, eb) = (largest_distance(&adams, &reference, "center"), largest_distance(&bdf, &reference, "center"));
    let e = adams.col("energy.total");
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / (0.5 * 6.25e-4 * 200.0 * 200.0);
    eprintln!(
        "heavy top, {t_end} s at tol {tol:.0e}: distance to a BDF reference at 1e-12: adams {ea:.2e} m, bdf {eb:.2e} m; \
         adams energy drift {drift:.1e} (of the spin energy)\n{}\n{}",
        summary("adams", &adams.report),
        summary("bdf", &bdf.report)
    );
    assert!(ea < 1e-6, "Adams is {ea:e} m from the reference");
    assert!(drift < 1e-7, "energy drift {drift:e}");
    assert!(adams.report.max_position_residual < 1e-10);
    assert!(adams.report.max_normalization_error < 1e-14);
}

/// The stiffness signature of the seed's table: with a stiff spring the Adams step is bounded by
/// stability (`h ≈ 1/√(k/m)`) however loose the tolerance, while the BDF steps over the damped fast
/// mode. Both are compared with a BDF reference at 1e-9. Both methods hold each step to the whole
/// tolerance (error per step), the setting the signature was measured with: it is about the stability
/// bound, which does not depend on how the tolerance is shared out.
#[test]
fn stiff_spring_makes_adams_take_many_more_steps_than_the_bdf() {
    eprintln!("pendulum with a critically damped spring, 2 s at tol 1e-5:");
    let (mut ratios, mut adams_steps) = (Vec::new(), Vec::new());
    for stiffness in [1e4, 1e5, 1e6] {
        // A bob on a translational joint along the rod, held by a stiff, critically damped spring:
        // eigenvalues near `−√(k/m)` beside the slow swing.
        let model = pendulum_with_stiff_slider_of(stiffness);
        let mut s = settings(2.0, 0.01, 1e-5);
        s.tolerances.span = ToleranceSpan::Step;
        let adams = run(&model, &with_adams(s));
        let bdf = run(&model, &s);
        let reference = run(&model, &settings(2.0, 0.01, 1e-9));
        let (ea, eb) = (largest_distance(&adams, &reference, "bob"), largest_distance(&bdf, &reference, "bob"));
        eprintln!(
            "  k = {stiffness:.0e} N/m (√(k/m) = {:.0} s⁻¹): distance to the reference: adams {ea:.1e} m, bdf {eb:.1e} m\n  {}\n  {}",
            stiffness.sqrt(),
            summary("adams", &adams.report),
            summary("bdf", &bdf.report)
        );
        assert!(ea < 1e-4, "Adams is {ea:e} m from the reference");
        ratios.push(adams.report.stats.steps as f64 / bdf.report.stats.steps as f64);
        adams_steps.push(adams.report.stats.steps as f64);
    }
    eprintln!("  Adams/BDF step ratio: {ratios:.2?}");
    assert!(ratios[2] > 5.0, "with k = 1e6 Adams should need far more steps than the BDF: {ratios:?}");
    assert!(ratios.windows(2).all(|w| w[1] > w[0]), "the ratio grows with the stiffness: {ratios:?}");
    // Stability-limited: the Adams steps grow about like √(k/m) (×3.16 per row), at least ×2.
    assert!(adams_steps.windows(2).all(|w| w[1] > 2.0 * w[0]), "{adams_steps:?}");
}

/// The projection keeps the difference table: it moves the state by a small fraction of the tolerance
/// per step, and the solution never leaves the constraints by more than the local error.
#[test]
fn projection_moves_the_state_by_much_less_than_the_tolerance() {
    let model = free_slider_crank();
    let (state, acc) = consistent_start(&model);
    eprintln!("free slider-crank, 2 s: drift before projection and the projection's change");
    for tol in [1e-5, 1e-8] {
        let tolerances = Tolerances::new(tol, tol);
        let mut adams = Adams::new(Arc::new(model.clone()), &state, &acc, tolerances, AdamsConfig::default()).unwrap();
        while adams.t() < 2.0 {
            adams.step(2.0).unwrap();
        }
        let d = *adams.drift().expect("projection");
        eprintln!(
            "  tol {tol:.0e}: {} steps; before projection |Φ| ≤ {:.1e}, |Bv + Φ_t| ≤ {:.1e}, |pᵀp − 1| ≤ {:.1e}; \
             change per step (in tolerances): max {:.2e}, RMS {:.2e}; {} Newton iterations, {} refactorizations",
            adams.stats().steps,
            d.max_position_residual,
            d.max_velocity_residual,
            d.max_normalization_error,
            d.max_weighted_correction,
            d.rms_weighted_correction(),
            d.newton_iterations,
            d.refactorizations
        );
        assert_eq!(d.projections, adams.stats().steps);
        // The error test bounds the estimated error of the order-k formula; the projection removes
        // the part of the (order k + 1) solution's error across the constraints: measured at most
        // about one tolerance, and about a tenth on average.
        assert!(d.max_weighted_correction < 2.0, "the projection moved the state by more than the tolerance");
        assert!(d.rms_weighted_correction() < 0.3);
        assert!(d.max_position_residual < 10.0 * tol);
    }
}

/// A flexible beam (8 lumped nodes, 3 modes of stiffness `k`, modal damping 2 %) hanging from a revolute
/// at its first node and swinging under gravity.
fn flexible_pendulum(stiffness: [f64; 3]) -> Model {
    let (mut b, _, tip) = lumped_flexible_pendulum(stiffness, [0.0; 3]);
    b.add_output("tip", OutputKind::MarkerPosition(tip)).unwrap();
    b.build().unwrap()
}

/// The flexible pendulum: Adams agrees with the BDF, and its step follows the highest modal frequency
/// (four times stiffer modes, about twice the steps) — the seed's table in miniature.
#[test]
fn flexible_pendulum_agrees_with_the_bdf_and_its_step_follows_the_highest_frequency() {
    let t_end = 1.0;
    eprintln!("flexible pendulum (3 modes), {t_end} s at tol 1e-6:");
    let mut rms = Vec::new();
    for scale in [1.0, 4.0, 16.0] {
        let model = flexible_pendulum([400.0 * scale, 3000.0 * scale, 9000.0 * scale]);
        let s = settings(t_end, 0.005, 1e-6);
        let adams = run(&model, &with_adams(s));
        let bdf_settings = SimulationSettings {
            tolerances: Tolerances::new(1e-6, 1e-6),
            method: Method::Bdf(BdfConfig::for_model(&model)),
            ..s
        };
        let bdf = run(&model, &bdf_settings);
        let reference = run(&model, &settings(t_end, 0.005, 1e-10));
        let (ea, eb) = (largest_distance(&adams, &reference, "tip"), largest_distance(&bdf, &reference, "tip"));
        eprintln!(
            "  modal stiffness ×{scale}: tip distance to a BDF reference at 1e-10: adams {ea:.1e} m, bdf {eb:.1e} m\n  {}\n  {}",
            summary("adams", &adams.report),
            summary("bdf", &bdf.report)
        );
        assert!(ea < 1e-4, "Adams is {ea:e} m from the reference");
        assert!(adams.report.max_position_residual < 1e-9);
        rms.push(adams.report.stats.rms_step());
    }
    eprintln!("  Adams RMS step: {rms:?}");
    // Frequencies ×2 per stiffness ×4: the RMS step at least 1.5 times smaller each time.
    assert!(rms.windows(2).all(|w| w[1] < w[0] / 1.5), "{rms:?}");
}

/// Limits and failures are reported with the time.
#[test]
fn too_many_steps_and_bad_settings_are_reported() {
    let model = free_slider_crank();
    let mut s = with_adams(settings(2.0, 0.01, 1e-8));
    s.tolerances.max_steps = 20;
    let (e, partial) = try_run(&model, &s).err().expect("the run stops");
    match e.cause {
        flexmb::analysis::SimulationFailure::Integration(IntegrationError::TooManySteps { t, max_steps: 20 }) => {
            assert!(t > 0.0 && t < 2.0)
        }
        other => panic!("unexpected {other:?}"),
    }
    assert_eq!(partial.report.stats.steps, 20);
    let bad = SimulationSettings { method: Method::Adams(AdamsConfig { max_order: 13, ..Default::default() }), ..s };
    let (e, _) = try_run(&model, &bad).err().expect("invalid order");
    assert!(e.to_string().contains("max_order"), "{e}");
    let mut no_atol = s;
    no_atol.tolerances.atol = 0.0;
    let (e, _) = try_run(&model, &no_atol).err().expect("atol = 0");
    assert!(e.to_string().contains("atol > 0"), "{e}");
}

/// Generalized coordinate partitioning (the DADS way) against projection, on the same tolerance: both
/// agree with a tight BDF reference and keep the constraints; projection needs fewer factorizations
/// everywhere and far fewer steps on the spinning top, whose independent Euler parameters force a
/// repartition (and a restart of the multistep history at order 1) every few steps.
#[test]
fn partitioning_against_projection() {
    let cases: Vec<(&str, Model, &str, f64)> = vec![
        ("free slider-crank", free_slider_crank(), "pin", 2.0),
        ("heavy top", heavy_top(), "center", 1.0),
        ("flexible pendulum", flexible_pendulum([400.0, 3000.0, 9000.0]), "tip", 0.5),
    ];
    let tol = 1e-7;
    let partitioning_config = AdamsConfig { constraints: ConstraintHandling::Partitioning, ..Default::default() };
    eprintln!("Adams at tol {tol:.0e}: projection against partitioning");
    for (name, model, output, t_end) in cases {
        let reference = run(&model, &settings(t_end, 0.01, 1e-11));
        let projection = run(&model, &with_adams(settings(t_end, 0.01, tol)));
        let partitioning = run(&model, &with_partitioning(settings(t_end, 0.01, tol)));
        let (ep, eg) =
            (largest_distance(&projection, &reference, output), largest_distance(&partitioning, &reference, output));
        // The partition's history, from a direct run over the same span as the simulation's (the run's
        // length: a method started directly takes 1 s).
        let (state, acc) = consistent_start(&model);
        let tolerances = Tolerances { span: ToleranceSpan::Run.over_run(t_end), ..Tolerances::new(tol, tol) };
        let mut direct = Adams::new(Arc::new(model.clone()), &state, &acc, tolerances, partitioning_config).unwrap();
        while direct.t() < t_end {
            direct.step(t_end).unwrap();
        }
        let report = *direct.partition().expect("partitioning");
        eprintln!(
            "  {name}, {t_end} s: distance to the reference: projection {ep:.1e} m, partitioning {eg:.1e} m; \
             wall time {:.1} ms vs {:.1} ms; {} independent coordinates, {} repartitions, {} Newton iterations\n  {}\n  {}",
            1e3 * projection.report.wall_time,
            1e3 * partitioning.report.wall_time,
            report.independent,
            report.repartitions,
            report.newton_iterations,
            summary("proj", &projection.report),
            summary("part", &partitioning.report)
        );
        assert_eq!(direct.stats().steps, partitioning.report.stats.steps);
        assert!(ep < 1e3 * tol && eg < 1e3 * tol, "{name}: {ep:e}, {eg:e}");
        assert!(partitioning.report.max_position_residual < 1e-9, "{:e}", partitioning.report.max_position_residual);
        assert!(partitioning.report.max_velocity_residual < 1e-9, "{:e}", partitioning.report.max_velocity_residual);
        assert!(
            projection.report.stats.factorizations < partitioning.report.stats.factorizations,
            "{name}: projection factors more often"
        );
        if name == "heavy top" {
            assert!(report.repartitions > 20, "the spinning top repartitions often: {report:?}");
            assert!(projection.report.stats.steps * 2 < partitioning.report.stats.steps);
        }
    }
}

/// Dense output is projected too: at every output time between the steps, a free slider-crank run with
/// Adams keeps its position constraints to the projection's tolerance (1e-2 atol) and its velocity
/// constraints to round-off, as the accepted steps do, not only to the local error of the interpolant.
#[test]
fn interpolated_outputs_keep_the_constraints() {
    let mut b = ModelBuilder::new("slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    slider_crank_linkage(&mut b, CRANK, ROD, Some(Vec3::new(0.0, 0.0, 8.0)));
    b.add_output("residual", OutputKind::ConstraintResidual).unwrap();
    let model = b.build().unwrap();
    let tol = 1e-6;
    // Outputs every 0.2 ms: the steps are held to error per unit step, 1,000 of them in 2 s.
    let run = run(&model, &with_adams(settings(2.0, 0.0002, tol)));
    let (position, velocity) = (run.col("residual.position"), run.col("residual.velocity"));
    let worst = |x: &[f64]| x.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
    eprintln!(
        "Adams slider-crank, {} steps, {} output times: largest residual at the outputs {:.1e} m, {:.1e} m/s",
        run.report.stats.steps,
        run.t.len(),
        worst(&position),
        worst(&velocity)
    );
    assert!(run.t.len() > 5 * run.report.stats.steps, "most outputs fall between steps");
    assert!(worst(&position) <= 1e-2 * tol, "{:e}", worst(&position));
    assert!(worst(&velocity) < 1e-12, "{:e}", worst(&velocity));
}
