//! `flexmb linearize` and `flexmb eigen` as a user runs them: the matrices of a hanging pendulum and its
//! state-space model against the closed form (read back from the Matrix Market files), a clamped
//! flexible cantilever against its FE model's frequencies, a four-bar's linear frequency against the
//! spectrum of a small-amplitude simulation, a tilting rotor's whirl swept over its spin against the
//! closed form, and the errors of bad requests.

use std::path::Path;

use flexmb_files::matrix_market::read_matrix_market;
use serde_json::Value;

use crate::program;

use program::{fail, flexmb, scratch, succeed, text, workspace};

const MODELS: &str = "crates/flexmb-cli/tests/models/linear_analysis";

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn frequencies(eigen: &Value) -> Vec<f64> {
    eigen["modes"].as_array().unwrap().iter().filter(|m| !m["rigid_body"].as_bool().unwrap()).map(|m| m["frequency_hz"].as_f64().unwrap()).collect()
}

/// The pendulum hanging at rest with a torque input and its angle as output: `M = I + m L²`,
/// `K = m g L`, `C = 0`, `A = [0 1; −K/M 0]`, `B = [0; 1/M]`, `C_out = [1 0]`, `D = 0`.
#[test]
fn a_hanging_pendulum_linearizes_to_its_closed_form_state_space() {
    let out = scratch("linearize_pendulum");
    let model = format!("{MODELS}/hanging_pendulum.toml");
    let stdout = succeed(&["linearize", &model, "--input", "drive.z", "--output", "pivot_angle", "--out", out.to_str().unwrap()]);
    assert!(stdout.contains("1 degrees of freedom (pendulum.theta.z)"), "{stdout}");
    let (l, m, ic, g) = (0.8, 1.5, 0.02, 9.81);
    let (mass, stiffness) = (ic + m * l * l, m * g * l);
    let read = |name: &str| read_matrix_market(&out.join(format!("{name}.mtx"))).unwrap();
    let close = |found: f64, exact: f64, what: &str| {
        let error = (found - exact).abs() / exact.abs().max(1.0);
        eprintln!("pendulum {what}: {found:e} against {exact:e} ({error:.1e})");
        assert!(error < 1e-9, "{what}: {found} against {exact}");
    };
    close(read("M").get(0, 0), mass, "M");
    close(read("K").get(0, 0), stiffness, "K");
    close(read("C").get(0, 0), 0.0, "C");
    let a = read("A");
    assert_eq!((a.rows, a.cols), (2, 2));
    close(a.get(0, 1), 1.0, "A[0,1]");
    close(a.get(1, 0), -stiffness / mass, "A[1,0]");
    close(read("B").get(1, 0), 1.0 / mass, "B[1,0]");
    let c = read("C_out");
    close(c.get(0, 0), 1.0, "C_out[0,0]");
    close(c.get(0, 1), 0.0, "C_out[0,1]");
    close(read("D").get(0, 0), 0.0, "D");
    let summary = json(&out.join("linearization.json"));
    assert_eq!(summary["coordinates"][0], "pendulum.theta.z");
    assert_eq!(summary["state_space"]["inputs"][0], "drive.z");
}

/// A mass on a spring-damper `(k, c)` whose base is driven, the driver's offset, rate and acceleration
/// as inputs: `B = [0 0 0; k/m c/m 0]` (`m z̈ + c (ż − u̇) + k (z − u) = 0`), and the spring's stretch
/// `z − u` reads the offset through `D = [−1 0 0]`.
#[test]
fn a_driven_base_is_an_input_through_its_offset_rate_and_acceleration() {
    let out = scratch("linearize_base_excited");
    let model = format!("{MODELS}/base_excited.toml");
    let drive = ["--input", "base_drive", "--input", "base_drive.rate", "--input", "base_drive.acceleration"];
    let args = [&["linearize", &model][..], &drive[..], &["--output", "height", "--output", "stretch", "--out", out.to_str().unwrap()][..]].concat();
    let stdout = succeed(&args);
    assert!(stdout.contains("1 degrees of freedom (mass.R.z)"), "{stdout}");
    let (m, k, c) = (2.0, 800.0, 6.0);
    let (b, d) = (read_matrix_market(&out.join("B.mtx")).unwrap(), read_matrix_market(&out.join("D.mtx")).unwrap());
    let exact_b = [k / m, c / m, 0.0];
    let exact_d = [[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]];
    let mut worst = 0.0_f64;
    for j in 0..3 {
        worst = worst.max(b.get(0, j).abs()).max((b.get(1, j) - exact_b[j]).abs() / (k / m));
        for r in 0..2 {
            worst = worst.max((d.get(r, j) - exact_d[r][j]).abs());
        }
    }
    eprintln!("base-excited mass: B and D against the closed form, largest relative error {worst:.1e}");
    assert!(worst < 1e-8, "{worst:.1e}");
}

