//! Static equilibrium of model files with flexible bodies: a cantilever clamped to ground by a fixed
//! joint bends under a tip load by Euler–Bernoulli's `P L³ / 3EI` (its mode set holds the static
//! correction mode of that load, so the modal model reproduces the FE model's static deflection); the
//! robot arm started from its equilibrium stays still, where started from its assembly it rings.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use flexmb::analysis::{static_equilibrium, EquilibriumSettings, OutputTable, Simulation, Start, State};
use flexmb::Data;
use flexmb_files::{load_model, parse_model};

fn model_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models").join(name)
}

/// models/fe/cantilever.toml (steel 1 m × 20 mm × 10 mm, modes 4N2S with the static mode of a tip
/// force along z) clamped by a fixed joint, 10 N along z at the tip, no gravity: the tip deflects by
/// `P L³ / 3EI` = 9.524 mm (E = 210 GPa, I = w h³/12). The beam elements are Timoshenko's, whose shear
/// adds `P L / κ G A` ≈ 8e-5 of that: the tolerance is 2e-4.
#[test]
fn a_clamped_cantilever_bends_under_a_tip_load_as_euler_bernoulli_says() {
    let text = r#"
        [model]
        name = "clamped cantilever"
        gravity = [0, 0, 0]
        [[flexible_body]]
        name = "beam"
        fe_model = "fe/cantilever.toml"
        [[marker]]
        name = "wall"
        body = "ground"
        [[marker]]
        name = "root"
        body = "beam"
        node = "arm.start"
        [[marker]]
        name = "tip"
        body = "beam"
        node = "arm.end"
        [[joint]]
        name = "clamp"
        type = "fixed"
        i = "wall"
        j = "root"
        [[force]]
        name = "load"
        type = "force"
        marker = "tip"
        components = [0, 0, 10]
        [[output]]
        type = "node_position"
        name = "tip"
        body = "beam"
        node = [1.0, 0.0, 0.0]
    "#;
    let loaded = parse_model(text, model_file("cantilever_test.toml").to_str().unwrap()).unwrap();
    let model = &loaded.model;
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let report = static_equilibrium(model, &mut data, &mut state, 0.0, &EquilibriumSettings::default()).unwrap();
    let values = flexmb::analysis::equilibrium_outputs(model, &mut data, &state, &report.multipliers).unwrap();
    let (p, l, e, w, h): (f64, f64, f64, f64, f64) = (10.0, 1.0, 210e9, 0.020, 0.010);
    let expected = p * l.powi(3) / (3.0 * e * w * h.powi(3) / 12.0);
    let tip_z = values[2];
    assert!((tip_z / expected - 1.0).abs() < 2e-4, "tip {tip_z} m, Euler–Bernoulli {expected} m");
    // The clamp carries the load and its moment P L about y.
    let clamp = &report.reactions[0].sides[0];
    assert!((clamp.force[2] + p).abs() < 1e-9 * p, "{clamp:?}");
    assert!(report.iterations <= 3, "{report:?}");
}

/// The robot arm (a flexible link held horizontal by its shoulder motor) started from equilibrium: the
/// positions stay at the equilibrium's to 1e-9 over 1 s (the run's tolerances are 1e-6; a state
/// that solves the equations of motion at rest gives the integrator nothing to do); started from its
/// assembly the tip rings by more than 30 mm peak to peak.
#[test]
fn the_robot_arm_started_from_equilibrium_stays_still() {
    let loaded = load_model(&model_file("robot_arm.toml")).unwrap();
    let model = Arc::clone(&loaded.model);
    let d = loaded.simulation;
    assert!(matches!(d.start, Start::Equilibrium(_)));
    let mut data = Data::new(&model);
    let mut equilibrium = State::initial(&model);
    static_equilibrium(&model, &mut data, &mut equilibrium, 0.0, &EquilibriumSettings::default()).unwrap();
    let run = |start: Start| {
        let settings = flexmb::analysis::SimulationSettings { start, ..d.settings(&model, d.assembly()) };
        let mut table = OutputTable::with_states(&model);
        Simulation::new(Arc::clone(&model), settings).unwrap().run(&mut table, &|| None).unwrap();
        table
    };
    let still = run(d.start);
    let drift = (0..still.len())
        .flat_map(|i| still.positions(i).unwrap().iter().zip(&equilibrium.q).map(|(a, b)| (a - b).abs()).collect::<Vec<_>>())
        .fold(0.0, f64::max);
    assert!(drift < 1e-9, "largest |q(t) − q_eq| {drift:e}");
    let ringing = run(Start::Assembly).column("tip.y").unwrap();
    let swing = ringing.iter().fold(f64::MIN, |m, y| m.max(*y)) - ringing.iter().fold(f64::MAX, |m, y| m.min(*y));
    assert!(swing > 0.03, "peak to peak {swing} m");
}
