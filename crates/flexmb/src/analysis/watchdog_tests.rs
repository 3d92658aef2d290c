//! The physics watchdog's measures on states and powers made up for the purpose; a run that leaves
//! physics is tested through `flexmb run` (crates/flexmb-cli/tests/commands/physics_watchdog.rs).

use super::watchdog::{Deflection, EnergyFlow, PhysicsLimits, Unphysical, Watchdog};
use crate::analysis::test_models::double_pendulum_with_spring;
use crate::stage::Energy;

#[test]
fn thresholds_are_positive_and_each_warning_is_at_most_its_limit() {
    assert_eq!(PhysicsLimits::default().validate(), Ok(()));
    let warning_above_limit = PhysicsLimits { energy_balance_warning: 0.6, ..Default::default() };
    let e = warning_above_limit.validate().unwrap_err();
    assert!(e.contains("energy_balance_warning (0.6) must not exceed energy_balance_limit (0.5)"), "{e}");
    let negative = PhysicsLimits { elastic_deflection_limit: -1.0, ..Default::default() };
    assert!(negative.validate().unwrap_err().contains("must be positive"));
    let nan = PhysicsLimits { elastic_deflection_warning: f64::NAN, ..Default::default() };
    assert!(nan.validate().is_err());
}

#[test]
fn a_non_finite_coordinate_is_named_by_body_and_index() {
    let model = double_pendulum_with_spring();
    let (nq, nv) = (model.layout.nq, model.layout.nv);
    let (mut q, v) = (vec![0.0; nq], vec![0.0; nv]);
    assert_eq!(Watchdog::check_finite(&model, 0.5, &q, &v), Ok(()));
    q[model.layout.q_offset[1] + 4] = f64::NAN;
    let e = Watchdog::check_finite(&model, 0.5, &q, &v).unwrap_err();
    assert!(matches!(e, Unphysical::NonFinite { t, .. } if t == 0.5), "{e:?}");
    assert!(e.to_string().contains("position coordinate 4 of body 'link2' is NaN"), "{e}");
    let mut v = v;
    q[model.layout.q_offset[1] + 4] = 0.0;
    v[2] = f64::INFINITY;
    let e = Watchdog::check_finite(&model, 0.5, &q, &v).unwrap_err();
    assert!(e.to_string().contains("velocity coordinate 2 of body 'link1' is inf"), "{e}");
}

/// The powers of `P(t) = c t²` at `t = 0, h, 2h, …` and the energy `∫ P`: the trapezoidal rule
/// overestimates each interval by `h³/12 · 2c`, which the second differences find exactly.
fn quadratic_power(flow: &mut EnergyFlow, c: f64, h: f64, frames: usize) -> (f64, f64) {
    let mut trapezoid = 0.0;
    for k in 0..frames {
        let t = k as f64 * h;
        let energy = Energy { kinetic: c * t.powi(3) / 3.0, ..Default::default() };
        flow.add(t, &energy, c * t * t);
        if k > 0 {
            let t0 = t - h;
            trapezoid += 0.5 * (c * t0 * t0 + c * t * t) * h;
        }
    }
    let t = (frames - 1) as f64 * h;
    (trapezoid, c * t.powi(3) / 3.0)
}

#[test]
fn the_energy_that_flowed_and_the_quadrature_error_of_the_balance() {
    let (c, h) = (3.0, 0.01);
    let mut flow = EnergyFlow::default();
    let (trapezoid, exact) = quadratic_power(&mut flow, c, h, 101);
    // The scale: ∫|P| by the trapezoidal rule (above the energy c t³/3 it brought).
    assert!((flow.scale() - trapezoid).abs() < 1e-12 * trapezoid, "{} against {trapezoid}", flow.scale());
    // The estimate: the first interval h |ΔP| / 4, then h³/12 · 2c per interval, exactly.
    let estimate = h * c * h * h / 4.0 + 99.0 * h.powi(3) / 12.0 * 2.0 * c;
    assert!((flow.quadrature_error - estimate).abs() < 1e-9 * estimate, "{} against {estimate}", flow.quadrature_error);
    let quadrature_error = trapezoid - exact;
    assert!(quadrature_error > 0.0 && quadrature_error < flow.quadrature_error);
    // A balance off by the quadrature alone is explained; 10 % of the energy more is not.
    assert_eq!(flow.unexplained_fraction(-quadrature_error, 0.0), 0.0);
    let off = -quadrature_error - 0.1 * trapezoid;
    let fraction = flow.unexplained_fraction(off, 0.0);
    assert!((fraction - 0.1).abs() < 3.0 * flow.quadrature_error / trapezoid, "{fraction}");
    // What the tolerance allows is subtracted too.
    assert_eq!(flow.unexplained_fraction(off, 0.2 * trapezoid), 0.0);
}

#[test]
fn the_largest_energy_seen_is_a_scale_too() {
    // A conservative swing: no power, kinetic and potential energy exchanged.
    let mut flow = EnergyFlow::default();
    for (k, (kinetic, potential)) in [(0.0, -2.0), (1.5, -3.5), (0.5, -2.5)].into_iter().enumerate() {
        flow.add(k as f64 * 0.1, &Energy { kinetic, potential, strain: 0.0 }, 0.0);
    }
    assert_eq!(flow.scale(), 5.0);
    assert_eq!(flow.unexplained_fraction(0.5, 0.0), 0.1);
}

fn deflection(angular_velocity: f64) -> Deflection {
    Deflection {
        t: 9.0,
        body: "beam".into(),
        node: 11,
        deflection: 5.0,
        size: 10.0,
        threshold: 0.5,
        angular_velocity,
        lowest_frequency: Some(3.8),
        geometric_stiffening: false,
    }
}

#[test]
fn a_deflection_is_explained_by_the_spin_when_the_body_turns_fast() {
    let spinning = deflection(4.5).describe("elastic_deflection_limit");
    for part in [
        "flexible body 'beam' is 5.000e0 m at node 11, 50 % of its size 10.000 m",
        "[simulation] elastic_deflection_limit = 0.5",
        "turns at 4.500 rad/s, above its lowest modal frequency 3.800 rad/s",
        "without geometric (centrifugal) stiffening",
        "split it into several flexible bodies",
    ] {
        assert!(spinning.contains(part), "{part}: {spinning}");
    }
    assert!(deflection(2.0).describe("x").contains("more than half its lowest modal frequency"));
    let stiffened = Deflection { geometric_stiffening: true, ..deflection(4.5) }.describe("x");
    assert!(!stiffened.contains("centrifugal") && stiffened.contains("small elastic displacements only"), "{stiffened}");
    let slow = deflection(0.1).describe("elastic_deflection_warning");
    assert!(!slow.contains("centrifugal") && slow.contains("small elastic displacements only"), "{slow}");
}