/// The FE cantilever clamped by a fixed joint at its clamped node: with vibration modes only (4N, the
/// FE model's clamped modes) the mechanism's frequencies are the FE frequencies; with 2 static
/// correction modes added (4N2S) the lowest four are those of the enlarged (Craig–Bampton-like) basis:
/// not below the FE ones (Rayleigh–Ritz), within 10⁻³.
#[test]
fn a_clamped_flexible_cantilever_has_its_fe_frequencies() {
    let fe_out = scratch("linear_cantilever_fe");
    let body = fe_out.join("arm.json");
    succeed(&["modes", "models/fe/cantilever.toml", "--modes", "4N", "--out", body.to_str().unwrap()]);
    let fe = json(&body)["fe_frequencies_hz"].as_array().unwrap().iter().map(|f| f.as_f64().unwrap()).collect::<Vec<_>>();
    let out = scratch("linear_cantilever");
    succeed(&["eigen", &format!("{MODELS}/clamped_cantilever.toml"), "--out", out.to_str().unwrap()]);
    let found = frequencies(&json(&out.join("eigen.json")));
    assert_eq!(found.len(), 4);
    let error = (0..4).map(|k| (found[k] - fe[k]).abs() / fe[k]).fold(0.0, f64::max);
    eprintln!("clamped cantilever 4N: {found:?} Hz against FE {:?} Hz, largest relative error {error:.1e}", &fe[..4]);
    assert!(error < 1e-8);

    // The same body with the static correction modes of the file's 4N2S set.
    let model = std::fs::read_to_string(workspace().join(MODELS).join("clamped_cantilever.toml")).unwrap();
    let cantilever = workspace().join("models/fe/cantilever.toml");
    let model = model.replace("../../../../../models/fe/cantilever.toml", cantilever.to_str().unwrap()).replace("modes = \"4N\"", "modes = \"4N2S\"");
    let with_statics = out.join("clamped_4n2s.toml");
    std::fs::write(&with_statics, model).unwrap();
    succeed(&["eigen", with_statics.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let found = frequencies(&json(&out.join("eigen.json")));
    assert_eq!(found.len(), 6);
    let error = (0..4).map(|k| (found[k] - fe[k]) / fe[k]).fold(0.0, f64::max);
    eprintln!("clamped cantilever 4N2S: {found:?} Hz, largest relative difference of the lowest four {error:.1e}");
    assert!(error < 1e-3 && (0..4).all(|k| found[k] >= fe[k] * (1.0 - 1e-9)));
}

/// The four-bar held by a crank spring, at rest, against a simulation started from there with a crank
/// speed of 0.02 rad/s (amplitude 1.1 mrad): the spectrum's peak of the crank angle at the linear
/// frequency, to the estimator's refinement and the amplitude's nonlinear shift.
#[test]
fn a_four_bar_swings_at_its_linear_frequency() {
    let out = scratch("linear_four_bar");
    let model = format!("{MODELS}/four_bar_spring.toml");
    succeed(&["eigen", &model, "-p", "w0=0", "--out", out.to_str().unwrap()]);
    let linear = frequencies(&json(&out.join("eigen.json")));
    assert_eq!(linear.len(), 1);
    succeed(&["run", &model, "--out", out.to_str().unwrap(), "--quiet"]);
    let csv = out.join("four_bar_spring.csv");
    let spectrum = succeed(&["spectrum", csv.to_str().unwrap(), "--y", "crank_angle", "--peaks", "1"]);
    let line = spectrum.lines().find(|l| l.trim_start().starts_with("1 ")).unwrap();
    let peak: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    let error = (peak - linear[0]).abs() / linear[0];
    eprintln!("four-bar: linear {:.9} Hz, spectrum of the simulation {peak:.6} Hz, relative difference {error:.1e}", linear[0]);
    assert!(error < 1e-5, "{spectrum}");
}

/// The tilting rotor swept over its spin: forward and backward whirl at each speed against the closed
/// form, the housing's torsion unchanged.
#[test]
fn a_tilting_rotor_sweep_gives_the_closed_form_whirl() {
    let out = scratch("linear_rotor_sweep");
    let stdout = succeed(&["eigen", &format!("{MODELS}/tilting_rotor.toml"), "--sweep", "spin=100:400:4", "--out", out.to_str().unwrap()]);
    assert!(stdout.contains("(backward)") && stdout.contains("(forward)"), "{stdout}");
    let sweep = json(&out.join("sweep.json"));
    let (it, ip, ktheta): (f64, f64, f64) = (0.03, 0.035, 2.0 * 2.0e4 * 0.1 * 0.1);
    let mut worst = 0.0_f64;
    for (k, spin) in [100.0, 200.0, 300.0, 400.0].into_iter().enumerate() {
        let f: Vec<f64> = sweep["frequencies_hz"][k].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let whirl: Vec<&str> = sweep["whirl"][k].as_array().unwrap().iter().map(|x| x.as_str().unwrap()).collect();
        let root = (ip * ip * spin * spin + 4.0 * it * ktheta).sqrt();
        let (backward, forward) = ((root - ip * spin) / (2.0 * it) / std::f64::consts::TAU, (root + ip * spin) / (2.0 * it) / std::f64::consts::TAU);
        assert_eq!((whirl[0], whirl[2]), ("backward", "forward"));
        worst = worst.max((f[0] - backward).abs() / backward).max((f[2] - forward).abs() / forward);
    }
    eprintln!("tilting rotor sweep: largest relative error of the whirl frequencies {worst:.1e}");
    assert!(worst < 1e-7);
    assert!(std::fs::read_to_string(out.join("sweep.csv")).unwrap().starts_with("spin,mode1_hz,mode1_damping_ratio,mode1_whirl"));
}

/// The tilting rotor swept from rest to 600 rad/s: the backward whirl falls through the housing's
/// torsion mode (15.57 Hz) between 0 and 50 rad/s. Followed by their shapes the modes keep their
/// columns through the crossing: column 1 the torsion at its constant frequency (whirl none), column 2
/// the backward and column 3 the forward whirl at every speed, each at the closed form; where sorting
/// by frequency would have put the backward whirl in column 1 from 50 rad/s on. The Campbell
/// diagram's 1× line then crosses the torsion at `2π × 15.57` rad/s.
#[test]
fn a_sweep_follows_crossing_modes_by_their_shapes() {
    let out = scratch("linear_rotor_crossing");
    let stdout = succeed(&["eigen", &format!("{MODELS}/tilting_rotor.toml"), "--sweep", "spin=0:600:13", "--plot", "--one-per-rev", "0.15915494309189535", "--out", out.to_str().unwrap()]);
    let sweep = json(&out.join("sweep.json"));
    let (it, ip, ktheta): (f64, f64, f64) = (0.03, 0.035, 2.0 * 2.0e4 * 0.1 * 0.1);
    let torsion = sweep["frequencies_hz"][0][0].as_f64().unwrap();
    let mut worst = 0.0_f64;
    for k in 1..13 {
        let spin = 50.0 * k as f64;
        let f: Vec<f64> = sweep["frequencies_hz"][k].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let whirl: Vec<&str> = sweep["whirl"][k].as_array().unwrap().iter().map(|x| x.as_str().unwrap()).collect();
        assert_eq!(whirl, ["none", "backward", "forward"], "spin {spin}");
        let root = (ip * ip * spin * spin + 4.0 * it * ktheta).sqrt();
        let (backward, forward) = ((root - ip * spin) / (2.0 * it) / std::f64::consts::TAU, (root + ip * spin) / (2.0 * it) / std::f64::consts::TAU);
        worst = worst.max((f[0] - torsion).abs() / torsion).max((f[1] - backward).abs() / backward).max((f[2] - forward).abs() / forward);
        assert!(f[1] < f[0], "the backward whirl has crossed below the torsion at {spin}: {f:?}");
    }
    let at_rest: Vec<f64> = sweep["frequencies_hz"][0].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(at_rest[1] > at_rest[0], "at rest the tilt modes are above the torsion: {at_rest:?}");
    eprintln!("tilting rotor through the crossing: largest relative error of the followed curves {worst:.1e}");
    assert!(worst < 1e-7);
    let critical = stdout.lines().find(|l| l.contains("crosses mode 1 at")).unwrap_or_else(|| panic!("{stdout}"));
    let value: f64 = critical.split("spin = ").nth(1).unwrap().split_whitespace().next().unwrap().parse().unwrap();
    assert!((value - torsion * std::f64::consts::TAU).abs() < 1e-6 * value, "{critical}");
    assert!(out.join("campbell.png").exists());
}

/// Requests that cannot be met are refused with what was wrong.
#[test]
fn bad_requests_are_refused_with_a_message() {
    let model = format!("{MODELS}/hanging_pendulum.toml");
    let out = scratch("linear_bad");
    let o = out.to_str().unwrap();
    assert!(fail(&["eigen", &model, "--at", "rest", "--out", o]).contains("--at: expected `initial` or `equilibrium`, got `rest`"));
    let e = fail(&["linearize", &model, "--input", "motor", "--out", o]);
    assert!(e.contains("input 'motor' is not a force element or driver of the model: inputs are drive.x"), "{e}");
    let e = fail(&["linearize", &model, "--input", "drive", "--out", o]);
    assert!(e.contains("the applied torque 'drive' is an input as NAME.x, NAME.y or NAME.z"), "{e}");
    let e = fail(&["linearize", &model, "--output", "height", "--out", o]);
    assert!(e.contains("the model has no measure 'height': it has pivot_angle"), "{e}");
    let e = text(&flexmb(&["eigen", &model, "--sweep", "L=1:2", "--out", o]).stderr);
    assert!(e.contains("expected NAME=START:STOP:COUNT"), "{e}");
    let e = fail(&["eigen", &model, "--sweep", "length=1:2:3", "--out", o]);
    assert!(e.contains("length"), "{e}");
    // A simulated operating point: the pendulum at rest stays where it is.
    let stdout = succeed(&["eigen", &model, "--at-time", "0.5", "--out", o]);
    assert!(stdout.contains("at the simulated state at t = 0.5 s"), "{stdout}");
}

/// The shipped pendulum starts swung 60° from hanging; linearized `--at equilibrium` it is the pendulum
/// hanging at rest: `M = I + m L²`, `K = m g L`, and `flexmb eigen --at equilibrium` gives
/// `√(K/M)/2π` (`--at initial` linearizes the swung, accelerating state instead).
#[test]
fn the_pendulum_linearized_at_its_equilibrium_hangs() {
    let model = format!("{}/../../models/pendulum.toml", env!("CARGO_MANIFEST_DIR"));
    let out = scratch("linearize_pendulum_equilibrium");
    let o = out.to_str().unwrap();
    succeed(&["linearize", &model, "--at", "equilibrium", "--out", o]);
    let (l, m, r, g) = (1.0, 1.0, 0.02, 9.81);
    let (mass, stiffness) = (0.4 * m * r * r + m * l * l, m * g * l);
    let read = |name: &str| read_matrix_market(&out.join(format!("{name}.mtx"))).unwrap().get(0, 0);
    let (em, ek) = ((read("M") - mass).abs() / mass, (read("K") - stiffness).abs() / stiffness);
    eprintln!("pendulum at its equilibrium: M error {em:.1e}, K error {ek:.1e}");
    assert!(em < 1e-9 && ek < 1e-7, "M {} K {}", read("M"), read("K"));
    succeed(&["eigen", &model, "--at", "equilibrium", "--vtk", "--out", o]);
    let f = frequencies(&json(&out.join("eigen.json")));
    let exact = (stiffness / mass).sqrt() / std::f64::consts::TAU;
    eprintln!("pendulum at its equilibrium: frequency {:e} against {exact:e}", f[0]);
    assert!((f[0] - exact).abs() / exact < 1e-7, "{f:?}");
    assert!(out.join("pendulum_mode_1.pvd").exists(), "the mode's animation is written");
}
