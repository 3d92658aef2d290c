//! The outputs engineers measure (issue 18, point 5), through `flexmb run` as a user runs them: body
//! orientation in Euler parameters, rotation matrix and Euler angles continued over turns; angular
//! velocity in body axes; kinetic energy and momenta; joint coordinates, multipliers and reactions in a
//! marker's axes; user expressions; and `flexmb check` listing the columns `flexmb run` writes. Each is
//! checked against a closed form or an identity at every output row.

use crate::program;

use std::path::Path;

use flexmb::math::{EulerSequence, Mat3, Vec3};
use program::{scratch, succeed, ResultCsv};

const FREE_BODIES: &str = "crates/flexmb-cli/tests/models/outputs/free_bodies.toml";

/// `flexmb run MODEL` into `dir`; its CSV.
fn run(model: &Path, dir: &Path) -> ResultCsv {
    succeed(&["run", model.to_str().unwrap(), "--quiet", "--out", dir.to_str().unwrap()]);
    ResultCsv::read(&dir.join(format!("{}.csv", model.file_stem().unwrap().to_str().unwrap())))
}

fn vector(csv: &ResultCsv, row: usize, base: &str) -> Vec3 {
    Vec3::new(csv.at(row as isize, &format!("{base}.x")), csv.at(row as isize, &format!("{base}.y")), csv.at(row as isize, &format!("{base}.z")))
}

fn rotation_matrix(csv: &ResultCsv, row: usize, base: &str) -> Mat3 {
    Mat3::from_fn(|r, c| csv.at(row as isize, &format!("{base}.a{}{}", r + 1, c + 1)))
}

fn angles(csv: &ResultCsv, row: usize, base: &str) -> [f64; 3] {
    ["phi", "theta", "psi"].map(|a| csv.at(row as isize, &format!("{base}.{a}")))
}

/// Largest deviation of a column from its first value.
fn drift(values: &[f64]) -> f64 {
    values.iter().map(|v| (v - values[0]).abs()).fold(0.0, f64::max)
}

/// The free bodies run in a scratch directory of the test's own (tests run at the same time).
fn free_bodies(test: &str) -> ResultCsv {
    let dir = scratch(&format!("outputs-free-bodies-{test}"));
    run(&program::workspace().join(FREE_BODIES), &dir)
}

#[test]
fn a_body_spinning_about_a_fixed_axis_has_its_closed_form_angles_continued_over_eight_turns() {
    // A(t) = A_z(w t) A_x(0.5) with w = 10 rad/s: 3-1-3 angles (w t, 0.5, 0), 3-2-1 angles (w t, 0, 0.5).
    let csv = free_bodies("spinning");
    let t = csv.column("t");
    assert!(10.0 * t[t.len() - 1] > 7.9 * std::f64::consts::TAU, "several turns");
    for (row, t) in t.iter().enumerate() {
        let a313 = angles(&csv, row, "spinner.angles_313");
        let a321 = angles(&csv, row, "spinner.angles_321");
        // The integration's error in the spin angle grows to 1.3e-7 rad at 5 s (rtol 1e-9).
        for (got, want, tolerance) in [
            (a313[0], 10.0 * t, 1e-6),
            (a313[1], 0.5, 1e-12),
            (a313[2], 0.0, 1e-12),
            (a321[0], 10.0 * t, 1e-6),
            (a321[1], 0.0, 1e-12),
            (a321[2], 0.5, 1e-12),
        ] {
            assert!((got - want).abs() < tolerance, "t = {t}: {a313:?} (313), {a321:?} (321)");
        }
        let closed_form = EulerSequence::parse("313").unwrap().rotation_matrix([10.0 * t, 0.5, 0.0]);
        assert!((rotation_matrix(&csv, row, "spinner.rotation_matrix") - closed_form).amax() < 1e-6, "t = {t}");
        let p = ["e0", "e1", "e2", "e3"].map(|e| csv.at(row as isize, &format!("spinner.euler_parameters.{e}")));
        let half = 0.5 * 10.0 * t;
        // p of A_z(w t) A_x(0.5): the product of [cos(wt/2), 0, 0, sin(wt/2)] and [cos .25, sin .25, 0, 0].
        let want = [half.cos() * 0.25_f64.cos(), half.cos() * 0.25_f64.sin(), half.sin() * 0.25_f64.sin(), half.sin() * 0.25_f64.cos()];
        let sign = if p[0] * want[0] + p[3] * want[3] < 0.0 { -1.0 } else { 1.0 };
        for (got, want) in p.iter().zip(want) {
            assert!((got - sign * want).abs() < 1e-6, "t = {t}: {p:?} vs {want:?}");
        }
    }
}

