//! A beam without rotary inertia (Euler–Bernoulli, as ANCF cables are) is simulated: its frame's spin
//! about the beam's axis carries no mass, which the hinge holds, and a torque's static mode that only
//! twists it is dropped by the reduction. The hinged steel pendulum (1 m, 20 mm square, hinged at one
//! end about z, released horizontal, gravity −y; four clamped-free modes) runs with every integrator;
//! its tip follows the same beam given a tiny rotary inertia (1e-9 kg m² at each node) to 2e-7 m
//! (measured 4.8e-8 to 6.2e-8 m, lumped and consistent mass) in no more steps (within the step
//! control's noise, 1 %), and with consistent mass it follows Exudyn's 32-element ANCF cable
//! (tests/data/ancf_pendulum_tip.csv) to 3e-5 m, the four-mode truncation (measured 1.9e-5 to 2.0e-5 m, against
//! the tip's elastic deflection of 2.6e-4 m; eight modes 7.3e-6 m).
//!
//! On a ball joint nothing holds the spin; the gauge does (`ω̄ · e = 0` through a gauge inertia, the
//! module `analysis::massless_motions` of the engine). The same pendulum on a spherical joint runs with
//! every integrator, its tip within 2e-7 m of the beam with the tiny rotary inertia (consistent mass;
//! measured 5.4e-8 to 1.1e-7 m) in no more steps, and of the hinged beam (the motion is planar; 1.3e-7 m); started
//! spinning at 5 rad/s about its own axis, its tip swings as without the spin (1.0e-7 m), the spin
//! moving no mass; and free, it falls undeformed, its tip at `(1, −g t²/2)`. About 5 s in release
//! (19 runs of about 5,000 to 17,000 steps).
use std::path::{Path, PathBuf};
use std::sync::Arc;

use flexmb::analysis::{check_model, OutputTable, Simulation};
use flexmb_files::model_file::parse_model_in;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmb-files-euler-bernoulli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The FE model: the peer's beam (models/peer/fe/beam_20x20.toml: 40 beam elements, clamped at the
/// hinge end for the modes) with `mass` lumped or consistent and without rotary inertia; with
/// `rotary > 0`, that much rotary inertia (kg m², about each axis) at every node; two static loads at
/// the tip, a torque about the axis (a pure twist) and a force across it.
fn fe_model(mass: &str, rotary: f64) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/peer/fe/beam_20x20.toml");
    let peer = std::fs::read_to_string(path).unwrap();
    assert!(peer.contains("mass = \"consistent\"") && peer.contains("rotary_inertia = true"), "the peer's beam changed");
    let mut text = peer.replace("mass = \"consistent\"", &format!("mass = \"{mass}\"")).replace("rotary_inertia = true", "rotary_inertia = false");
    text += "\n[[static_load]]\nname = \"tip_twist\"\nat = \"beam.end\"\ntorque = [1, 0, 0]\n\n\
             [[static_load]]\nname = \"tip_fy\"\nat = \"beam.end\"\nforce = [0, 1, 0]\n";
    if rotary > 0.0 {
        for node in 1..=41 {
            text += &format!("[[mass]]\nat = {node}\nmass = 0\nrotary_inertia = [{rotary}, {rotary}, {rotary}]\n");
        }
    }
    text
}

/// The pendulum on `fe` with `modes`, on a `joint` at its start (`revolute`, `spherical`) or free
/// (`None`), run by `integrator`.
fn pendulum(fe: &str, modes: &str, integrator: &str, joint: Option<&str>) -> String {
    let hinge = joint.map_or(String::new(), |joint| {
        format!(
            "[[marker]]\nname = \"g\"\nbody = \"ground\"\n[[marker]]\nname = \"b\"\nbody = \"beam\"\nnode = \"beam.start\"\n\
             [[joint]]\nname = \"hinge\"\ntype = \"{joint}\"\ni = \"g\"\nj = \"b\"\n"
        )
    });
    format!(
        r#"
        [model]
        name = "pendulum"
        gravity = [0.0, -9.81, 0.0]
        [simulation]
        t_end = 1.0
        output_step = 0.05
        integrator = "{integrator}"
        [[flexible_body]]
        name = "beam"
        fe_model = "{fe}"
        modes = "{modes}"
        {hinge}
        [[output]]
        type = "node_position"
        body = "beam"
        node = [1.0, 0.0, 0.0]
        "#
    )
}

