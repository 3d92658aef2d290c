//! The published benchmarks of `models/benchmarks/` against their reference values: Andrews' squeezing
//! mechanism against the IVP test set's solution at t = 0.03 s, the IFToMM pendulum (A01) against the
//! closed forms of its energy and period, Bricard's mechanism (A04) with its redundant equation named and
//! its swings timed against a tight reference, and the stiff flyball governor (A05) keeping its angular
//! momentum about the shaft. Short runs at tight tolerances; the tolerances of the assertions are stated
//! with what was measured.

use crate::program;

use program::{scratch, succeed, ResultCsv};

/// Runs `models/benchmarks/MODEL.toml` with `integrator` at rtol = atol = `tol` and the extra `args` in a
/// scratch directory of its own (`test` names the test), and reads its result CSV.
fn run_benchmark(test: &str, model: &str, integrator: &str, tol: &str, args: &[&str]) -> ResultCsv {
    let dir = scratch(&format!("benchmark-{test}-{integrator}-{tol}"));
    let path = format!("models/benchmarks/{model}.toml");
    let out = dir.to_str().unwrap();
    let mut command = vec!["run", &path, "--integrator", integrator, "--rtol", tol, "--atol", tol, "--quiet", "--out", out];
    command.extend_from_slice(args);
    succeed(&command);
    ResultCsv::read(&dir.join(format!("{model}.csv")))
}

/// The times at which `x` changes sign between output times `t`, by linear interpolation.
fn sign_changes(t: &[f64], x: &[f64]) -> Vec<f64> {
    (1..t.len())
        .filter(|&k| x[k - 1] * x[k] < 0.0)
        .map(|k| t[k - 1] + (t[k] - t[k - 1]) * x[k - 1] / (x[k - 1] - x[k]))
        .collect()
}

/// The IVP test set's solution of Andrews' squeezer at t = 0.03 s (Mazzia, Magherini and Iavernaro,
/// release 2.3, problem "andrews", computed with PSIDE at rtol = atol = 1e-14): the seven angles (rad)
/// and their rates (rad/s), by the names of this model's measures.
const ANDREWS_AT_0_03: [(&str, f64, f64); 7] = [
    ("beta", 15.81077119629904, 1139.920302151208),
    ("Theta", -15.75637105984298, -1424.379294994111),
    ("gamma", 0.04082224013073101, 11.03291221937134),
    ("Phi", -0.5347301163226948, 19.29337464421385),
    ("delta", 0.5244099658805304, 0.5735699284790808),
    ("Omega", 0.5347301163226948, -19.29337464421385),
    ("epsilon", 1.048080741042263, 0.3231791658026955),
];

#[test]
fn andrews_squeezer_reaches_the_ivp_test_sets_solution_at_0_03_s() {
    // Measured at rtol = atol = 1e-10: the angles are off by at most 1.8e-9 rad (Adams, Θ) and 1.6e-7 rad
    // (BDF, Θ), the rates by 5.9e-7 and 6.4e-5 rad/s; at 1e-12 Adams reproduces the angles to 3e-10
    // relative. The bounds: 1e-6 rad and 1e-3 rad/s, 7 digits of β ≈ 15.8 rad and 6 of β̇ ≈ 1140 rad/s.
    // The BDF at 1e-9 over the run's span (the default): at 1e-10 its steps collapse to about 2e-8 s at the
    // share's floor `1e-12 / rtol` (docs/accuracy.md, "The default: error per unit step over the run"),
    // and 1e-9 resolves them better than 1e-10 per step did: Θ off by 2.1e-9 rad, its rate by 1.0e-7 rad/s.
    for (integrator, tol) in [("adams", "1e-10"), ("bdf", "1e-9")] {
        let csv = run_benchmark("andrews-reference", "andrews_squeezer", integrator, tol, &[]);
        assert!((csv.at(-1, "t") - 0.03).abs() < 1e-12);
        for (name, angle, rate) in ANDREWS_AT_0_03 {
            let angle_error = (csv.at(-1, name) - angle).abs();
            let rate_error = (csv.at(-1, &format!("{name}_rate")) - rate).abs();
            eprintln!("{integrator}: {name} off by {angle_error:.1e} rad, its rate by {rate_error:.1e} rad/s");
            assert!(angle_error < 1e-6, "{integrator}: {name} = {} against {angle}", csv.at(-1, name));
            assert!(rate_error < 1e-3, "{integrator}: {name}_rate = {} against {rate}", csv.at(-1, &format!("{name}_rate")));
        }
    }
}