/// The angles continued over many turns carry round-off of a few ulps of their size (1.3e-14 at 66 rad).
#[test]
fn the_angles_of_any_two_sequences_give_the_written_rotation_matrix_at_every_row() {
    let csv = free_bodies("sequences");
    let (s313, s321) = (EulerSequence::parse("313").unwrap(), EulerSequence::parse("321").unwrap());
    for row in 0..csv.rows.len() {
        let a = rotation_matrix(&csv, row, "spinner.rotation_matrix");
        assert!((s313.rotation_matrix(angles(&csv, row, "spinner.angles_313")) - a).amax() < 1e-13, "row {row}");
        assert!((s321.rotation_matrix(angles(&csv, row, "spinner.angles_321")) - a).amax() < 1e-13, "row {row}");
    }
}

#[test]
fn free_bodies_keep_their_momenta_and_kinetic_energies() {
    let csv = free_bodies("momenta");
    // Measured at rtol = atol = 1e-9 over 5 s: drifts of 1.2e-8 to 7.7e-8 N s (linear), 3.7e-8 to
    // 2.6e-7 N m s (angular), 6.2e-8 J: the integration's error; the test allows 1e-6 of 1 or the value.
    for name in [
        "momentum.linear.x",
        "momentum.linear.y",
        "momentum.linear.z",
        "momentum.angular.x",
        "momentum.angular.y",
        "momentum.angular.z",
        "tumbler.kinetic_energy",
    ] {
        let values = csv.column(name);
        let d = drift(&values);
        assert!(d < 1e-6 * values[0].abs().max(1.0), "{name} drifts by {d:e}");
    }
    // The spinner's kinetic energy is ½ I w² = ½ 0.1 · 10² = 5 J: the body columns sum to the total.
    for (row, t) in csv.column("t").iter().enumerate() {
        let sum = csv.at(row as isize, "tumbler.kinetic_energy") + 5.0;
        assert!((csv.at(row as isize, "energy.kinetic") - sum).abs() < 1e-7, "t = {t}");
    }
    assert!(csv.column("euler_parameter_norm_error").iter().all(|e| *e < 1e-8));
}

#[test]
fn a_user_expression_equals_its_hand_computed_value_at_every_row() {
    // spin_turns = spinner.angles_313.phi / (2 PI) - w t / (2 PI), w = 10.
    let csv = free_bodies("expression");
    let tau = std::f64::consts::TAU;
    for (row, t) in csv.column("t").iter().enumerate() {
        let want = csv.at(row as isize, "spinner.angles_313.phi") / tau - 10.0 * t / tau;
        assert!((csv.at(row as isize, "spin_turns") - want).abs() < 1e-14, "t = {t}");
    }
}

/// The heavy top of `models/spinning_top.toml` with the outputs of point 5 added.
const TOP_OUTPUTS: &str = r#"
[[output]]
type = "rotation_matrix"
body = "top"

[[output]]
type = "euler_angles"
body = "top"

[[output]]
type = "euler_angles"
body = "top"
sequence = "123"

[[output]]
type = "angular_velocity"
body = "top"
axes = "body"

[[output]]
type = "kinetic_energy"
body = "top"

[[output]]
type = "angular_momentum"
body = "top"

[[output]]
type = "system_momentum"

[[output]]
type = "joint_reaction"
joint = "tip"
frame = "center"

[[output]]
type = "joint_multipliers"
joint = "tip"

[[output]]
type = "joint_coordinates"
joint = "tip"

[[output]]
name = "spin_energy"
type = "expression"
expression = "0.5*C*top.angular_velocity_body.z^2"
unit = "J"
"#;

fn heavy_top(test: &str) -> (ResultCsv, std::path::PathBuf) {
    let dir = scratch(&format!("outputs-heavy-top-{test}"));
    let text = std::fs::read_to_string(program::workspace().join("models/spinning_top.toml")).unwrap();
    let model = dir.join("heavy_top.toml");
    std::fs::write(&model, text.replace("t_end = 4.0 ", "t_end = 2.0 ") + TOP_OUTPUTS).unwrap();
    (run(&model, &dir), model)
}

