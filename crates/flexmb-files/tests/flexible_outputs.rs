//! The outputs of a flexible body (issue 18, point 5): models/fe/cantilever.toml (4 vibration modes)
//! floating free without gravity, thrown with rigid and elastic velocities. Its momenta are conserved
//! over the run; its kinetic energy and momenta equal those summed over the FE model's lumped nodal
//! masses and rotary inertias moved by the written state (`r_i = R + A (s̄_i + Ψ_i a)`, an independent
//! computation from the flexmb-fem assembly and the mode shapes, not from the inertia invariants);
//! and the angular acceleration written at the tip node is the time derivative of the angular
//! velocity written there.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use flexmb::analysis::{OutputTable, Simulation};
use flexmb::math::{rotation_matrix, Vec3};
use flexmb::model::BodyId;
use flexmb_files::parse_model;
use nalgebra::{DVector, Vector4};

fn model_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models").join(name)
}

const OUTPUT_STEP: f64 = 2.5e-5;

/// The free cantilever run for 0.05 s, its outputs every 25 µs with the states.
fn free_cantilever() -> (Arc<flexmb::Model>, OutputTable) {
    let text = format!(
        r#"
        [model]
        name = "free cantilever"
        gravity = [0, 0, 0]
        [simulation]
        t_end = 0.05
        output_step = {OUTPUT_STEP}
        rtol = 1e-11
        atol = 1e-11
        [[flexible_body]]
        name = "beam"
        fe_model = "fe/cantilever.toml"
        modes = "4N"
        velocity = [0.3, -0.1, 0.2]
        angular_velocity = [0.5, 2.0, 1.0]
        modal_rates = [0.3, -0.2, 0.1, 0.05]
        [[marker]]
        name = "tip"
        body = "beam"
        node = "arm.end"
        [[output]]
        type = "kinetic_energy"
        body = "beam"
        [[output]]
        type = "system_momentum"
        [[output]]
        type = "angular_velocity"
        marker = "tip"
        [[output]]
        type = "angular_acceleration"
        marker = "tip"
    "#
    );
    let loaded = parse_model(&text, model_file("free_cantilever_test.toml").to_str().unwrap()).unwrap();
    let model = Arc::clone(&loaded.model);
    let settings = loaded.simulation.settings(&model, loaded.simulation.assembly());
    let mut table = OutputTable::with_states(&model);
    Simulation::new(Arc::clone(&model), settings).unwrap().run(&mut table, &|| None).unwrap();
    (model, table)
}

/// Kinetic energy, linear momentum and angular momentum about the global origin summed over the FE
/// model's lumped nodes: node `i` at `r_i = R + A (s̄_i + Ψ_i a)` with velocity
/// `ṙ_i = Ṙ + A (ω̄ × (s̄_i + Ψ_i a) + Ψ_i ȧ)` and angular velocity `A (ω̄ + Θ_i ȧ)`.
fn nodal_sums(model: &flexmb::Model, masses: &[(u64, f64, nalgebra::Matrix3<f64>)], q: &[f64], v: &[f64]) -> (f64, Vec3, Vec3) {
    let body = model.modal_body(BodyId(0)).unwrap();
    let m = body.mode_labels.len();
    let r0 = Vec3::new(q[0], q[1], q[2]);
    let a_mat = rotation_matrix(&Vector4::new(q[3], q[4], q[5], q[6]));
    let a = DVector::from_column_slice(&q[7..7 + m]);
    let (rdot, omega, adot) = (Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), DVector::from_column_slice(&v[6..6 + m]));
    let (mut kinetic, mut linear, mut angular) = (0.0, Vec3::zeros(), Vec3::zeros());
    for node in &body.nodes {
        let &(_, mass, inertia) = masses.iter().find(|(label, _, _)| *label == node.label).unwrap();
        let s = node.position + &node.psi * &a;
        let r = r0 + a_mat * s;
        let velocity = rdot + a_mat * (omega.cross(&s) + &node.psi * &adot);
        let spin = omega + &node.theta * &adot;
        kinetic += 0.5 * mass * velocity.norm_squared() + 0.5 * spin.dot(&(inertia * spin));
        linear += mass * velocity;
        angular += r.cross(&(mass * velocity)) + a_mat * (inertia * spin);
    }
    (kinetic, linear, angular)
}

