//! Static equilibrium of model files with flexible bodies: a cantilever clamped to ground by a fixed
//! joint bends under a tip load by Euler–Bernoulli's `P L³ / 3EI` (its mode set holds the static
//! correction mode of that load, so the modal model reproduces the FE model's static deflection); the
//! same cantilever's deflection at every node against the FE model's own static solution `K u = f`
//! (the flexmb-fem assembly, solved here), under a tip load and under gravity, with and without the
//! static correction modes; the robot arm started from its equilibrium stays still, where started
//! from its assembly it rings.

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
    let text = clamped_cantilever("", 0.0, 10.0)
        + r#"
        [[output]]
        type = "node_position"
        name = "tip"
        body = "beam"
        node = [1.0, 0.0, 0.0]
    "#;
    let loaded = parse_model(&text, model_file("cantilever_test.toml").to_str().unwrap()).unwrap();
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

/// The deflection `Ψ a` at every node of models/fe/cantilever.toml clamped by a fixed joint, at the
/// static equilibrium with the mode set `modes`, gravity `g` along −z and a tip force `p` along z, by
/// node label.
fn equilibrium_deflection(modes: &str, g: f64, p: f64) -> Vec<(u64, [f64; 3])> {
    let text = clamped_cantilever(&format!("modes = \"{modes}\""), g, p);
    let loaded = parse_model(&text, model_file("cantilever_test.toml").to_str().unwrap()).unwrap();
    let model = &loaded.model;
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    static_equilibrium(model, &mut data, &mut state, 0.0, &EquilibriumSettings::default()).unwrap();
    let beam = flexmb::model::BodyId(0);
    let a = nalgebra::DVector::from_column_slice(&state.q[model.layout().modal_q_range(beam).unwrap()]);
    let body = model.modal_body(beam).unwrap();
    body.nodes.iter().map(|n| (n.label, (&n.psi * &a).into())).collect()
}

/// models/fe/cantilever.toml clamped at its start by a fixed joint, gravity `g` along −z, a force `p`
/// along z at its end; `modes_line` (e.g. `modes = "4N"`, or empty) goes into the body's table.
fn clamped_cantilever(modes_line: &str, g: f64, p: f64) -> String {
    format!(
        r#"
        [model]
        name = "clamped cantilever"
        gravity = [0, 0, {}]
        [[flexible_body]]
        name = "beam"
        fe_model = "fe/cantilever.toml"
        {modes_line}
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
        components = [0, 0, {p}]
    "#,
        -g
    )
}

/// The static solution `K u = f` of the FE model itself (its supports clamp node 1) for gravity `g`
/// along −z (`f = M g` with the assembled mass) and a tip force `p` along z, by node label.
fn fe_static_deflection(g: f64, p: f64) -> Vec<(u64, [f64; 3])> {
    use faer::linalg::solvers::Solve;
    use flexmb_fem::Dof;
    let fe = flexmb_files::fe_model_file::load_fe_model(&model_file("fe/cantilever.toml")).unwrap().model;
    let assembled = flexmb_fem::assembly::assemble(&fe).unwrap();
    let dofs = &assembled.dofs;
    let n = dofs.n_free();
    let nodes = &fe.mesh.nodes;
    let tip = (0..nodes.len()).max_by(|&i, &j| nodes[i].position.x.total_cmp(&nodes[j].position.x)).unwrap();
    let mut along_z = faer::Mat::<f64>::zeros(n, 1);
    for node in 0..nodes.len() {
        if let Some(e) = dofs.equation(node, Dof::Uz) {
            along_z[(e, 0)] = -g;
        }
    }
    let mut f = &assembled.mass * &along_z;
    f[(dofs.equation(tip, Dof::Uz).unwrap(), 0)] += p;
    let u = assembled.stiffness.to_dense().partial_piv_lu().solve(&f);
    (0..nodes.len())
        .map(|node| {
            let component = |dof: Dof| dofs.equation(node, dof).map_or(0.0, |e| u[(e, 0)]);
            (nodes[node].label, [component(Dof::Ux), component(Dof::Uy), component(Dof::Uz)])
        })
        .collect()
}

/// The largest difference of two deflections over the nodes, relative to the largest FE deflection.
fn deflection_error(found: &[(u64, [f64; 3])], fe: &[(u64, [f64; 3])]) -> f64 {
    let size = fe.iter().flat_map(|(_, u)| u.iter()).fold(0.0_f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0_f64;
    for (label, u) in fe {
        let (_, x) = found.iter().find(|(l, _)| l == label).unwrap_or_else(|| panic!("node {label} in the flexible body"));
        worst = (0..3).fold(worst, |w, k| w.max((x[k] - u[k]).abs() / size));
    }
    worst
}

/// models/fe/cantilever.toml clamped by a fixed joint at its clamped node: the equilibrium's
/// deflection `Ψ a` at all 21 nodes against the FE model's static solution `K u = f` (assembled by
/// flexmb-fem, solved densely here). Under a 10 N tip force along z the mode set 4N2S, which holds the
/// static correction mode of that load, reproduces it to round-off; the vibration modes alone (4N)
/// leave the truncation error of the modal series. Under gravity (a distributed load no static mode
/// is made for) both mode sets leave a truncation error.
#[test]
fn a_clamped_cantilever_deflects_as_the_fe_model_s_static_solution() {
    let cases = [("tip force, 4N2S", "4N2S", 0.0, 10.0, 1e-10), ("tip force, 4N", "4N", 0.0, 10.0, 1e-2), ("gravity, 4N2S", "4N2S", 9.81, 0.0, 1e-3), ("gravity, 4N", "4N", 9.81, 0.0, 2e-3)];
    for (what, modes, g, p, tolerance) in cases {
        let fe = fe_static_deflection(g, p);
        let error = deflection_error(&equilibrium_deflection(modes, g, p), &fe);
        let tip = fe.iter().map(|(_, u)| u[2].abs()).fold(0.0, f64::max);
        eprintln!("clamped cantilever, {what}: FE tip deflection {tip:.6e} m; largest difference over the nodes {error:.1e} of it");
        assert!(error < tolerance, "{what}: {error:.1e}");
    }
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
