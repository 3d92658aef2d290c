//! `flexmb modes` as a new user runs it: the shipped FE models reduce to flexible-body files whose
//! frequencies are printed, mode shapes are written for ParaView, `.inp` meshes are read directly, the
//! lumped or consistent mass is chosen in the file or on the command line, and bad requests are
//! refused with a message.


use std::path::Path;

use flexmb_fem::reduction::{Basis, BodyMass, FlexibleBody};

use crate::program;

use program::{fail, flexmb, scratch, succeed, text, workspace};

#[test]
fn modes_of_the_shipped_cantilever_write_a_flexible_body_and_mode_shapes() {
    let out = scratch("cantilever");
    let body_path = out.join("arm.json");
    let o = flexmb(&["modes", "models/fe/cantilever.toml", "--out", body_path.to_str().unwrap(), "--vtk", out.to_str().unwrap()]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "stdout:\n{stdout}\nstderr:\n{}", text(&o.stderr));
    assert!(stdout.contains("mode set 4N2S"), "{stdout}");
    assert!(stdout.contains("FE f [Hz]") && stdout.contains("reduced f [Hz]"), "{stdout}");
    let body = FlexibleBody::read(&body_path).unwrap();
    assert_eq!(body.mode_count(), 6);
    assert_eq!(body.basis, Basis::Orthonormal);
    assert_eq!(body.nodes.len(), 21);
    // The first frequency printed is the first bending mode of the 1 m steel bar (20 × 10 mm), about the
    // weak axis: Euler–Bernoulli gives 8.355 Hz; the lumped 20-element model with rotary inertia 8.341 Hz.
    assert!((body.fe_frequencies_hz[0] - 8.3414).abs() < 1e-3, "{}", body.fe_frequencies_hz[0]);
    assert!(stdout.contains("8.341"), "{stdout}");
    let vtu = std::fs::read_to_string(out.join("cantilever_modes.vtu")).unwrap();
    assert!(vtu.contains("NumberOfPoints=\"21\"") && vtu.contains("NumberOfCells=\"20\""), "{}", &vtu[..300]);
    assert!(vtu.contains("O1 translation"));
}

