//! Solid flexible bodies as a new user meets them: `flexmb modes` on the shipped deck of a steel link
//! of C3D20 bricks gives the beam-theory frequencies and VTK hexahedra, and the mechanism that hangs
//! the link from a revolute joint at the reference node of its rigid coupling swings as the compound
//! pendulum it is — and so does the link with distributing (RBE3) interface nodes reduced by
//! Craig–Bampton (`models/fe/solid_link_interfaces.toml`).

use flexmb_fem::reduction::FlexibleBody;

use crate::program;

use program::{scratch, succeed, workspace};

/// Euler–Bernoulli frequency (Hz) of the 0.5 m steel link with eigenvalue βL and second moment `i`.
fn beam_hz(beta_l: f64, i: f64) -> f64 {
    let (e, rho, area, length) = (210e9, 7850.0, 0.01 * 0.04, 0.5_f64);
    beta_l.powi(2) / (2.0 * std::f64::consts::PI) * (e * i / (rho * area * length.powi(4))).sqrt()
}

#[test]
fn modes_of_the_shipped_solid_link() {
    let out = scratch("solid-link");
    let body_path = out.join("link.json");
    let stdout = succeed(&[
        "modes",
        "models/fe/solid_link.inp",
        "--modes",
        "4N",
        "--mass",
        "consistent",
        "--out",
        body_path.to_str().unwrap(),
        "--vtk",
        out.to_str().unwrap(),
    ]);
    assert!(stdout.contains("20 elements (0 beam, 0 shell, 20 solid)"), "{stdout}");
    let body = FlexibleBody::read(&body_path).unwrap();
    // Held at the reference node as the hinge holds it: clamped out of the plane of the swing
    // (bending across the 40 mm width), pinned in it (across the 10 mm thickness). The solid is
    // 0.3 % stiffer than the beam (its coupled end face is rigid; Timoshenko would be softer).
    let (out_of_plane, in_plane) = (beam_hz(1.875_104, 0.01 * 0.04_f64.powi(3) / 12.0), beam_hz(3.926_602, 0.04 * 0.01_f64.powi(3) / 12.0));
    let f = &body.fe_frequencies_hz;
    println!("solid link: {f:?} Hz; beam theory {out_of_plane:.2} and {in_plane:.2} Hz");
    assert!((f[0] / out_of_plane - 1.0).abs() < 5e-3, "{} against {out_of_plane}", f[0]);
    assert!((f[1] / in_plane - 1.0).abs() < 5e-3, "{} against {in_plane}", f[1]);
    let vtu = std::fs::read_to_string(out.join("solid_link_modes.vtu")).unwrap();
    assert!(vtu.contains("NumberOfCells=\"20\""), "{}", &vtu[..300]);
}

#[test]
fn the_solid_pendulum_swings_as_a_compound_pendulum() {
    let out = scratch("solid-pendulum");
    succeed(&["run", "models/solid_pendulum.toml", "--out", out.to_str().unwrap()]);
    swings_as_a_compound_pendulum(&out.join("solid_pendulum.csv"));
}

/// The same pendulum with the link of two distributing interface nodes, reduced by Craig–Bampton
/// (8N12C): the hinge acts at the reference node 1000 of the hinge face's distributing coupling.
#[test]
fn the_solid_pendulum_on_a_distributing_coupling_swings_as_a_compound_pendulum() {
    let out = scratch("solid-pendulum-rbe3");
    let shipped = std::fs::read_to_string(workspace().join("models/solid_pendulum.toml")).unwrap();
    let interfaces = workspace().join("models/fe/solid_link_interfaces.toml");
    let text = shipped.replace("\"fe/solid_link.toml\"", &format!("{:?}", interfaces.to_str().unwrap()));
    assert_ne!(text, shipped);
    let model = out.join("solid_pendulum.toml");
    std::fs::write(&model, text).unwrap();
    let stdout = succeed(&["run", model.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    println!("{stdout}");
    swings_as_a_compound_pendulum(&out.join("solid_pendulum.csv"));
}

fn swings_as_a_compound_pendulum(csv: &std::path::Path) {
    let csv = std::fs::read_to_string(csv).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (t, y) = (column("t"), column("link.node125.position.y"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    let lowest = rows.iter().min_by(|a, b| a[y].total_cmp(&b[y])).unwrap();
    // A uniform bar of length L pivoted at its end, released horizontal, reaches the bottom after
    // √(2L / 3g) K(sin 45°) = 0.3418 s; its free end then hangs L − 5 mm (the pivot's height) below.
    let quarter = (2.0 * 0.5 / (3.0 * 9.81_f64)).sqrt() * 1.854_075;
    println!("lowest at t = {} s (rigid {quarter:.4} s), y = {}", lowest[t], lowest[y]);
    assert!((lowest[t] - quarter).abs() < 2e-3, "{} against {quarter}", lowest[t]);
    assert!((lowest[y] + 0.495).abs() < 1e-4, "{}", lowest[y]);
}
