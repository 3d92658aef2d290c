//! The generalized-α method (`Method::GeneralizedAlpha`): second order at fixed step against a tight BDF
//! reference; agreement with the BDF on a slider-crank and a heavy top; no energy drift of a conservative
//! pendulum with `ρ∞ = 1`; numerical damping of an unresolved stiff spring–mass at `ρ∞ = 0.5` with the
//! slow motion kept; constraints held; step sizes that follow the tolerance.
//! Run with `--nocapture` for the measured numbers.

mod support;

use std::sync::Arc;
use flexmb::analysis::{
    SimulationFailure, SimulationSettings,
};

use flexmb::function::TimeFunction;
use flexmb::integrate::{Bdf, BdfConfig, GeneralizedAlpha, GeneralizedAlphaConfig, IntegrationError, Method, ToleranceSpan, Tolerances};
use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::measure::{Measure, MeasureKind};
use flexmb::model::{BodyRef, Model, ModelBuilder, OutputKind};
use std::f64::consts::PI;
use support::*;

const G: f64 = 9.81;

/// Generalized-α at the fixed step `h` to `t_end`, Newton tolerance `tol`.
fn fixed_step_run(model: &Model, rho: f64, h: f64, t_end: f64, tol: f64) -> GeneralizedAlpha {
    let (state, acc) = consistent_start(model);
    // The Newton tolerance from rtol itself, as measured: each step its whole tolerance (over a span the
    // Newton tolerance is the step's share of it, 2.9 solves per step at 2 ms).
    let tolerances = Tolerances { span: ToleranceSpan::Step, ..Tolerances::new(tol, tol) };
    let alpha = GeneralizedAlphaConfig { spectral_radius: rho, fixed_step: Some(h) };
    let mut ga = GeneralizedAlpha::new(Arc::new(model.clone()), &state, &acc, tolerances, alpha).unwrap();
    while ga.t() < t_end {
        ga.step(t_end).unwrap();
    }
    assert_eq!(ga.t(), t_end);
    ga
}

