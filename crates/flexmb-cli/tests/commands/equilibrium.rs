//! `flexmb equilibrium` as a user runs it: the robot arm's equilibrium printed and written (JSON with
//! the reactions, CSV of the outputs, ParaView), its motor torque the closed form `m g L / 2`; the
//! wiper, whose motor turns the crank with nothing resisting at rest, refused with the motion named.

use crate::program;

use program::{flexmb, scratch, text};

#[test]
fn the_robot_arm_equilibrium_is_printed_and_written() {
    let out = scratch("equilibrium");
    let o = flexmb(&["equilibrium", "models/robot_arm.toml", "--out", out.to_str().unwrap(), "--vtk"]);
    assert!(o.status.success(), "stdout:\n{}\nstderr:\n{}", text(&o.stdout), text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("4 degrees of freedom") && stdout.contains("converged by newton"), "{stdout}");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("equilibrium.json")).unwrap()).unwrap();
    assert_eq!(json["method"], "newton");
    assert_eq!(json["bodies"][0]["modal_coordinates"].as_array().unwrap().len(), 4);
    // The motor's torque on the link: the link's weight (1.57 kg) at half its length, less the
    // sagging link's shortening of its arm (the tip moves in by 0.15 mm: about 1e-4 of the torque).
    let motor = json["reactions"].as_array().unwrap().iter().find(|r| r["joint"] == "shoulder_motor").unwrap();
    let torque = motor["sides"][0]["torque"][2].as_f64().unwrap();
    let mass = 7850.0 * 1.0 * 0.040 * 0.005;
    assert!((torque.abs() - mass * 9.81 * 0.5).abs() < 2e-4 * torque.abs(), "motor torque {torque} N m");
    let csv = std::fs::read_to_string(out.join("equilibrium.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 2);
    assert!(lines[0].starts_with("t,tip.x,tip.y"), "{csv}");
    assert!(out.join("equilibrium.pvd").exists());
}

#[test]
fn the_wiper_with_its_motor_on_has_no_equilibrium_and_says_which_motion() {
    let out = scratch("equilibrium_wiper");
    let o = flexmb(&["equilibrium", "models/wiper/wiper.toml", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    let stderr = text(&o.stderr);
    assert!(stderr.contains("no static equilibrium") && stderr.contains("body 'crank': rotation about +z"), "{stderr}");
}
