//! Heavy symmetric top with its tip in a spherical joint: gyroscopic precession, conserved spin, energy,
//! and the whole axis trajectory against an independent integration of the Euler-angle equations.
//!
//! Top: mass `m`, centre of mass at distance `r` up the symmetry axis (body z), moments `I₃` about the
//! axis and `A` about transverse axes through the centre of mass, so `I₁ = A + m r²` about the tip.
//! Euler angles: `θ` of the axis from the upward vertical, `φ` its azimuth (precession), spin
//! `ω₃ = ψ̇ + φ̇ cos θ`. Lagrange's equations (Goldstein §5.7) with `ω₃` and
//! `p_φ = I₁ φ̇ sin²θ + I₃ ω₃ cos θ` conserved:
//!
//! ```text
//! I₁ θ̈ = I₁ φ̇² sin θ cos θ − I₃ ω₃ φ̇ sin θ + m g r sin θ
//! ```
//! Steady precession at angle `θ` needs `m g r = I₃ ω₃ Ω − I₁ Ω² cos θ`; with the axis horizontal
//! (`cos θ = 0`) the gyroscopic value `Ω = m g r / (I₃ ω₃)` solves it exactly, so a top started there
//! precesses uniformly with no nutation: the fast-top error term `I₁ Ω² cos θ` (relative size
//! `(I₁/I₃)(Ω/ω₃) cos θ`) and the nutation amplitude both vanish, and the only tolerance needed is that
//! of the integration.

mod support;

use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, Model, ModelBuilder, OutputKind};
use std::f64::consts::PI;
use support::*;

const M: f64 = 0.5; // kg
const R: f64 = 0.1; // m, tip to centre of mass
const I3: f64 = 6.25e-4; // kg m², about the symmetry axis
const A: f64 = 3.5e-4; // kg m², transverse, about the centre of mass
const G: f64 = 9.81; // m/s²
const SPIN: f64 = 200.0; // rad/s, ψ̇

fn i1() -> f64 {
    A + M * R * R
}

