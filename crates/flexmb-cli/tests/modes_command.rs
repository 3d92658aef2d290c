//! `flexmb modes` as a new user runs it: the shipped FE models reduce to flexible-body files whose
//! frequencies are printed, mode shapes are written for ParaView, `.inp` meshes are read directly, and
//! bad requests are refused with a message.


use flexmb_fem::reduction::{Basis, FlexibleBody};

mod program;

use program::{flexmb, scratch, text};

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
