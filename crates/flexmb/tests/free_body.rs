//! Torque-free asymmetric rigid body (no joints, no gravity) whose body frame is neither at the centre of
//! mass nor along principal axes, spinning about a direction that is not principal: kinetic energy,
//! linear momentum and angular momentum about the centre of mass are constants of the motion
//! (formulation.md §9), and the Euler parameters stay on the unit sphere.
//!
//! The conserved quantities are computed here from the state `y = [R, p, Ṙ, ω̄, …]` alone, not from the
//! engine's mass matrix: with `A = A(p)`, centre of mass `c̄` and inertia `J̄_c` about it (body axes),
//!
//! ```text
//! ṙ_c = Ṙ + A (ω̄ × c̄),   P = m ṙ_c,   H_c = A J̄_c ω̄,   T = ½ m |ṙ_c|² + ½ ω̄ᵀ J̄_c ω̄.
//! ```

mod support;

use std::sync::Arc;
use flexmb::analysis::{assemble, velocity_analysis, AccelerationSolver, State};
use flexmb::integrate::{Bdf, BdfConfig, Tolerances};
use flexmb::math::{EulerParameters, Mat3, Vec3, Vec4};
use flexmb::model::{Model, ModelBuilder};
use flexmb::Data;
use support::*;

const MASS: f64 = 2.5; // kg

fn com() -> Vec3 {
    Vec3::new(0.12, -0.07, 0.2) // m, body frame
}

/// Principal moments 0.10, 0.16, 0.21 kg m² about axes turned away from the body frame.
fn inertia() -> Mat3 {
    let q = EulerParameters::from_axis_angle(&Vec3::new(0.3, 1.0, -0.6), 0.9).unwrap().rotation_matrix();
    q * Mat3::from_diagonal(&Vec3::new(0.10, 0.16, 0.21)) * q.transpose()
}

fn free_body() -> Model {
    let mut b = ModelBuilder::new("free body");
    b.add_body(rigid(
        "tumbler",
        MASS,
        com(),
        inertia(),
        Vec3::new(0.3, -0.2, 1.0),
        EulerParameters::from_axis_angle(&Vec3::new(1.0, 2.0, 0.5), 0.7).unwrap(),
        Some(Vec3::new(0.4, 0.1, -0.3)),
        Some(Vec3::new(2.0, -3.5, 4.0)),
    )).unwrap();
    b.build().unwrap()
}

/// `(T, P, H_c)` from the state vector of the one body.
fn invariants(y: &[f64]) -> (f64, Vec3, Vec3) {
    let p = Vec4::new(y[3], y[4], y[5], y[6]);
    let a = EulerParameters(p).rotation_matrix();
    let r_dot = Vec3::new(y[7], y[8], y[9]);
    let w_bar = Vec3::new(y[10], y[11], y[12]);
    let v_c = r_dot + a * w_bar.cross(&com());
    let j = inertia();
    let kinetic = 0.5 * MASS * v_c.norm_squared() + 0.5 * w_bar.dot(&(j * w_bar));
    (kinetic, MASS * v_c, a * j * w_bar)
}

/// Largest relative drifts of `T`, `P`, `H_c` and of `|pᵀp − 1|` over 20 periods of `|ω|`, at every
/// accepted step with `rtol = atol = tol`; also how far the global `ω` wanders (relative) and the step count.
struct Drifts {
    energy: f64,
    linear: f64,
    angular: f64,
    norm: f64,
    omega_wander: f64,
    steps: usize,
}