#[test]
fn andrews_squeezer_gains_the_motors_work_and_switches_off_the_loops_repeated_rows() {
    // The IFToMM A03 energy balance: kinetic plus spring energy grows by the motor's work,
    // E − E0 = 0.033 N m × (β − β0), at every output time. Measured at 1e-10 with BDF, each step the whole
    // tolerance: 2.9e-9 J of 1.96 J; at 1e-9 over the run's span (the default; 1e-10 collapses its steps,
    // see the test above): 1.1e-10 J.
    let check = succeed(&["check", "models/benchmarks/andrews_squeezer.toml"]);
    assert!(check.contains("degrees of freedom: 1"), "{check}");
    assert!(check.contains("redundant constraints: 9"), "three repeated rows in each of the three loops: {check}");
    let csv = run_benchmark("andrews-energy", "andrews_squeezer", "bdf", "1e-9", &[]);
    let (energy, beta) = (csv.column("energy.total"), csv.column("beta"));
    let worst = energy.iter().zip(&beta).map(|(e, b)| (e - energy[0] - 0.033 * (b - beta[0])).abs()).fold(0.0, f64::max);
    eprintln!("energy balance off by {worst:.1e} J of {:.3} J", energy[energy.len() - 1]);
    assert!(worst < 1e-7, "E − E0 − mom (β − β0) = {worst:e} J");
    assert!(energy[energy.len() - 1] > 1.9, "the motor has put in about 2 J: {}", energy[energy.len() - 1]);
}

/// The complete elliptic integral of the first kind, `K(k) = π / (2 AGM(1, √(1 − k²)))`.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn the_iftomm_pendulum_keeps_its_energy_and_swings_with_the_closed_form_period() {
    // Released from the horizontal: T = 4 √(I_pivot / (m g L)) K(sin 45°), I_pivot = m L² + 1e-9 kg m²
    // (the lumped mass's own inertia), 2.367842 s. Over five swings at 1e-10 the measured period is the
    // closed form's to 7e-11 (Adams) and 1.1e-9 (BDF) relative; the energy stays within 1.9e-7 J of 0.
    let period = 4.0 * ((1.0 + 1e-9) / 9.81_f64).sqrt() * elliptic_k(std::f64::consts::FRAC_1_SQRT_2);
    for integrator in ["adams", "bdf"] {
        let csv = run_benchmark("a01", "simple_pendulum", integrator, "1e-10", &["--t-end", "12", "--output-step", "0.001"]);
        let crossings = sign_changes(&csv.column("t"), &csv.column("p1.position.x"));
        assert_eq!(crossings.len(), 10, "{integrator}: P1 passes below the pivot twice a period");
        let measured = 2.0 * (crossings[9] - crossings[0]) / 9.0;
        let energy = csv.column("energy.total").iter().fold(0.0_f64, |m, e| m.max(e.abs()));
        eprintln!("{integrator}: period {measured:.10} s against {period:.10} s, energy within {energy:.1e} J");
        assert!((measured / period - 1.0).abs() < 1e-8, "{integrator}: period {measured} s against {period} s");
        assert!((crossings[0] - period / 4.0).abs() < 1e-8, "{integrator}: first at the bottom at {} s", crossings[0]);
        assert!(energy < 1e-6, "{integrator}: energy {energy} J");
    }
}