#[test]
fn the_heavy_top_keeps_its_vertical_angular_momentum_and_its_energy_and_its_outputs_agree() {
    let (csv, _) = heavy_top("conservation");
    // Gravity and the support act through the tip (the origin) or have no vertical moment about it.
    let hz = csv.column("momentum.angular.z");
    assert!((hz[0] - 0.5 * (30f64).to_radians().cos()).abs() < 1e-12, "C w_s cos 30° = {}", hz[0]);
    // Measured at the model's rtol = atol = 1e-7 over 2 s: 2.0e-6 N m s (4.7e-6 of the value) and
    // 4.8e-6 J (1.9e-7 of the 25.8 J); the test allows 1e-5 and 1e-6 relative.
    assert!(drift(&hz) < 1e-5 * hz[0], "vertical angular momentum drifts by {:e}", drift(&hz));
    let energy = csv.column("energy.total");
    assert!(drift(&energy) < 1e-6 * energy[0], "energy drifts by {:e}", drift(&energy));
    let (s313, s123) = (EulerSequence::parse("313").unwrap(), EulerSequence::parse("123").unwrap());
    for row in 0..csv.rows.len() {
        let r = row as isize;
        let a = rotation_matrix(&csv, row, "top.rotation_matrix");
        assert!((s313.rotation_matrix(angles(&csv, row, "top.angles_313")) - a).amax() < 1e-13, "row {row}");
        assert!((s123.rotation_matrix(angles(&csv, row, "top.angles_123")) - a).amax() < 1e-13, "row {row}");
        assert!((csv.at(r, "top.kinetic_energy") - csv.at(r, "energy.kinetic")).abs() < 1e-12);
        // Body axes: Aᵀ ω; the angular momentum about the origin is that about the centre of mass
        // plus r_c × L.
        let omega_body = a.transpose() * vector(&csv, row, "center.angular_velocity");
        assert!((vector(&csv, row, "top.angular_velocity_body") - omega_body).amax() < 1e-12);
        let about_origin = vector(&csv, row, "top.angular_momentum")
            + vector(&csv, row, "center.position").cross(&vector(&csv, row, "momentum.linear"));
        assert!((vector(&csv, row, "momentum.angular") - about_origin).amax() < 1e-12, "row {row}");
        // The reaction in the axes of marker `center` (the body's axes) is the global one rotated.
        for (part, base) in [("f", "tip.reaction"), ("t", "tip.reaction")] {
            let component = |base: &str, c: &str| csv.at(r, &format!("{base}.{part}{c}"));
            let global = Vec3::new(component(base, "x"), component(base, "y"), component(base, "z"));
            let local = Vec3::new(component("tip.reaction_in_center", "x"), component("tip.reaction_in_center", "y"), component("tip.reaction_in_center", "z"));
            assert!((a.transpose() * global - local).amax() < 1e-9 * (1.0 + global.amax()), "row {row} {part}");
        }
        // The spherical joint's multipliers are the force on ground, component by component.
        for (k, c) in ["x", "y", "z"].iter().enumerate() {
            let lambda = csv.at(r, &format!("tip.multipliers.lambda{}", k + 1));
            assert!((lambda - csv.at(r, &format!("tip.reaction.f{c}"))).abs() < 1e-9, "row {row}");
        }
        // The spherical joint's relative rotation is that of the body (the support's axes are global).
        let rotation = vector(&csv, row, "tip.coordinates.rotation");
        let angle = rotation.norm();
        let from_vector = nalgebra::Rotation3::from_scaled_axis(rotation).into_inner();
        assert!((from_vector - a).amax() < 1e-12 && angle <= std::f64::consts::PI, "row {row}");
        let spin = csv.at(r, "top.angular_velocity_body.z");
        assert!((csv.at(r, "spin_energy") - 0.5 * 5.0e-3 * spin * spin).abs() < 1e-14);
    }
}

/// `flexmb check` lists `name [unit]` lines after `output columns (N):`.
fn checked_columns(model: &str) -> Vec<String> {
    let out = succeed(&["check", model]);
    let list = out.split_once("output columns (").unwrap_or_else(|| panic!("{out}")).1;
    let (count, lines) = list.split_once("):\n").unwrap();
    let names: Vec<String> = lines.lines().map(|l| l.trim().rsplit_once(" [").unwrap().0.to_string()).collect();
    assert_eq!(names.len(), count.parse::<usize>().unwrap());
    names
}

#[test]
fn check_lists_exactly_the_header_run_writes() {
    let free = free_bodies("check");
    assert_eq!(checked_columns(FREE_BODIES), free.header);
    let (top, model) = heavy_top("check");
    assert_eq!(checked_columns(model.to_str().unwrap()), top.header);
    let pendulum_dir = scratch("outputs-pendulum");
    let pendulum = run(&program::workspace().join("models/pendulum.toml"), &pendulum_dir);
    assert_eq!(checked_columns("models/pendulum.toml"), pendulum.header);
}