#[test]
fn a_free_flexible_body_keeps_its_momenta_and_its_energy_and_momenta_are_the_fe_nodes_sums() {
    let (model, table) = free_cantilever();
    let fe = flexmb_files::fe_model_file::load_fe_model(&model_file("fe/cantilever.toml")).unwrap().model;
    let assembled = flexmb_fem::assembly::assemble(&fe).unwrap();
    let masses: Vec<_> = fe.mesh.nodes.iter().zip(&assembled.nodal_masses).map(|(n, m)| (n.label, m.mass, m.rotary_inertia)).collect();
    let names = ["momentum.linear.x", "momentum.linear.y", "momentum.linear.z", "momentum.angular.x", "momentum.angular.y", "momentum.angular.z"];
    let columns: Vec<Vec<f64>> = names.iter().map(|n| table.column(n).unwrap()).collect();
    let energy = table.column("beam.kinetic_energy").unwrap();
    let (mut drift, mut energy_error, mut momentum_error) = (0.0_f64, 0.0_f64, 0.0_f64);
    let size = columns.iter().map(|c| c[0].abs()).fold(0.0, f64::max);
    for i in 0..table.len() {
        for c in &columns {
            drift = drift.max((c[i] - c[0]).abs() / size);
        }
        let (kinetic, linear, angular) = nodal_sums(&model, &masses, table.positions(i).unwrap(), table.velocities(i).unwrap());
        energy_error = energy_error.max((energy[i] - kinetic).abs() / kinetic);
        for k in 0..3 {
            momentum_error = momentum_error.max((columns[k][i] - linear[k]).abs() / size).max((columns[3 + k][i] - angular[k]).abs() / size);
        }
    }
    eprintln!(
        "free flexible body over {} rows: momenta drift {drift:.1e} of the largest component; kinetic energy against the FE nodes' sum {energy_error:.1e}; momenta against the nodes' sums {momentum_error:.1e}",
        table.len()
    );
    assert!(drift < 1e-8, "{drift:.1e}");
    assert!(energy_error < 1e-10, "{energy_error:.1e}");
    assert!(momentum_error < 1e-10, "{momentum_error:.1e}");
    let elastic = energy[0] - nodal_sums(&model, &masses, table.positions(0).unwrap(), &{
        let mut v = table.velocities(0).unwrap().to_vec();
        v[6..].iter_mut().for_each(|x| *x = 0.0);
        v
    }).0;
    assert!(elastic.abs() > 1e-3 * energy[0], "the elastic rates carry energy: {elastic:e} of {}", energy[0]);
}

/// The tip node's angular acceleration (global) against the five-point central difference in time of
/// its angular velocity written every 25 µs (truncation `h⁴ ω⁽⁵⁾ / 30`; the three-point difference's
/// `h² ω⃛ / 6` left 1.3e-2 at 0.1 ms and 8.3e-4 at 25 µs, the h² of a truncation, not a missing term).
#[test]
fn the_angular_acceleration_at_a_flexible_node_is_the_rate_of_its_angular_velocity() {
    let (_, table) = free_cantilever();
    let axes = ["x", "y", "z"];
    let omega: Vec<Vec<f64>> = axes.iter().map(|a| table.column(&format!("tip.angular_velocity.{a}")).unwrap()).collect();
    let alpha: Vec<Vec<f64>> = axes.iter().map(|a| table.column(&format!("tip.angular_acceleration.{a}")).unwrap()).collect();
    let size = alpha.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0_f64;
    for i in 2..table.len() - 2 {
        for k in 0..3 {
            let w = &omega[k];
            let rate = (8.0 * (w[i + 1] - w[i - 1]) - (w[i + 2] - w[i - 2])) / (12.0 * OUTPUT_STEP);
            worst = worst.max((rate - alpha[k][i]).abs() / size);
        }
    }
    eprintln!("tip angular acceleration against the five-point difference of its angular velocity: {worst:.1e} of its largest component {size:.3e} rad/s²");
    assert!(worst < 1e-5, "{worst:.1e}");
}