#[test]
fn bricards_mechanism_names_its_redundant_equation_and_swings_as_the_tight_reference() {
    // Six revolutes, 30 equations on 30 coordinates: one equation repeats the others. Released from rest,
    // the loop swings to its mirror image in x = 0 and back; link 1's end crosses x = 0 at the times of
    // flexmb's Adams at 1e-12 (BDF at 1e-11 agrees to 2e-9 s). At 1e-9 BDF is 4.7e-8 s off at the fourth
    // crossing, Adams 1e-9 s; the bounds are 5e-7 s, and the energy (measured spread 5.1e-7 J) 1e-5 J.
    let check = succeed(&["check", "models/benchmarks/bricard_mechanism.toml"]);
    assert!(check.contains("degrees of freedom: 1"), "{check}");
    assert!(check.contains("redundant constraints: 1 ") && check.contains("joint 'j6' (revolute), equation 5"), "{check}");
    let reference = [1.247927878, 3.743783635, 6.239639392, 8.735495149];
    for integrator in ["adams", "bdf"] {
        let csv = run_benchmark("a04", "bricard_mechanism", integrator, "1e-9", &["--output-step", "0.001"]);
        let x = csv.column("link1_end.position.x");
        let crossings = sign_changes(&csv.column("t"), &x);
        assert_eq!(crossings.len(), 4, "{integrator}: {crossings:?}");
        for (measured, expected) in crossings.iter().zip(reference) {
            assert!((measured - expected).abs() < 5e-7, "{integrator}: crosses at {measured} s, the reference at {expected} s");
        }
        let mirror = x.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        assert!((mirror + 1.0).abs() < 1e-5, "{integrator}: link 1's end reaches x = {mirror} m, the mirror image -1 m");
        let energy = csv.column("energy.total");
        let spread = energy.iter().fold(f64::NEG_INFINITY, |m, &e| m.max(e)) - energy.iter().fold(f64::INFINITY, |m, &e| m.min(e));
        assert!(spread < 1e-5, "{integrator}: energy spread {spread} J");
    }
}

#[test]
fn the_flyball_governor_keeps_its_angular_momentum_about_the_shaft_while_its_dampers_take_energy_out() {
    // No torque acts about the shaft: L_z = ω (J_shaft + J_slider + 2 J_arm(α)) is conserved, with each
    // arm (rod and ball) at the angle α below the horizontal: J_arm = J_t cos²α + J_a sin²α + m ρ²,
    // ρ = 0.05 m + c cos α the radius of its centre of mass. The arms' swing about their hinges adds
    // nothing about z. Measured with BDF at 1e-10: L_z constant to 1.5e-8 relative (3e-10 at 1e-12);
    // s(10 s) 0.619622915 m against the tight reference 0.61962291706 m (Adams and BDF at 1e-12).
    let m_bar = 3000.0 * 1.0 * 0.01 * 0.01;
    let (j_axial, j_transverse) = (m_bar * (0.01_f64.powi(2) * 2.0) / 12.0, m_bar * (1.0 + 0.01_f64.powi(2)) / 12.0);
    let j_slider = 3.0 * (0.1_f64.powi(2) * 2.0) / 12.0;
    let m_arm = m_bar + 5.0;
    let c = (m_bar * 0.5 + 5.0) / m_arm;
    let j_arm_t = j_transverse + m_bar * (0.5 - c).powi(2) + 5.0 * (1.0 - c).powi(2);
    let csv = run_benchmark("a05", "flyball_governor", "bdf", "1e-10", &[]);
    let (omega, alpha, energy) = (csv.column("shaft_speed"), csv.column("arm_angle"), csv.column("energy.total"));
    let momentum: Vec<f64> = omega
        .iter()
        .zip(&alpha)
        .map(|(w, a)| {
            let rho = 0.05 + c * a.cos();
            w * (j_axial + j_slider + 2.0 * (j_arm_t * a.cos().powi(2) + j_axial * a.sin().powi(2) + m_arm * rho * rho))
        })
        .collect();
    let drift = momentum.iter().map(|l| (l / momentum[0] - 1.0).abs()).fold(0.0, f64::max);
    eprintln!("angular momentum {:.6} kg m²/s, kept to {drift:.1e}", momentum[0]);
    assert!(drift < 1e-7, "L_z drifts by {drift:e} of itself");
    assert!(omega[omega.len() - 1] < 0.9 * omega[0], "the arms rise and the shaft slows: {} rad/s", omega[omega.len() - 1]);
    assert!(energy.windows(2).all(|e| e[1] <= e[0] + 1e-7), "the dampers only take energy out");
    let s = csv.at(-1, "slider_centre.position.z");
    assert!((s - 0.61962291706).abs() < 1e-7, "the slider at 10 s: {s} m");
}
