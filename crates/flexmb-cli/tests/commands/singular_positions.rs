//! A declared constraint is never silently dropped: where rows of the constraint Jacobian are
//! dependent, the rows switched off are chosen among those that hold, drivers last, and every declared
//! equation must still hold after the assembly and the velocity analysis; where they cannot all hold
//! the mechanism is at a singular position and `check` and `run` stop naming the equations.

use crate::program;

use program::{fail, scratch, succeed, ResultCsv};

/// The shipped slider-crank (crank 0.1 m, rod 0.3 m) driven at the slider instead of the crank:
/// `x = x0 − 0.5 t` along the guide, which starts at `x0` (`slider_x0`, m), with the bodies posed at
/// the crank angle `theta0` (rad) that puts the slider there.
fn slider_driven(slider_x0: &str, theta0: &str) -> String {
    let shipped = std::fs::read_to_string(program::workspace().join("models/slider_crank.toml")).unwrap();
    let replace = |s: String, from: &str, to: &str| {
        assert!(s.contains(from), "models/slider_crank.toml no longer holds {from:?}");
        s.replace(from, to)
    };
    let s = replace(
        shipped,
        "l = 0.3                              # m, connecting-rod length",
        &format!(
            "l = 0.3\nx0 = \"{slider_x0}\"\ntheta0 = \"{theta0}\"\nphi0 = \"asin(r*sin(theta0)/l)\"   # rod angle below the guide"
        ),
    );
    let s = replace(s, "position = [0.0, 0.0, 0.0]           # body frame at the crank pivot, crank along body x", "orientation = { axis = [0, 0, 1], angle = \"theta0\" }");
    let s = replace(
        s,
        "position = [\"r\", 0.0, 0.0]           # body frame at the crank pin, rod along body x",
        "position = [\"r*cos(theta0)\", \"r*sin(theta0)\", 0]\norientation = { axis = [0, 0, 1], angle = \"-phi0\" }",
    );
    let s = replace(s, "position = [\"r + l\", 0.0, 0.0]       # body frame at the rod-slider pin", "position = [\"x0\", 0, 0]");
    let s = replace(
        s,
        "name = \"crank_motion\"\njoint = \"crank_pivot\"                # revolute: an angle driver\nfunction = \"2*PI*t\" ",
        "name = \"slider_motion\"\njoint = \"slide\"\nfunction = \"x0 - 0.5*t\" ",
    );
    replace(s, "joint = \"crank_motion\"", "joint = \"slider_motion\"")
}

