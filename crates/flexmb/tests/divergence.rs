//! The divergence check (`SimulationSettings::divergence_check`): a second run started 30 tolerances
//! away warns where the two separate exponentially, with the exponent, and stays silent where they do
//! not.

mod support;

use flexmb::analysis::{simulate, SimulationReport, SimulationSettings, WarningKind};
use flexmb::integrate::Tolerances;

fn run(theta0: f64, t_end: f64, tol: f64) -> SimulationReport {
    let model = support::pendulum(1.0, 1.0, 1e-6, theta0, 9.81).build().unwrap();
    let settings = SimulationSettings {
        t_end,
        output_step: 0.01,
        tolerances: Tolerances::new(tol, tol),
        divergence_check: true,
        ..Default::default()
    };
    simulate(&model, &settings, &mut |_| {}).unwrap()
}

/// The number after `key` in `message`.
fn number_after(message: &str, key: &str) -> f64 {
    let rest = &message[message.find(key).unwrap_or_else(|| panic!("no '{key}' in: {message}")) + key.len()..];
    rest.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-')).next().unwrap().parse().unwrap()
}

/// A pendulum (1 m, 1 kg, its own inertia 1e-6 kg m²) released at rest 1e-6 rad from upright: near the
/// top its angle from upright grows as `δ₀ cosh(λt)`, and any neighbouring motion separates from it as
/// `e^{λt}`, `λ = √(m g l / I_pivot)` = 3.1321 1/s. Over 3 s the angle stays below 0.01 rad (linear),
/// and the separation from A = 10 on is `e^{λt}` to `e^{−2λt}` ≈ 0.2 %: the warning gives λ within 1 %
/// and the time A passed 10, `ln 20 / λ` ≈ 0.96 s (from a separation in velocity, `cosh λt` ≈ `e^{λt}/2`),
/// within 0.1 s (the separation starts in the velocities only, and the weighted norm mixes the angle's
/// `sinh λt / λ` into it).
#[test]
fn escape_from_the_upright_pendulum_gives_its_exponent() {
    let report = run(std::f64::consts::PI - 1e-6, 3.0, 1e-8);
    let lambda = (9.81_f64 / (1.0 + 1e-6)).sqrt();
    let warnings: Vec<_> = report.warnings.iter().filter(|w| w.message.contains("separate exponentially")).collect();
    assert_eq!(warnings.len(), 1, "{:?}", report.warnings);
    let w = warnings[0];
    assert_eq!(w.kind, WarningKind::Tolerance);
    let exponent = number_after(&w.message, "Λ ≈ ");
    eprintln!("Λ = {exponent} 1/s against λ = {lambda} 1/s; from t = {} s", w.t);
    assert!((exponent / lambda - 1.0).abs() < 0.01, "Λ {exponent} against λ {lambda}: {}", w.message);
    assert!((w.t - 20.0_f64.ln() / lambda).abs() < 0.1, "from t = {} against {}", w.t, 20.0_f64.ln() / lambda);
}

/// The same pendulum swinging from 1 rad over 20 s (about ten periods): a neighbouring swing of another
/// energy drifts in phase, linearly in time, and the check does not warn.
#[test]
fn a_swinging_pendulum_does_not_warn() {
    let report = run(1.0, 20.0, 1e-8);
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
}