fn drifts(tol: f64) -> Drifts {
    let model = free_body();
    let mut data = Data::new(&model);
    let mut state = State::initial(&model);
    assemble(&model, &mut data, &mut state, Default::default()).unwrap();
    velocity_analysis(&model, &mut data, &mut state).unwrap();
    let acc = AccelerationSolver::new(&model)
        .solve(&model, &mut data, 0.0, &state.q, &state.v, &state.active)
        .unwrap()
        .clone();
    let mut bdf = Bdf::new(Arc::new(model.clone()), &state, &acc, Tolerances::new(tol, tol), BdfConfig::default()).unwrap();

    let global_omega = |y: &[f64]| {
        EulerParameters(Vec4::new(y[3], y[4], y[5], y[6])).rotation_matrix() * Vec3::new(y[10], y[11], y[12])
    };
    let (t0, p0, h0) = invariants(bdf.y());
    let w0 = global_omega(bdf.y());
    let t_end = 20.0 * 2.0 * std::f64::consts::PI / w0.norm();
    let mut d = Drifts { energy: 0.0, linear: 0.0, angular: 0.0, norm: 0.0, omega_wander: 0.0, steps: 0 };
    while bdf.t() < t_end {
        bdf.step(t_end).unwrap();
        let y = bdf.y();
        let (t, p, h) = invariants(y);
        d.energy = d.energy.max((t - t0).abs() / t0);
        d.linear = d.linear.max((p - p0).norm() / p0.norm());
        d.angular = d.angular.max((h - h0).norm() / h0.norm());
        d.norm = d.norm.max((y[3..7].iter().map(|x| x * x).sum::<f64>() - 1.0).abs());
        d.omega_wander = d.omega_wander.max((global_omega(y) - w0).norm() / w0.norm());
    }
    d.steps = bdf.stats.steps;
    eprintln!(
        "free body, tol {tol:.0e}, 20 periods of |ω| ({:.1} s, {} steps): |ΔT|/T {:.2e}, |ΔP|/|P| {:.2e}, |ΔH_c|/|H_c| {:.2e}, \
         |pᵀp − 1| {:.2e}; global ω wanders by {:.2} of |ω₀|",
        bdf.t(),
        d.steps,
        d.energy,
        d.linear,
        d.angular,
        d.norm,
        d.omega_wander
    );
    d
}

#[test]
fn torque_free_body_conserves_energy_and_momenta() {
    let d = drifts(1e-9);
    // Not a trivial steady spin: the global angular velocity wanders (H is fixed, ω is not).
    assert!(d.omega_wander > 0.1, "the body tumbles: global ω changes by {} of its size", d.omega_wander);
    // Measured at rtol 1e-9: T 6.0e-7, P 9.2e-7, H 4.6e-8 (BDF is dissipative; these are global errors).
    assert!(d.energy < 2e-6, "kinetic energy drift {:e} (relative) > 2e-6 over 20 periods at rtol 1e-9", d.energy);
    assert!(d.linear < 3e-6, "linear momentum drift {:e} (relative) > 3e-6", d.linear);
    assert!(d.angular < 2e-7, "angular momentum about the centre of mass drifts by {:e} (relative) > 2e-7", d.angular);
    assert!(d.norm < 1e-14, "Euler-parameter norm off by {:e} > 1e-14 at an accepted step", d.norm);
}

/// The drifts are integration error, not a wrong term in the equations: they shrink with the tolerance.
#[test]
fn free_body_drifts_converge_with_the_tolerance() {
    let (loose, tight) = (drifts(1e-8), drifts(1e-10));
    for (what, a, b) in [
        ("kinetic energy", loose.energy, tight.energy),
        ("linear momentum", loose.linear, tight.linear),
        ("angular momentum", loose.angular, tight.angular),
    ] {
        assert!(a / b > 10.0, "{what} drift {a:e} at tol 1e-8 vs {b:e} at 1e-10: should shrink more than tenfold");
    }
}

#[test]
fn free_body_simulation_reports_unit_euler_parameters() {
    let model = free_body();
    let run = run(&model, &settings(10.0, 0.1, 1e-9));
    assert!(
        run.report.max_normalization_error < 1e-14,
        "report.max_normalization_error = {:e} ≥ 1e-14",
        run.report.max_normalization_error
    );
    assert_eq!(run.report.assembly.as_ref().unwrap().degrees_of_freedom, 6, "a free body has 6 degrees of freedom");
}