#[test]
fn a_slider_driven_at_the_dead_centre_is_a_singular_position_not_a_dropped_driver() {
    // Crank along the guide: the slider's speed is zero to first order in the crank's, so the driver's
    // row depends on the joints' there, and −0.5 m/s cannot be followed. Before: the driver was removed
    // as "redundant", 1 degree of freedom, an undriven run with a zero driver force, exit 0.
    let dir = scratch("dead-centre");
    let model = dir.join("dead_centre.toml");
    std::fs::write(&model, slider_driven("r + l", "0")).unwrap();
    let out = dir.join("out");
    let check = fail(&["check", model.to_str().unwrap()]);
    let run = fail(&["run", model.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    for (command, e) in [("check", check), ("run", run)] {
        assert!(e.contains("dead_centre.toml"), "{command}: the file is named: {e}");
        assert!(e.contains("singular position") && e.contains("cannot all hold"), "{command}: {e}");
        assert!(e.contains("at t = 0 s"), "{command}: {e}");
        assert!(e.contains("driver 'slider_motion'"), "{command}: the driver involved is named: {e}");
        assert!(e.contains("velocity residual of 5.000e-1"), "{command}: the unfollowable 0.5 m/s is the residual: {e}");
        assert!(!e.contains("redundant"), "{command}: nothing is reported as merely redundant: {e}");
    }
}

#[test]
fn one_step_from_the_dead_centre_the_driver_holds_and_the_crank_follows_the_closed_form() {
    // The slider starts 0.5 mm (one 1 ms step of the driver) inside the dead centre and is pulled in at
    // 0.5 m/s; the crank turns at 43 rad/s at first. No row is dependent; the driver holds at every
    // output and the crank angle is the closed form cos θ = (x² + r² − l²)/(2 x r).
    let dir = scratch("near-dead-centre");
    let model = dir.join("near_dead_centre.toml");
    std::fs::write(&model, slider_driven("r + l - 0.5e-3", "acos((x0^2 + r^2 - l^2)/(2*x0*r))")).unwrap();
    let s = succeed(&["check", model.to_str().unwrap()]);
    assert!(s.contains("degrees of freedom: 0") && s.contains("redundant constraints: none"), "{s}");
    let out = dir.join("out");
    succeed(&["run", model.to_str().unwrap(), "--t-end", "0.35", "--output-step", "0.005", "--quiet", "--out", out.to_str().unwrap()]);
    let csv = ResultCsv::read(&out.join("near_dead_centre.csv"));
    let (r, l, x0) = (0.1_f64, 0.3_f64, 0.4 - 0.5e-3);
    let (t, x, theta, force) = (csv.column("t"), csv.column("slider_position"), csv.column("crank_angle"), csv.column("motor.fx"));
    assert_eq!(t.len(), 71);
    let mut worst_x = 0.0_f64;
    let mut worst_theta = 0.0_f64;
    for k in 0..t.len() {
        let x_exact = x0 - 0.5 * t[k];
        let theta_exact = ((x_exact * x_exact + r * r - l * l) / (2.0 * x_exact * r)).acos();
        worst_x = worst_x.max((x[k] - x_exact).abs());
        worst_theta = worst_theta.max((theta[k] - theta_exact).abs());
    }
    eprintln!("slider off its driver by {worst_x:.1e} m, crank off the closed form by {worst_theta:.1e} rad");
    assert!(worst_x < 1e-9, "the driver holds at every output: {worst_x:e} m");
    assert!(worst_theta < 1e-6, "the crank follows the closed form: {worst_theta:e} rad");
    let largest_force = force.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    assert!(largest_force > 1.0, "the driver pulls the slider (its reaction is not zero): {largest_force} N");
}

/// The parallelogram four-bar of four revolutes (three rows repeat others in 3D), driven at its crank.
/// `tilt` tilts the axis of the last revolute's marker on the coupler (rad).
fn driven_four_revolutes(tilt: f64) -> String {
    four_revolutes(tilt)
        + r#"
[[driver]]
name = "crank_motion"
joint = "a"
function = "2*t"

[[output]]
name = "motor"
type = "joint_reaction"
joint = "crank_motion"
"#
}

/// The parallelogram four-bar of four revolutes, undriven (one degree of freedom).
fn four_revolutes(tilt: f64) -> String {
    format!(
        r#"
[model]
name = "four revolutes"
gravity = [0, -9.81, 0]

[simulation]
t_end = 0.5
output_step = 0.05

[[body]]
name = "crank"
mass = 1.0
inertia = [0.01, 0.1, 0.1]

[[body]]
name = "coupler"
mass = 1.0
inertia = [0.01, 0.1, 0.1]
position = [0, 1, 0]

[[body]]
name = "rocker"
mass = 1.0
inertia = [0.01, 0.1, 0.1]
position = [2, 0, 0]

[[marker]]
name = "g1"
body = "ground"

[[marker]]
name = "g2"
body = "ground"
origin = [2, 0, 0]

[[marker]]
name = "c0"
body = "crank"

[[marker]]
name = "c1"
body = "crank"
origin = [0, 1, 0]

[[marker]]
name = "k0"
body = "coupler"

[[marker]]
name = "k1"
body = "coupler"
origin = [2, 0, 0]
z_axis = [{tilt}, 0, 1]

[[marker]]
name = "r0"
body = "rocker"

[[marker]]
name = "r1"
body = "rocker"
origin = [0, 1, 0]

[[joint]]
name = "a"
type = "revolute"
i = "g1"
j = "c0"

[[joint]]
name = "b"
type = "revolute"
i = "c1"
j = "k0"

[[joint]]
name = "c"
type = "revolute"
i = "g2"
j = "r0"

[[joint]]
name = "d"
type = "revolute"
i = "k1"
j = "r1"
"#
    )
}

#[test]
fn redundant_rows_are_named_in_the_last_joint_of_the_loop() {
    let dir = scratch("undriven-four-revolutes");
    let model = dir.join("four_revolutes.toml");
    std::fs::write(&model, four_revolutes(0.0)).unwrap();
    let s = succeed(&["check", model.to_str().unwrap()]);
    assert!(s.contains("degrees of freedom: 1") && s.contains("redundant constraints: 3"), "{s}");
    assert!(s.contains("joint 'd' (revolute)"), "the last joint of the loop is named: {s}");
}

#[test]
fn redundant_rows_are_joint_rows_not_the_driver_and_check_and_run_name_the_same() {
    let dir = scratch("four-revolutes");
    let model = dir.join("four_revolutes.toml");
    std::fs::write(&model, driven_four_revolutes(0.0)).unwrap();
    let s = succeed(&["check", model.to_str().unwrap()]);
    assert!(s.contains("degrees of freedom: 0") && s.contains("redundant constraints: 3"), "{s}");
    let listed: Vec<String> = s.lines().filter_map(|l| l.strip_prefix("  - ")).map(str::to_string).collect();
    assert_eq!(listed.len(), 3, "{s}");
    assert!(listed.iter().all(|r| r.starts_with("joint 'd' (revolute)")), "the loop's last joint, never the driver: {listed:?}");

    let out = dir.join("out");
    succeed(&["run", model.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()]);
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("four_revolutes.json")).unwrap()).unwrap();
    let in_run: Vec<String> = summary["assembly"]["redundant_constraints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_str().unwrap().to_string())
        .collect();
    assert_eq!(in_run, listed, "check and run name the same rows");
    let csv = ResultCsv::read(&out.join("four_revolutes.csv"));
    // The driver's reaction is the whole gravity load: with the masses at the crank pin and the pivots
    // and the crank turning at 2 rad/s from upright, the coupler's height is cos 2t and the driving
    // torque d(m g cos 2t)/dθ = −m g sin 2t (its reaction on ground has the opposite sign).
    let (t, torque) = (csv.column("t"), csv.column("motor.tz"));
    let worst = (0..t.len()).map(|k| (torque[k] - 9.81 * (2.0 * t[k]).sin()).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-6, "the driver carries the gravity load, m g sin 2t: off by {worst:e} N m in {torque:?}");
}

#[test]
fn redundant_joints_that_disagree_geometrically_are_named_not_dropped() {
    // The last revolute's axis tilted by 0.01 rad: its parallel-axis rows repeat the planar loop's and
    // cannot hold with them. Before, they were switched off as redundant and the run went on.
    let dir = scratch("tilted-four-revolutes");
    let model = dir.join("tilted.toml");
    std::fs::write(&model, driven_four_revolutes(0.01)).unwrap();
    let e = fail(&["check", model.to_str().unwrap()]);
    assert!(e.contains("singular position") && e.contains("cannot all hold"), "{e}");
    assert!(e.contains("joint 'd' (revolute), equation"), "the disagreeing joint is named: {e}");
    assert!(e.contains("position residual of 1.000e-2") || e.contains("position residual of 9.99"), "its residual: {e}");
}

#[test]
fn a_driver_not_finite_at_the_start_is_named_not_called_a_singular_matrix() {
    // Before: "assembly: the constraint matrix is singular even after removing redundant rows" (ln 0 =
    // −inf), and "velocity analysis: …" for sqrt(t − 1), whose NaN passed the assembly's test.
    let shipped = std::fs::read_to_string(program::workspace().join("models/slider_crank.toml")).unwrap();
    let dir = scratch("non-finite-driver");
    for (function, value) in [("ln(t)", "inf"), ("sqrt(t - 1)", "NaN")] {
        let model = dir.join("driver.toml");
        std::fs::write(&model, shipped.replace("function = \"2*PI*t\"", &format!("function = \"{function}\""))).unwrap();
        let (m, out) = (model.to_str().unwrap(), dir.to_str().unwrap());
        for e in [fail(&["check", m]), fail(&["run", m, "--out", out])] {
            assert!(e.contains("at t = 0 s joint 'crank_motion' (angle driver), equation 1"), "{function}: {e}");
            assert!(e.contains(&format!("is not finite (its value is {value})")) && !e.contains("singular"), "{function}: {e}");
        }
    }
}