struct Run {
    tip: Vec<[f64; 2]>,
    steps: usize,
}

fn run(dir: &Path, fe: &str, modes: &str, integrator: &str) -> Run {
    run_on(dir, &pendulum(fe, modes, integrator, Some("revolute")), integrator)
}

fn run_on(dir: &Path, text: &str, integrator: &str) -> Run {
    let loaded = parse_model_in(text, "pendulum.toml", dir).unwrap_or_else(|e| panic!("{e}"));
    let model = Arc::clone(&loaded.model);
    let settings = loaded.simulation.settings(&model, loaded.simulation.assembly());
    let mut table = OutputTable::new(&model);
    let mut simulation = Simulation::new(Arc::clone(&model), settings).unwrap_or_else(|e| panic!("{integrator}: {e}"));
    simulation.run(&mut table, &|| None).unwrap_or_else(|e| panic!("{integrator}: {e}"));
    let (x, y) = (table.column("beam.node41.position.x").unwrap(), table.column("beam.node41.position.y").unwrap());
    Run { tip: x.iter().zip(&y).map(|(&x, &y)| [x, y]).collect(), steps: simulation.stats().steps }
}

fn largest_distance(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs())).fold(0.0, f64::max)
}

/// Exudyn's ANCF tip every 0.05 s, from the test data (source in the file's header).
fn ancf_tip() -> Vec<[f64; 2]> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ancf_pendulum_tip.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('t'))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[1], v[2]]
        })
        .collect()
}

/// The tip of the run without rotary inertia within 2e-7 m of the run with the tiny one, in no more steps
/// (within the step control's noise, 1 %).
fn assert_as_with_a_tiny_rotary_inertia(case: &str, none: &Run, tiny: &Run) {
    let difference = largest_distance(&none.tip, &tiny.tip);
    println!("{case}: tip without rotary inertia − with 1e-9 kg m² {difference:.2e} m; steps {} and {}", none.steps, tiny.steps);
    assert!(difference < 2e-7, "{case}: {difference:.2e} m");
    assert!(none.steps as f64 <= 1.01 * tiny.steps as f64, "{case}: {} steps against {}", none.steps, tiny.steps);
}

#[test]
fn a_hinged_beam_without_rotary_inertia_runs_with_every_integrator_as_with_a_tiny_one() {
    let dir = scratch("hinged");
    let ancf = ancf_tip();
    for mass in ["lumped", "consistent"] {
        std::fs::write(dir.join(format!("{mass}.toml")), fe_model(mass, 0.0)).unwrap();
        std::fs::write(dir.join(format!("{mass}_tiny.toml")), fe_model(mass, 1e-9)).unwrap();
        for integrator in ["bdf", "adams", "gen-alpha"] {
            let none = run(&dir, &format!("{mass}.toml"), "4N", integrator);
            let tiny = run(&dir, &format!("{mass}_tiny.toml"), "4N", integrator);
            assert_as_with_a_tiny_rotary_inertia(&format!("{mass} mass, {integrator}"), &none, &tiny);
            if mass == "consistent" {
                let error = largest_distance(&none.tip, &ancf);
                println!("consistent mass, {integrator}: tip − ANCF {error:.2e} m");
                assert!(error < 3e-5, "{integrator}: {error:.2e} m from the ANCF cable");
            }
        }
    }
}

#[test]
fn a_static_mode_that_only_twists_the_beam_is_dropped_and_the_pendulum_runs() {
    let dir = scratch("twist");
    std::fs::write(dir.join("beam.toml"), fe_model("consistent", 0.0)).unwrap();
    let text = pendulum("beam.toml", "4N2S", "bdf", Some("revolute")).replace("modes = \"4N2S\"", "modes = \"4N2S\"\nbasis = \"raw\"");
    let loaded = parse_model_in(&text, "pendulum.toml", &dir).unwrap_or_else(|e| panic!("{e}"));
    let modal = loaded.model.modal_body(flexmb::model::BodyId(0)).unwrap();
    // The twist (S1) is gone; the bending of the tip force (S2) stays.
    assert_eq!(modal.mode_labels, ["N1", "N2", "N3", "N4", "S2"]);
    check_model(&loaded.model, Default::default()).unwrap();
}