/// `(q, v, λ)` at `t_end` from the BDF at tolerance `tol`.
fn bdf_reference(model: &Model, t_end: f64, tol: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (state, acc) = consistent_start(model);
    let mut bdf = Bdf::new(Arc::new(model.clone()), &state, &acc, Tolerances::new(tol, tol), BdfConfig::default()).unwrap();
    while bdf.t() < t_end {
        bdf.step(t_end).unwrap();
    }
    let l = model.layout();
    let y = bdf.y();
    (y[..l.nq].to_vec(), y[l.nq..l.nq + l.nv].to_vec(), y[l.nq + l.nv..l.nq + l.nv + l.nc].to_vec())
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// Least-squares slope of `log err` against `log h`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let xs: Vec<f64> = points.iter().map(|p| p.0.ln()).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.1.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Energy of the pendulum of [`support::pendulum`] (one body, centre of mass at its frame origin,
/// isotropic inertia `ic`) from the integrator's state; gravity −y.
fn pendulum_energy(q: &[f64], v: &[f64], m: f64, ic: f64) -> f64 {
    let speed2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let spin2 = v[3] * v[3] + v[4] * v[4] + v[5] * v[5];
    0.5 * m * speed2 + 0.5 * ic * spin2 + m * G * q[1]
}

#[test]
fn second_order_at_fixed_step_on_a_pendulum() {
    let (l, m, ic, theta0) = (1.0, 1.0, 1e-3, 1.0);
    let model = pendulum(l, m, ic, theta0, G).build().unwrap();
    let t_end = 1.0;
    let (q_ref, v_ref, lambda_ref) = bdf_reference(&model, t_end, 1e-12);
    let lambda_scale = lambda_ref.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    for rho in [1.0, 0.9, 0.5] {
        let mut points_q = Vec::new();
        let mut points_v = Vec::new();
        let mut points_l = Vec::new();
        eprintln!("ρ∞ = {rho}:\n        h     error q     error v   error λ/max|λ|   Newton its/step");
        for n in [25, 50, 100, 200, 400] {
            let h = t_end / n as f64;
            let ga = fixed_step_run(&model, rho, h, t_end, 1e-11);
            let (eq, ev) = (max_difference(ga.q(), &q_ref), max_difference(ga.v(), &v_ref));
            let el = max_difference(ga.multipliers(), &lambda_ref) / lambda_scale;
            let its = ga.stats.newton_iterations as f64 / ga.stats.steps as f64;
            eprintln!("  {h:8.5} {eq:11.3e} {ev:11.3e} {el:14.3e} {its:12.2}");
            points_q.push((h, eq));
            points_v.push((h, ev));
            points_l.push((h, el));
            assert_eq!(ga.stats.steps, n, "fixed steps");
        }
        let (sq, sv, sl) = (slope(&points_q), slope(&points_v), slope(&points_l));
        eprintln!("  slopes: q {sq:.3}, v {sv:.3}, λ {sl:.3}");
        for (what, s) in [("positions", sq), ("velocities", sv), ("multipliers", sl)] {
            assert!((s - 2.0).abs() < 0.2, "ρ∞ = {rho}: observed order of the {what} {s:.3}, expected 2");
        }
    }
}

/// At a fixed step the predictor extrapolates `v̇` and `λ` through the last step, as under error control:
/// on a pendulum whose step resolves the swing the chord iteration then converges in about two solves
/// per step at rtol 1e-6 (before, from the held predictor, about four), fewer as the step shrinks, with the
/// error of second order down to what the Newton tolerance leaves.
#[test]
fn a_fixed_step_predictor_extrapolates() {
    let model = pendulum(1.0, 1.0, 1e-3, 1.0, G).build().unwrap();
    let t_end = 2.0;
    let (q_ref, _, _) = bdf_reference(&model, t_end, 1e-12);
    for (h, tol) in [(2e-3, 1e-6), (1e-3, 1e-6), (5e-4, 1e-6)] {
        let ga = fixed_step_run(&model, 0.9, h, t_end, tol);
        let s = &ga.stats;
        let per_step = s.newton_iterations as f64 / s.steps as f64;
        let e = max_difference(ga.q(), &q_ref);
        eprintln!(
            "fixed h {h:.0e}, Newton tolerance from rtol {tol:.0e}: {} steps, {per_step:.2} solves per step, {} factorizations; error {e:.3e}",
            s.steps, s.factorizations
        );
        assert_eq!(s.steps, (t_end / h).round() as usize);
        assert!(per_step < 2.6, "{per_step} solves per step");
        // Second order, measured 3.5e-6 (h / 1 ms)² m, above what the Newton tolerance of rtol 1e-6 leaves
        // (1.7e-6 m at 4,000 steps of 0.5 ms, 1.3 solves per step).
        assert!(e < 5e-6 * (h / 1e-3).powi(2) + 2.5e-6, "error {e:e} at h {h:e}");
    }
}

/// `settings(t_end, output_step, tol)` for the generalized-α method.
fn alpha_settings(t_end: f64, output_step: f64, tol: f64, rho: f64) -> SimulationSettings {
    SimulationSettings {
        method: Method::generalized_alpha(rho),
        ..settings(t_end, output_step, tol)
    }
}

/// An undriven slider-crank (one degree of freedom) under gravity, crank started at 8 rad/s.
fn free_slider_crank() -> Model {
    let mut b = ModelBuilder::new("free slider-crank").gravity(Vec3::new(0.0, -G, 0.0));
    let SliderCrank { crank_joint, slide, slider_pin, .. } =
        slider_crank_linkage(&mut b, 0.1, 0.3, Some(Vec3::new(0.0, 0.0, 8.0)));
    let x = b.add_measure(Measure { name: "slider_position".into(), kind: MeasureKind::JointDisplacement(slide) }).unwrap();
    let angle = b.add_measure(Measure { name: "crank_angle".into(), kind: MeasureKind::JointAngle(crank_joint) }).unwrap();
    b.add_output("x", OutputKind::Measure(x)).unwrap();
    b.add_output("angle", OutputKind::Measure(angle)).unwrap();
    b.add_output("pin", OutputKind::MarkerVelocity(slider_pin)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    b.build().unwrap()
}

#[test]
fn slider_crank_agrees_with_the_bdf() {
    let model = free_slider_crank();
    let reference = run(&model, &settings(2.0, 0.01, 1e-10));
    for tol in [1e-5, 1e-7] {
        let ga = run(&model, &alpha_settings(2.0, 0.01, tol, 0.9));
        assert_eq!(ga.report.method, "gen-alpha");
        let n = ga.t.len();
        assert_eq!(n, reference.t.len());
        let (x, x_ref) = (ga.col("x"), reference.col("x"));
        let (a, a_ref) = (unwrap_angles(&ga.col("angle")), unwrap_angles(&reference.col("angle")));
        let (w, w_ref) = (ga.vec3("pin"), reference.vec3("pin"));
        let x_err = max_over(n, |k| (x[k] - x_ref[k]).abs());
        let a_err = max_over(n, |k| (a[k] - a_ref[k]).abs());
        let v_err = max_over(n, |k| (w[k] - w_ref[k]).norm());
        let bdf = run(&model, &settings(2.0, 0.01, tol));
        let x_bdf = bdf.col("x");
        let bdf_err = max_over(n, |k| (x_bdf[k] - x_ref[k]).abs());
        let s = &ga.report.stats;
        eprintln!(
            "slider-crank tol {tol:.0e}: BDF's own max |Δx| {bdf_err:.2e} m; gen-α max |Δx| {x_err:.2e} m, |Δθ| {a_err:.2e} rad, |Δv_pin| {v_err:.2e} m/s; \
             {} steps ({} rejected: {} error test, {} Newton), {:.2} Newton its/step, {} Jacobians; BDF {} steps; \
             max |Φ| {:.1e}, |Φ̇| {:.1e}, crank turns {:.1}",
            s.steps,
            s.rejected_steps(),
            s.error_test_failures,
            s.newton_failures,
            s.newton_iterations as f64 / s.steps as f64,
            s.jacobian_evaluations,
            bdf.report.stats.steps,
            ga.report.max_position_residual,
            ga.report.max_velocity_residual,
            (a_ref[n - 1] - a_ref[0]) / (2.0 * PI),
        );
        assert!(x_err < 100.0 * tol, "slider position differs from the BDF by {x_err:e} m");
        assert!(ga.report.max_position_residual < tol, "position constraints {:e}", ga.report.max_position_residual);
        assert!(ga.report.max_velocity_residual < tol, "velocity constraints {:e}", ga.report.max_velocity_residual);
        assert!(ga.report.max_normalization_error < 1e-14);
        let _ = (a_err, v_err);
    }
}

/// Heavy symmetric top with its tip in a spherical joint (as in heavy_top.rs): mass 0.5 kg, centre of
/// mass 0.1 m up the axis, axial and transverse moments 6.25e-4 and 3.5e-4 kg m², spin 200 rad/s, axis at
/// `theta0` from the vertical with the gyroscopic precession rate, so it nutates slightly.
fn heavy_top(theta0: f64) -> (Model, f64) {
    let (m, r, i3, a, spin) = (0.5, 0.1, 6.25e-4, 3.5e-4, 200.0);
    let precession = m * G * r / (i3 * spin);
    let mut b = ModelBuilder::new("heavy top").gravity(Vec3::new(0.0, 0.0, -G));
    let axis = Vec3::new(theta0.sin(), 0.0, theta0.cos());
    let body = b.add_body(rigid(
        "top",
        m,
        Vec3::new(0.0, 0.0, r),
        Mat3::from_diagonal(&Vec3::new(a, a, i3)),
        Vec3::zeros(),
        EulerParameters::from_axis_angle(&Vec3::y(), theta0).unwrap(),
        Some(Vec3::zeros()),
        Some(spin * axis + precession * Vec3::z()),
    )).unwrap();
    let support = marker(&mut b, "support", BodyRef::Ground, Vec3::zeros());
    let tip = marker(&mut b, "tip", BodyRef::Body(body), Vec3::zeros());
    let center = marker(&mut b, "center_marker", BodyRef::Body(body), Vec3::new(0.0, 0.0, r));
    joint(&mut b, "tip", JointKind::Spherical, support, tip);
    b.add_output("center", OutputKind::MarkerPosition(center)).unwrap();
    b.add_output("w", OutputKind::MarkerAngularVelocity(center)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    (b.build().unwrap(), 2.0 * PI / precession)
}

#[test]
fn heavy_top_agrees_with_the_bdf() {
    let (model, period) = heavy_top(PI / 3.0);
    let t_end = period;
    let reference = run(&model, &settings(t_end, 2e-3, 1e-10));
    for tol in [1e-6, 1e-8] {
        let ga = run(&model, &alpha_settings(t_end, 2e-3, tol, 0.9));
        let n = ga.t.len();
        let (c, c_ref) = (ga.vec3("center"), reference.vec3("center"));
        let (w, w_ref) = (ga.vec3("w"), reference.vec3("w"));
        let e = ga.col("energy.total");
        let c_err = max_over(n, |k| (c[k] - c_ref[k]).norm()) / 0.1;
        let w_err = max_over(n, |k| (w[k] - w_ref[k]).norm()) / 200.0;
        let e_drift = max_over(n, |k| (e[k] - e[0]).abs()) / (0.5 * 6.25e-4 * 200.0 * 200.0);
        let bdf = run(&model, &settings(t_end, 2e-3, tol));
        let c_bdf = bdf.vec3("center");
        let bdf_err = max_over(n, |k| (c_bdf[k] - c_ref[k]).norm()) / 0.1;
        let s = &ga.report.stats;
        eprintln!(
            "heavy top tol {tol:.0e} over {t_end:.2} s: axis error {c_err:.2e} rad, |Δω|/ω₃ {w_err:.2e}, energy drift {e_drift:.2e}; \
             {} steps ({} rejected), {:.2} Newton its/step, {} Jacobians; BDF {} steps, axis error {bdf_err:.2e}; max |Φ| {:.1e}, |Φ̇| {:.1e}",
            s.steps,
            s.rejected_steps(),
            s.newton_iterations as f64 / s.steps as f64,
            s.jacobian_evaluations,
            bdf.report.stats.steps,
            ga.report.max_position_residual,
            ga.report.max_velocity_residual,
        );
        // A second-order method whose local error is held at tol has a global error growing like
        // tol^(2/3); measured 47 tol^(2/3) at both tolerances (4.7e-3 and 2.2e-4 rad).
        assert!(c_err < 100.0 * tol.powf(2.0 / 3.0), "axis differs from the BDF by {c_err:e} rad");
        assert!(ga.report.max_position_residual < tol);
        assert!(ga.report.max_velocity_residual < tol);
        assert!(ga.report.max_normalization_error < 1e-14);
    }
}

#[test]
fn energy_of_a_conservative_pendulum_does_not_drift_at_rho_one() {
    let (l, m, ic, theta0) = (1.0, 1.0, 1e-3, 1.0);
    let model = pendulum(l, m, ic, theta0, G).build().unwrap();
    let period = 4.0 * ((ic + m * l * l) / (m * G * l)).sqrt() * elliptic_k((theta0 / 2.0_f64).sin());
    let periods = 100;
    let steps_per_period = 80;
    let h = period / steps_per_period as f64;
    for rho in [1.0, 0.9] {
        let (state, acc) = consistent_start(&model);
        let tolerances = Tolerances::new(1e-11, 1e-11);
        let alpha = GeneralizedAlphaConfig { spectral_radius: rho, fixed_step: Some(h) };
        let mut ga = GeneralizedAlpha::new(Arc::new(model.clone()), &state, &acc, tolerances, alpha).unwrap();
        let e0 = pendulum_energy(ga.q(), ga.v(), m, ic);
        let scale = m * G * l * (1.0 - theta0.cos());
        let mut per_period = Vec::new();
        let mut worst = 0.0_f64;
        for _ in 0..periods {
            let mut sum = 0.0;
            for _ in 0..steps_per_period {
                ga.step(f64::INFINITY).unwrap();
                let e = (pendulum_energy(ga.q(), ga.v(), m, ic) - e0) / scale;
                sum += e;
                worst = worst.max(e.abs());
            }
            per_period.push(sum / steps_per_period as f64);
        }
        let first: f64 = per_period[..10].iter().sum::<f64>() / 10.0;
        let last: f64 = per_period[periods - 10..].iter().sum::<f64>() / 10.0;
        eprintln!(
            "pendulum ρ∞ = {rho}, {steps_per_period} steps per period, {periods} periods: max |E − E₀| {worst:.2e} of m g l (1 − cos θ₀); \
             mean over periods 1–10 {first:.3e}, over {}–{periods} {last:.3e}",
            periods - 9
        );
        if rho == 1.0 {
            assert!(worst < 1e-2, "energy error {worst:e}");
            assert!((last - first).abs() < 1e-3 * worst, "energy drifts: {first:e} → {last:e} (oscillation {worst:e})");
        }
    }
}

/// Angle of the bob from the hanging position, and the energy of the slider's oscillation (spring and
/// relative kinetic energy), from a state of [`pendulum_with_stiff_slider`].
fn slow_and_fast(q: &[f64], v: &[f64]) -> (f64, f64) {
    let (s0, k, m) = (0.1, 1e4, 0.01);
    let angle = q[0].atan2(-q[1]);
    let x = (q[2] - q[9]) - s0;
    let x_rate = v[2] - v[8];
    (angle, 0.5 * k * x * x + 0.5 * m * x_rate * x_rate)
}

#[test]
fn rho_half_damps_an_unresolved_stiff_spring_and_keeps_the_swing() {
    let excited = pendulum_with_stiff_slider(1e-3);
    let t_end = 2.0;
    // h ω = 10 for the spring. The slow motion: the BDF, tightly, with the spring not excited.
    let h = 0.01;
    let (q_ref, _, _) = bdf_reference(&pendulum_with_stiff_slider(0.0), t_end, 1e-10);
    let (angle_ref, _) = slow_and_fast(&q_ref, &[0.0; 12]);
    for rho in [0.5, 1.0] {
        let (state, acc) = consistent_start(&excited);
        let fast0 = slow_and_fast(&state.q, &state.v).1;
        let tolerances = Tolerances::new(1e-9, 1e-9);
        let alpha = GeneralizedAlphaConfig { spectral_radius: rho, fixed_step: Some(h) };
        let mut ga = GeneralizedAlpha::new(Arc::new(excited.clone()), &state, &acc, tolerances, alpha).unwrap();
        let mut fast_after_half = 0.0_f64;
        while ga.t() < t_end {
            ga.step(t_end).unwrap();
            if ga.t() > 0.5 {
                fast_after_half = fast_after_half.max(slow_and_fast(ga.q(), ga.v()).1);
            }
        }
        let (angle, _) = slow_and_fast(ga.q(), ga.v());
        let s = &ga.stats;
        eprintln!(
            "stiff slider ρ∞ = {rho}, h ω = 10: fast energy {fast0:.2e} J at start, at most {fast_after_half:.2e} J after 0.5 s; \
             bob angle at {t_end} s {angle:.6} rad vs unexcited BDF {angle_ref:.6} (Δ {:.2e}); {:.2} Newton its/step, {} Jacobians, {} rejected",
            (angle - angle_ref).abs(),
            s.newton_iterations as f64 / s.steps as f64,
            s.jacobian_evaluations,
            s.rejected_steps()
        );
        if rho == 0.5 {
            assert!(fast_after_half < 1e-12 * fast0, "the fast motion keeps {fast_after_half:e} J of {fast0:e} J");
        } else {
            assert!(
                fast_after_half > 0.5 * fast0,
                "ρ∞ = 1 keeps the fast energy: {fast_after_half:e} J of {fast0:e} J"
            );
        }
        assert!((angle - angle_ref).abs() < 1e-2, "slow motion: {angle} vs {angle_ref}");
    }
}

#[test]
fn steps_follow_the_tolerance() {
    let model = free_slider_crank();
    let mut previous = 0;
    for tol in [1e-4, 1e-6, 1e-8] {
        let ga = run(&model, &alpha_settings(2.0, 0.01, tol, 0.9));
        let bdf = run(&model, &settings(2.0, 0.01, tol));
        let s = &ga.report.stats;
        eprintln!(
            "tol {tol:.0e}: gen-α {} steps (rms h {:.2e} s, {} rejected), BDF {} steps",
            s.steps,
            s.rms_step(),
            s.rejected_steps(),
            bdf.report.stats.steps
        );
        assert!(s.steps > previous, "tighter tolerance, more steps");
        assert_eq!(s.order_counts[2], s.steps);
        previous = s.steps;
    }
}

/// Dense output: positions and velocities interpolated in the middle of the last fixed step agree with
/// the BDF there to second order in the step, as the step ends do.
#[test]
fn dense_output_within_a_step() {
    let model = pendulum(1.0, 1.0, 1e-3, 1.0, G).build().unwrap();
    let t_end = 1.0;
    let t_mid = |h: f64| t_end - 0.5 * h;
    let (nq, nv) = (model.layout().nq, model.layout().nv);
    let mut points = Vec::new();
    for n in [50, 100, 200, 400] {
        let h = t_end / n as f64;
        let (q_ref, v_ref, _) = bdf_reference(&model, t_mid(h), 1e-12);
        let mut ga = fixed_step_run(&model, 0.9, h, t_end, 1e-11);
        let (mut q, mut v) = (vec![0.0; nq], vec![0.0; nv]);
        ga.interpolate(t_end, &mut q, &mut v);
        assert!(
            max_difference(&q, ga.q()) < 1e-15 && max_difference(&v, ga.v()) < 1e-13,
            "the interpolant ends on the step"
        );
        ga.interpolate(t_mid(h), &mut q, &mut v);
        let norm: f64 = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-15, "interpolated Euler parameters are unit: {norm}");
        let (eq, ev) = (max_difference(&q, &q_ref), max_difference(&v, &v_ref));
        eprintln!("dense output h {h:.4}: error at mid-step q {eq:.3e}, v {ev:.3e}");
        points.push((h, eq.max(ev)));
    }
    let s = slope(&points);
    eprintln!("dense output: observed order {s:.3}");
    assert!((s - 2.0).abs() < 0.25, "observed order of the interpolated state {s:.3}, expected 2");
}

/// A slider-crank whose crank (0.3 m) is longer than its rod (0.2 m), driven at 1 rev/s, locks at
/// `θ = asin(l/r)` (as in diagnostics.rs): the generalized-α run stops there with the time and a joint
/// equation in its message.
#[test]
fn mechanism_that_locks_fails_with_time_and_equation() {
    let (r, l) = (0.3, 0.2);
    let mut b = ModelBuilder::new("locking slider-crank");
    let SliderCrank { pivot_ground, pivot, .. } = slider_crank_linkage(&mut b, r, l, None);
    let driver = JointKind::AngleDriver { function: TimeFunction::parse("2*PI*t").unwrap() };
    joint(&mut b, "crank_motion", driver, pivot_ground, pivot);
    let model = b.build().unwrap();
    let t_lock = (l / r).asin() / (2.0 * PI);
    let (err, partial) =
        try_run(&model, &alpha_settings(1.0, 0.005, 1e-7, 0.9)).err().expect("the crank cannot turn past the toggle");
    let message = err.to_string();
    eprintln!("locking slider-crank, gen-α (lock at t = {t_lock:.6} s): {message}");
    let t_fail = match &err.cause {
        SimulationFailure::Integration(IntegrationError::StepSizeTooSmall { t, .. }) => *t,
        SimulationFailure::SingularAccelerations { t, .. } => *t,
        other => panic!("expected a step-size or singular-acceleration failure, got {other:?}"),
    };
    assert_eq!(err.report.method, "gen-alpha");
    assert!((t_fail - t_lock).abs() < 2e-3, "fails at t = {t_fail} s, the lock is at {t_lock} s");
    assert!(message.contains(&format!("{t_fail:.6}")), "the message gives the time: {message}");
    assert!(message.contains("joint '"), "the message names a joint equation: {message}");
    assert_eq!(partial.t.len(), (t_fail / 0.005).floor() as usize + 1, "frames up to the failure");
}

#[test]
fn invalid_spectral_radius_is_refused() {
    let model = pendulum(1.0, 1.0, 1e-3, 1.0, G).build().unwrap();
    let (err, _) = try_run(&model, &alpha_settings(1.0, 0.1, 1e-6, 1.5)).err().expect("ρ∞ = 1.5 is refused");
    eprintln!("{err}");
    assert!(matches!(err.cause, SimulationFailure::Invalid(_)), "{err}");
    assert!(err.to_string().contains("spectral radius"), "{err}");
}

/// Redundant constraint rows (a spherical joint on top of the revolute pivot: 3 of its rows repeat the
/// revolute's) are switched off by the assembly; the generalized-α run holds their multipliers at zero
/// and moves exactly as without them.
#[test]
fn redundant_rows_change_nothing() {
    let plain = pendulum(1.0, 1.0, 1e-3, 1.0, G);
    let mut doubled = pendulum(1.0, 1.0, 1e-3, 1.0, G);
    let (g, p) = (doubled.find_marker("pivot_ground").unwrap(), doubled.find_marker("pivot_bob").unwrap());
    joint(&mut doubled, "ball", JointKind::Spherical, g, p);
    let mut runs = Vec::new();
    for mut b in [plain, doubled] {
        let bob = b.find_marker("bob_centre").unwrap();
        b.add_output("bob", OutputKind::MarkerPosition(bob)).unwrap();
        let model = b.build().unwrap();
        runs.push(run(&model, &alpha_settings(2.0, 0.01, 1e-7, 0.9)));
    }
    assert_eq!(runs[1].report.assembly.as_ref().unwrap().redundant.len(), 3);
    let (a, b) = (runs[0].vec3("bob"), runs[1].vec3("bob"));
    let diff = max_over(a.len(), |k| (a[k] - b[k]).norm());
    eprintln!(
        "pendulum with a redundant spherical joint: max bob difference {diff:.2e} m; steps {} and {}",
        runs[0].report.stats.steps, runs[1].report.stats.steps
    );
    assert!(diff < 1e-9, "the redundant joint changes the motion by {diff:e} m");
    assert!(runs[1].report.max_position_residual < 1e-7 && runs[1].report.max_velocity_residual < 1e-7);
}

/// A flexible pendulum (a lumped beam with 3 modes on a revolute, gravity): the generalized-α method
/// follows a tight BDF solution of the tip within a hundred tolerances (measured 8.6e-6 m at 1e-6)
/// and keeps the constraints.
#[test]
fn flexible_pendulum_agrees_with_the_bdf() {
    let (mut b, _, tip) = lumped_flexible_pendulum([400.0, 3000.0, 9000.0], [0.1, 0.0, 0.0]);
    b.add_output("tip", OutputKind::MarkerPosition(tip)).unwrap();
    let model = b.build().unwrap();
    let reference = run(&model, &settings(1.0, 0.01, 1e-10));
    let tol = 1e-6;
    let ga = run(&model, &alpha_settings(1.0, 0.01, tol, 0.9));
    let (p, p_ref) = (ga.vec3("tip"), reference.vec3("tip"));
    let n = ga.t.len();
    assert_eq!(n, reference.t.len());
    let error = max_over(n, |k| (p[k] - p_ref[k]).norm());
    eprintln!(
        "flexible pendulum tol {tol:.0e}: gen-α max tip distance from a BDF at 1e-10 {error:.2e} m, {} steps; max |Φ| {:.1e}, |Φ̇| {:.1e}",
        ga.report.stats.steps, ga.report.max_position_residual, ga.report.max_velocity_residual
    );
    assert!(error < 100.0 * tol, "tip differs by {error:e} m");
    assert!(ga.report.max_position_residual < tol && ga.report.max_velocity_residual < tol);
}