/// The top with its axis at `theta0` from the vertical in the x–z plane, spin `SPIN` about the axis and
/// precession rate `phi_rate0` about global z.
fn top(theta0: f64, phi_rate0: f64) -> Model {
    let mut b = ModelBuilder::new("heavy top").gravity(Vec3::new(0.0, 0.0, -G));
    let axis = Vec3::new(theta0.sin(), 0.0, theta0.cos());
    let omega = SPIN * axis + phi_rate0 * Vec3::z();
    let body = b.add_body(rigid(
        "top",
        M,
        Vec3::new(0.0, 0.0, R),
        Mat3::from_diagonal(&Vec3::new(A, A, I3)),
        Vec3::zeros(),
        EulerParameters::from_axis_angle(&Vec3::y(), theta0).unwrap(),
        Some(Vec3::zeros()),
        Some(omega),
    )).unwrap();
    let support = marker(&mut b, "support", BodyRef::Ground, Vec3::zeros());
    let tip = marker(&mut b, "tip", BodyRef::Body(body), Vec3::zeros());
    let center = marker(&mut b, "center_marker", BodyRef::Body(body), Vec3::new(0.0, 0.0, R));
    joint(&mut b, "tip", JointKind::Spherical, support, tip);
    b.add_output("center", OutputKind::MarkerPosition(center)).unwrap();
    b.add_output("w", OutputKind::MarkerAngularVelocity(center)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    b.build().unwrap()
}

/// Spin `ω₃ = ω · axis` at every frame.
fn spin_rates(run: &Run) -> Vec<f64> {
    let (c, w) = (run.vec3("center"), run.vec3("w"));
    c.iter().zip(&w).map(|(c, w)| w.dot(&(c / R))).collect()
}

/// Largest |E − E₀| relative to the kinetic energy of the spin.
fn energy_drift(run: &Run) -> f64 {
    let e = run.col("energy.total");
    let scale = 0.5 * I3 * SPIN * SPIN;
    e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / scale
}

#[test]
fn horizontal_top_precesses_at_the_gyroscopic_rate() {
    let omega3 = SPIN; // axis ⟂ z, so the precession adds nothing along the axis
    let precession = M * G * R / (I3 * omega3);
    let period = 2.0 * PI / precession;
    let model = top(PI / 2.0, precession);
    let run = run(&model, &settings(2.0 * period, 1e-3, 1e-10));

    let centers = run.vec3("center");
    let phi = unwrap_angles(&centers.iter().map(|c| c.y.atan2(c.x)).collect::<Vec<_>>());
    let n = run.t.len();
    let measured = (phi[n - 1] - phi[0]) / (run.t[n - 1] - run.t[0]);
    let rel = (measured - precession).abs() / precession;
    // Uniform precession: the azimuth is linear in time at every frame, and the axis stays horizontal.
    let phase_error = max_over(n, |k| (phi[k] - phi[0] - precession * run.t[k]).abs());
    let nutation = max_over(n, |k| centers[k].z.abs() / R);
    let spin = spin_rates(&run);
    let spin_drift = max_over(n, |k| (spin[k] - spin[0]).abs()) / spin[0];
    let drift = energy_drift(&run);
    eprintln!(
        "horizontal top: Ω = {precession:.6} rad/s, measured {measured:.9} (rel {rel:.2e}); azimuth error {phase_error:.2e} rad; \
         nutation {nutation:.2e} rad; spin drift {spin_drift:.2e}; energy drift {drift:.2e}; steps {}",
        run.report.stats.steps
    );
    assert!(
        rel < 1e-6,
        "mean precession rate {measured} vs m g r/(I₃ ω₃) = {precession}: relative error {rel:e} > 1e-6"
    );
    assert!(phase_error < 1e-5, "azimuth departs from Ω t by {phase_error:e} rad > 1e-5 rad");
    assert!(nutation < 1e-5, "axis leaves the horizontal by {nutation:e} rad > 1e-5 rad (no nutation expected)");
    assert!((spin[0] - omega3).abs() < 1e-9 * omega3, "initial spin {} vs {omega3}", spin[0]);
    assert!(spin_drift < 1e-6, "spin about the symmetry axis drifts by {spin_drift:e} (relative) > 1e-6");
    assert!(drift < 1e-6, "energy drift {drift:e} of ½ I₃ ω₃² > 1e-6");
    assert!(run.report.max_normalization_error < 1e-14, "|pᵀp − 1| = {:e}", run.report.max_normalization_error);
}

/// `(θ, θ̇, φ)` of the Euler-angle equations at the times `times`, RK4 with step `h`.
fn euler_angle_reference(theta0: f64, phi_rate0: f64, times: &[f64], h: f64) -> Vec<(f64, f64)> {
    let i1 = i1();
    let omega3 = SPIN + phi_rate0 * theta0.cos();
    let p_phi = i1 * phi_rate0 * theta0.sin().powi(2) + I3 * omega3 * theta0.cos();
    let f = |y: [f64; 3]| {
        let (s, c) = y[0].sin_cos();
        let phi_rate = (p_phi - I3 * omega3 * c) / (i1 * s * s);
        let theta_acc = (i1 * phi_rate * phi_rate * s * c - I3 * omega3 * phi_rate * s + M * G * R * s) / i1;
        [y[1], theta_acc, phi_rate]
    };
    let mut y = [theta0, 0.0, 0.0];
    let mut t = 0.0;
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target - 1e-12 {
            let dt = h.min(target - t);
            let k1 = f(y);
            let k2 = f(std::array::from_fn(|i| y[i] + 0.5 * dt * k1[i]));
            let k3 = f(std::array::from_fn(|i| y[i] + 0.5 * dt * k2[i]));
            let k4 = f(std::array::from_fn(|i| y[i] + dt * k3[i]));
            y = std::array::from_fn(|i| y[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
            t += dt;
        }
        out.push((y[0], y[2]));
    }
    out
}

#[test]
fn tilted_top_follows_the_euler_angle_solution() {
    let theta0 = PI / 3.0;
    let omega3_guess = SPIN;
    let gyroscopic = M * G * R / (I3 * omega3_guess);
    let period = 2.0 * PI / gyroscopic;
    let model = top(theta0, gyroscopic);
    let run = run(&model, &settings(2.0 * period, 2e-3, 1e-10));
    let reference = euler_angle_reference(theta0, gyroscopic, &run.t, 1e-4);
    let centers = run.vec3("center");
    let n = run.t.len();
    let axis_error = max_over(n, |k| {
        let (theta, phi) = reference[k];
        let axis = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
        (centers[k] / R - axis).norm()
    });
    let theta_range = reference.iter().map(|r| r.0).fold(f64::NEG_INFINITY, f64::max)
        - reference.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
    let phi = unwrap_angles(&centers.iter().map(|c| c.y.atan2(c.x)).collect::<Vec<_>>());
    let duration = run.t[n - 1] - run.t[0];
    let mean_rate = (phi[n - 1] - phi[0]) / duration;
    let reference_rate = (reference[n - 1].1 - reference[0].1) / duration;
    let omega3 = SPIN + gyroscopic * theta0.cos();
    let i1 = i1();
    let steady = (I3 * omega3 - ((I3 * omega3).powi(2) - 4.0 * i1 * theta0.cos() * M * G * R).sqrt())
        / (2.0 * i1 * theta0.cos());
    // Fast-top estimate off by the first-order term ε = I₁ Ω cos θ / (I₃ ω₃) (8 % here): the mean rate
    // must lie between the gyroscopic value and the steady root Ω₀(1 + ε + O(ε²)) — the engine follows the
    // full equations, not the gyroscopic approximation.
    let eps = i1 * gyroscopic * theta0.cos() / (I3 * omega3);
    let excess = (mean_rate - gyroscopic) / gyroscopic;
    eprintln!(
        "tilted top: mean precession {mean_rate:.7} (Euler-angle reference {reference_rate:.7}), gyroscopic {gyroscopic:.6}, \
         steady root {steady:.6}; excess over gyroscopic {excess:.4} for ε = {eps:.4}"
    );
    let rel = (mean_rate - reference_rate).abs() / reference_rate;
    assert!(
        rel < 1e-6,
        "mean precession {mean_rate} vs Euler-angle reference {reference_rate}: relative {rel:e} > 1e-6"
    );
    assert!(
        excess > 0.5 * eps && mean_rate < steady,
        "mean precession {mean_rate} should exceed the gyroscopic {gyroscopic} by about ε = {eps:.3} and stay below the steady root {steady}"
    );
    let spin = spin_rates(&run);
    let spin_drift = max_over(n, |k| (spin[k] - spin[0]).abs()) / spin[0];
    let drift = energy_drift(&run);
    eprintln!(
        "tilted top: axis error vs Euler-angle RK4 {axis_error:.2e} rad over {:.2} s; nutation range of θ {theta_range:.2e} rad; \
         spin drift {spin_drift:.2e}; energy drift {drift:.2e}; steps {}",
        run.t[n - 1],
        run.report.stats.steps
    );
    // The comparison is not vacuous: the axis moves through a full turn of precession twice and nutates.
    assert!(theta_range > 1e-4, "the reference nutates: θ range {theta_range:e}");
    assert!(axis_error < 1e-5, "axis direction differs from the Euler-angle solution by {axis_error:e} > 1e-5 rad");
    assert!(spin_drift < 1e-6, "spin about the symmetry axis drifts by {spin_drift:e} (relative) > 1e-6");
    assert!(drift < 1e-6, "energy drift {drift:e} of ½ I₃ ω₃² > 1e-6");
}