/// The spherical pendulum's model, optionally spinning about its own axis at the start.
fn ball_pendulum(fe: &str, integrator: &str, spin: f64) -> String {
    let text = pendulum(fe, "4N", integrator, Some("spherical"));
    if spin == 0.0 {
        return text;
    }
    text.replace("modes = \"4N\"", &format!("modes = \"4N\"\nangular_velocity = [{spin}, 0.0, 0.0]"))
}

#[test]
fn a_beam_without_rotary_inertia_on_a_ball_joint_runs_with_every_integrator_as_with_a_tiny_one() {
    // Nothing holds the spin about the beam's axis: the gauge does (ω̄ · e = 0 through a gauge inertia).
    let dir = scratch("ball");
    std::fs::write(dir.join("beam.toml"), fe_model("consistent", 0.0)).unwrap();
    std::fs::write(dir.join("tiny.toml"), fe_model("consistent", 1e-9)).unwrap();
    for integrator in ["bdf", "adams", "gen-alpha"] {
        let none = run_on(&dir, &ball_pendulum("beam.toml", integrator, 0.0), integrator);
        let tiny = run_on(&dir, &ball_pendulum("tiny.toml", integrator, 0.0), integrator);
        assert_as_with_a_tiny_rotary_inertia(&format!("ball joint, {integrator}"), &none, &tiny);
        if integrator == "bdf" {
            // The same beam on the hinge swings the same way (the motion is planar).
            let hinged = run(&dir, "beam.toml", "4N", integrator);
            let difference = largest_distance(&none.tip, &hinged.tip);
            println!("ball joint − hinge, {integrator}: {difference:.2e} m");
            assert!(difference < 2e-7, "{integrator}: {difference:.2e} m from the hinged beam");
        }
    }
}

#[test]
fn the_spin_of_a_beam_without_rotary_inertia_about_its_axis_moves_no_mass() {
    // Started spinning at 5 rad/s about its own axis, the ball-jointed beam's tip swings as without the
    // spin: the gauge keeps the spin constant, and the deflection turns back in the modes.
    let dir = scratch("spin");
    std::fs::write(dir.join("beam.toml"), fe_model("consistent", 0.0)).unwrap();
    let still = run_on(&dir, &ball_pendulum("beam.toml", "bdf", 0.0), "bdf");
    let spinning = run_on(&dir, &ball_pendulum("beam.toml", "bdf", 5.0), "bdf");
    let difference = largest_distance(&still.tip, &spinning.tip);
    println!("tip spinning − still {difference:.2e} m; steps {} and {}", spinning.steps, still.steps);
    assert!(difference < 2e-7, "{difference:.2e} m");
}

#[test]
fn a_free_floating_beam_without_rotary_inertia_falls_freely() {
    // No joint: the gauge holds the spin, and the beam falls undeformed, its tip at (1, −g t²/2).
    let dir = scratch("free");
    std::fs::write(dir.join("beam.toml"), fe_model("consistent", 0.0)).unwrap();
    let text = pendulum("beam.toml", "4N", "bdf", None);
    let loaded = parse_model_in(&text, "free.toml", &dir).unwrap_or_else(|e| panic!("{e}"));
    check_model(&loaded.model, Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let fall = run_on(&dir, &text, "bdf");
    let closed_form: Vec<[f64; 2]> = (0..fall.tip.len()).map(|k| 0.05 * k as f64).map(|t| [1.0, -0.5 * 9.81 * t * t]).collect();
    let error = largest_distance(&fall.tip, &closed_form);
    let along = fall.tip.iter().map(|p| (p[0] - 1.0).abs()).fold(0.0, f64::max);
    println!("free fall: tip − closed form {error:.2e} m (along the beam {along:.2e} m) in {} steps", fall.steps);
    // The fall's error is the BDF's at its default tolerances (its first steps are of order 1).
    assert!(error < 2e-5 && along < 1e-9, "{error:.2e} m, {along:.2e} m along");
}