#[test]
fn command_line_mode_set_and_raw_basis_override_the_file() {
    let out = scratch("raw");
    let body_path = out.join("arm.json");
    let o = flexmb(&["modes", "models/fe/cantilever.toml", "--modes", "3N1S", "--basis", "raw", "--out", body_path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let body = FlexibleBody::read(&body_path).unwrap();
    let labels: Vec<&str> = body.modes.iter().map(|m| m.label.as_str()).collect();
    assert_eq!(labels, ["N1", "N2", "N3", "S1"]);
    assert_eq!(body.basis, Basis::Raw);
}

#[test]
fn the_plate_reports_the_rigid_motions_its_supports_leave() {
    let out = scratch("plate");
    let o = flexmb(&["modes", "models/fe/plate.toml", "--out", out.join("plate.json").to_str().unwrap()]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "stdout:\n{stdout}\nstderr:\n{}", text(&o.stderr));
    assert!(stdout.contains("3 rigid motion(s)"), "{stdout}");
}

#[test]
fn an_inp_mesh_is_read_directly() {
    let out = scratch("inp");
    let o = flexmb(&[
        "modes",
        "crates/flexmb-fem/tests/data/cantilever_b31.inp",
        "--modes",
        "4N",
        "--out",
        out.join("b31.json").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "stdout:\n{}\nstderr:\n{}", text(&o.stdout), text(&o.stderr));
    assert!(FlexibleBody::read(&out.join("b31.json")).unwrap().mode_count() == 4);
}

#[test]
fn bad_requests_are_refused_with_a_message() {
    let o = flexmb(&["modes", "models/fe/cantilever.toml", "--modes", "4X", "--out", "/dev/null"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("--modes: mode set `4X`"), "{}", text(&o.stderr));
    let o = flexmb(&["modes", "crates/flexmb-fem/tests/data/cantilever_b31.inp"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("no mode set"), "{}", text(&o.stderr));
    let o = flexmb(&["modes", "models/fe/cantilever.toml", "--modes", "300N", "--out", "/dev/null"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("asked for 300 vibration modes"), "{}", text(&o.stderr));
}

/// A steel cantilever 1 m long of 20 Euler–Bernoulli beam elements, clamped at x = 0, without rotary
/// inertia; its 10 mm square section bends alike in both planes, so its bending modes come in pairs.
/// `fe_model_keys` go into `[fe_model]`.
fn square_cantilever(fe_model_keys: &str) -> String {
    format!(
        r#"[fe_model]
name = "square_cantilever"
{fe_model_keys}

[[material]]
name = "steel"
E = 210e9
nu = 0.3
rho = 7850

[[beam_section]]
name = "square"
material = "steel"
shape = "rectangle"
width = 0.01
height = 0.01
orientation = [0, 1, 0]

[[beam_line]]
name = "arm"
section = "square"
from = [0, 0, 0]
to = [1, 0, 0]
elements = 20

[[support]]
at = "arm.start"
dofs = "all"
"#
    )
}

/// Roots of `cos βL cosh βL = −1`: the cantilever's first five bending modes.
const CANTILEVER_BETA_L: [f64; 5] = [1.8751041, 4.6940911, 7.8547574, 10.9955407, 14.1371684];

/// Euler–Bernoulli's bending frequency `(βL)² / (2π L²) √(EI / ρA)` of the square cantilever.
fn euler_bernoulli_hz(beta_l: f64) -> f64 {
    let (e, rho, h, length): (f64, f64, f64, f64) = (210e9, 7850.0, 0.01, 1.0);
    beta_l * beta_l / (2.0 * std::f64::consts::PI * length * length) * (e * h * h / (12.0 * rho)).sqrt()
}

/// Runs `flexmb modes FILE --modes 10N --out DIR/body.json EXTRA…`; returns the report and the body.
fn modes_of(file: &Path, extra: &[&str]) -> (String, FlexibleBody) {
    let body_path = file.with_extension("json");
    let mut args = vec!["modes", file.to_str().unwrap(), "--modes", "10N", "--out", body_path.to_str().unwrap()];
    args.extend_from_slice(extra);
    let report = succeed(&args);
    (report, FlexibleBody::read(&body_path).unwrap())
}

/// The relative errors of the five bending pairs against Euler–Bernoulli: the larger of each pair.
fn bending_errors(body: &FlexibleBody) -> Vec<f64> {
    let f = &body.fe_frequencies_hz;
    (0..5)
        .map(|k| {
            let exact = euler_bernoulli_hz(CANTILEVER_BETA_L[k]);
            ((f[2 * k] - exact) / exact).abs().max(((f[2 * k + 1] - exact) / exact).abs())
        })
        .collect()
}

fn scientific(values: &[f64]) -> String {
    values.iter().map(|x| format!("{x:.1e}")).collect::<Vec<_>>().join(", ")
}

#[test]
fn consistent_mass_by_default_gives_the_cantilever_within_half_a_percent_and_lumped_on_request() {
    let dir = scratch("mass");
    let plain = dir.join("plain.toml");
    std::fs::write(&plain, square_cantilever("")).unwrap();

    // Consistent by default for beams: fourth order, every one of the five within 0.5 % (measured
    // below 2e-4).
    let (report, consistent) = modes_of(&plain, &[]);
    assert!(report.contains("mass matrix: consistent"), "{report}");
    assert_eq!(consistent.mass, BodyMass::Consistent);
    let written = std::fs::read_to_string(plain.with_extension("json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&written).unwrap();
    assert_eq!(json["mass"], "consistent");
    let errors = bending_errors(&consistent);
    println!("consistent mass, 20 elements, relative errors of modes 1-5: {}", scientific(&errors));
    assert!(errors.iter().all(|&e| e < 5e-3), "{errors:?}");

    // `--mass lumped`: second order at the free end, −1.18 % at the fifth mode with 20 elements.
    let (report, lumped) = modes_of(&plain, &["--mass", "lumped"]);
    assert!(report.contains("mass matrix: lumped"), "{report}");
    assert_eq!(lumped.mass, BodyMass::Lumped);
    let errors = bending_errors(&lumped);
    println!("lumped mass, 20 elements, relative errors of modes 1-5: {}", scientific(&errors));
    assert!(errors[0] < 5e-3 && errors[4] > 5e-3, "{errors:?}");
    // Both masses are the bar's 0.785 kg.
    assert!((consistent.mass_properties.mass - lumped.mass_properties.mass).abs() < 1e-12);
    assert!((consistent.mass_properties.mass - 0.785).abs() < 1e-9, "{}", consistent.mass_properties.mass);

    // The file's `[fe_model] mass`, and `--mass` over it.
    let from_file = dir.join("lumped.toml");
    std::fs::write(&from_file, square_cantilever(r#"mass = "lumped""#)).unwrap();
    let (report, body) = modes_of(&from_file, &[]);
    assert!(report.contains("mass matrix: lumped"), "{report}");
    assert_eq!(body.fe_frequencies_hz, lumped.fe_frequencies_hz);
    let (report, body) = modes_of(&from_file, &["--mass", "consistent"]);
    assert!(report.contains("mass matrix: consistent"), "{report}");
    assert_eq!(body.mass, BodyMass::Consistent);
    assert_eq!(body.fe_frequencies_hz, consistent.fe_frequencies_hz);
}

#[test]
fn fe_model_mass_applies_over_an_inp_mesh() {
    let dir = scratch("mass-inp");
    let deck = workspace().join("crates/flexmb-fem/tests/data/cantilever_b31.inp").canonicalize().unwrap();
    let file = dir.join("b31.toml");
    std::fs::write(&file, format!("[fe_model]\nmesh = {:?}\nmass = \"lumped\"\n", deck.to_str().unwrap())).unwrap();
    let lumped_path = dir.join("b31_lumped.json");
    let report = succeed(&["modes", file.to_str().unwrap(), "--modes", "4N", "--out", lumped_path.to_str().unwrap()]);
    assert!(report.contains("mass matrix: lumped"), "{report}");
    let lumped = FlexibleBody::read(&lumped_path).unwrap();
    assert_eq!(lumped.mass, BodyMass::Lumped);
    // The deck alone: its beams take their default, the consistent mass.
    let body_path = dir.join("b31.json");
    succeed(&["modes", deck.to_str().unwrap(), "--modes", "4N", "--out", body_path.to_str().unwrap()]);
    let consistent = FlexibleBody::read(&body_path).unwrap();
    assert_eq!(consistent.mass, BodyMass::Consistent);
    // At the free end the lumped mass is low in frequency and the consistent one high: ten elements
    // put them apart by about half a percent in the first mode.
    let (c, l) = (consistent.fe_frequencies_hz[0], lumped.fe_frequencies_hz[0]);
    assert!(c > l * 1.002, "consistent {c} Hz, lumped {l} Hz");
}

#[test]
fn an_unknown_mass_model_is_a_located_error() {
    let dir = scratch("mass-bad");
    let file = dir.join("heavy.toml");
    let text = square_cantilever(r#"mass = "heavy""#);
    std::fs::write(&file, &text).unwrap();
    let line = text.lines().position(|l| l.starts_with("mass = ")).unwrap() + 1;
    let out = dir.join("heavy.json");
    let e = fail(&["modes", file.to_str().unwrap(), "--modes", "4N", "--out", out.to_str().unwrap()]);
    let located = format!("{}:{line}: fe_model.mass: ", file.display());
    assert!(e.contains(&located), "expected `{located}` in:\n{e}");
    assert!(e.contains("`heavy`") && e.contains("`lumped`") && e.contains("`consistent`"), "{e}");
    let e = fail(&["modes", "models/fe/cantilever.toml", "--mass", "heavy", "--out", "/dev/null"]);
    assert!(e.contains("--mass") && e.contains("lumped") && e.contains("consistent"), "{e}");
}

/// FLEXMB_MEMORY_LIMIT bounds the mode analysis as it bounds the dense initial-condition analyses: a
/// mesh that needs more is refused before it is assembled, by `modes` and when a model reduces it (a
/// beam line of 10⁶ elements aborted on a 3.2 GB allocation before).
#[test]
fn a_mesh_larger_than_the_memory_limit_is_refused_with_what_it_needs() {
    let limited = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_flexmb"))
            .args(args)
            .env("FLEXMB_MEMORY_LIMIT", "100k")
            .current_dir(workspace())
            .output()
            .unwrap()
    };
    let out = scratch("memory-limit");
    let body = out.join("plate.json");
    let o = limited(&["modes", "models/fe/plate.toml", "--out", body.to_str().unwrap()]);
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("models/fe/plate.toml: the mesh is too large for the mode analysis: 192 elements and 221 nodes need about"), "{e}");
    assert!(e.contains("more than the 0.1 MiB it may use"), "{e}");
    // A model file reduces its flexible bodies (a copy of the pendulum's FE model, so that no cache answers).
    std::fs::copy(workspace().join("models/fe/pendulum_beam.toml"), out.join("beam.toml")).unwrap();
    let model = std::fs::read_to_string(workspace().join("models/flexible_pendulum.toml")).unwrap();
    std::fs::write(out.join("pendulum.toml"), model.replace("fe/pendulum_beam.toml", "beam.toml")).unwrap();
    let o = limited(&["check", out.join("pendulum.toml").to_str().unwrap()]);
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("too large for the mode analysis: 20 elements and 21 nodes"), "{e}");
}

/// The shipped strip of models/fe/pendulum_beam.toml in 20,000 elements of 50 µm is as ill-conditioned
/// as double precision allows: the Lanczos iteration's Ritz residuals stop at round-off, which a test
/// relative to the operator's largest eigenvalue (2e-13 s² here) never met, and it ran for four minutes
/// before giving up. It ends in about a second now, and the modes' own checks judge what it found
/// (found by the fuzz test).
#[test]
fn the_lanczos_iteration_ends_on_an_ill_conditioned_mesh() {
    let dir = scratch("ill-conditioned");
    let strip = std::fs::read_to_string(workspace().join("models/fe/pendulum_beam.toml")).unwrap();
    let fe = dir.join("fine.toml");
    std::fs::write(&fe, strip.replace("elements = 20", "elements = 20000")).unwrap();
    let started = std::time::Instant::now();
    let o = flexmb(&["modes", fe.to_str().unwrap(), "--modes", "6N", "--out", dir.join("fine.json").to_str().unwrap()]);
    let seconds = started.elapsed().as_secs_f64();
    assert!(o.status.code() == Some(0) || text(&o.stderr).starts_with("error:"), "{}", text(&o.stderr));
    assert!(seconds < 20.0, "{seconds} s");
}

/// A free plate of 1.2 mm sheet with a thin rod at one corner and a drilling stiffness of 5e-5: its
/// lowest elastic mode (0.039 Hz) is 10¹⁰ times softer than its stiffest element, so that computing
/// `K φ − λ M φ` leaves a residual of 3e-6 ‖K φ‖ from rounding alone. That is not an inaccurate mode:
/// the dense and the Lanczos solvers agree on every frequency (within what rounding allows), and the check allows what rounding
/// explains (before, both refused it: "mode 1: eigen residual 3.12e-6 exceeds 1e-6"; found by the
/// fuzz test, seed 7 case 19, with the lumped mass).
#[test]
fn a_mode_far_softer_than_the_stiffest_element_passes_the_residual_check() {
    let dir = scratch("soft-mode");
    let fe = dir.join("sheet.toml");
    std::fs::write(
        &fe,
        r#"[fe_model]
name = "sheet"
mass = "lumped"
rotary_inertia = false
drilling_stiffness = 5.367349321073993e-5

[[material]]
name = "m"
E = 12207730778.799467
nu = 0.4319099754088278
rho = 3203.9566483977833

[[beam_section]]
name = "rod"
material = "m"
orientation = [-0.9156358169430028, -0.20936435237682988, -0.9833318902649736]
shape = "circle"
radius = 0.0073702330109871594
shear_coefficient = 0.6708869869329691

[[shell_section]]
name = "sheet"
material = "m"
thickness = 0.001241989399643473

[[plate]]
name = "p0"
section = "sheet"
corner = [0.0, 0.0, 0.0]
edge_a = [0.0, 0.9395053739962633, 0.0]
edge_b = [-0.1767653030500227, -0.02338732154915904, -0.23476449562151783]
elements = [8, 3]

[[beam_line]]
name = "p1"
section = "rod"
from = [0.0, 0.0, 0.0]
to = [0.3055687737551338, 0.0, 0.0]
elements = 10
"#,
    )
    .unwrap();
    let frequencies = |solver: &str| {
        let body = dir.join(format!("{solver}.json"));
        succeed(&["modes", fe.to_str().unwrap(), "--modes", "6N", "--solver", solver, "--out", body.to_str().unwrap()]);
        FlexibleBody::read(&body).unwrap().fe_frequencies_hz
    };
    let (a, b) = (frequencies("dense"), frequencies("lanczos"));
    assert_eq!(a.len(), 6);
    assert!((a[0] - 0.038933).abs() < 1e-6, "{a:?}");
    for (x, y) in a.iter().zip(&b) {
        // The soft mode's eigenvalue is known to about ε ‖K‖ / λ: the two agree to 1.6e-7 there, to
        // 1e-10 on the others.
        assert!((x - y).abs() <= 1e-6 * x, "dense {a:?}, Lanczos {b:?}");
    }
}
