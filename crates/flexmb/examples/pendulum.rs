//! A pendulum built in Rust code, simulated with `Simulation`, paused, checkpointed and continued,
//! and its period read from the results and compared with the theory.
//!
//! Run with `cargo run --release -p flexmb --example pendulum`.

use std::sync::Arc;

use flexmb::analysis::{OutputTable, Simulation, SimulationCheckpoint, SimulationSettings};
use flexmb::body::{InitialState, Marker, RigidBody};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{Mat3, Vec3};
use flexmb::model::{BodyRef, Model, ModelBuilder, ModelError, OutputKind};

/// Rod length (m), gravity (m/s²), release angle from the vertical (rad).
const LENGTH: f64 = 1.0;
const GRAVITY: f64 = 9.81;
const RELEASE: f64 = 0.2;

/// A 1 kg bob (nearly a point mass) on a massless rod of `LENGTH`, pivoted at the origin about z by a
/// revolute joint, released at rest `RELEASE` from the vertical; outputs the bob's position and the
/// energy.
fn pendulum() -> Result<Model, ModelError> {
    let mut b = ModelBuilder::new("pendulum").gravity(Vec3::new(0.0, -GRAVITY, 0.0));
    let bob_position = LENGTH * Vec3::new(RELEASE.sin(), -RELEASE.cos(), 0.0);
    let bob = b.add_body(RigidBody {
        name: "bob".into(),
        mass: 1.0,
        center_of_mass: Vec3::zeros(),
        inertia: Mat3::identity() * 1e-6,
        initial: InitialState { position: bob_position, ..Default::default() },
    })?;
    let marker = |name: &str, body, origin| Marker { name: name.into(), body, origin, axes: Mat3::identity() };
    let pivot = b.add_marker(marker("pivot", BodyRef::Ground, Vec3::zeros()))?;
    let hinge = b.add_marker(marker("hinge", BodyRef::Body(bob), -bob_position))?;
    let center = b.add_marker(marker("center", BodyRef::Body(bob), Vec3::zeros()))?;
    b.add_joint(Joint { name: "pin".into(), kind: JointKind::Revolute, marker_i: pivot, marker_j: hinge })?;
    b.add_output("bob", OutputKind::MarkerPosition(center))?;
    b.add_output("energy", OutputKind::Energy)?;
    b.build()
}

/// Times at which `x` crosses zero upwards, by linear interpolation between the rows.
fn upward_crossings(t: &[f64], x: &[f64]) -> Vec<f64> {
    (1..t.len())
        .filter(|&i| x[i - 1] < 0.0 && x[i] >= 0.0)
        .map(|i| t[i - 1] + (t[i] - t[i - 1]) * -x[i - 1] / (x[i] - x[i - 1]))
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = Arc::new(pendulum()?);
    let settings = SimulationSettings { t_end: 10.0, output_step: 0.001, ..Default::default() };
    let mut simulation = Simulation::new(model.clone(), settings)?;
    let mut table = OutputTable::new(&model);

    // Run half way, look at the state, and save it.
    simulation.advance_to(5.0, &mut table)?;
    let q = simulation.positions();
    println!("paused at t = {:.4} s: bob at ({:.4}, {:.4}) m, {} steps so far", simulation.time(), q[0], q[1], simulation.stats().steps);
    let saved = serde_json::to_string(&simulation.checkpoint()?)?;
    println!("checkpoint: {} bytes of JSON", saved.len());

    // Continue from the saved state in a new simulation (as a later process would).
    let checkpoint: SimulationCheckpoint = serde_json::from_str(&saved)?;
    let mut resumed = Simulation::resume(model.clone(), settings, &checkpoint)?;
    resumed.advance_to(settings.t_end, &mut table)?;
    let report = resumed.report();
    println!("finished at t = {} s: {} steps, {} output rows", report.t_reached, report.stats.steps, table.len());

    // Read the results by column name.
    let t = table.column("t").ok_or("no column t")?;
    let x = table.column("bob.x").ok_or("no column bob.x")?;
    let energy = table.column("energy.total").ok_or("no column energy.total")?;
    let crossings = upward_crossings(&t, &x);
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    // Small-amplitude period with the first amplitude correction: 2π √(L/g) (1 + θ₀²/16).
    let theory = std::f64::consts::TAU * (LENGTH / GRAVITY).sqrt() * (1.0 + RELEASE * RELEASE / 16.0);
    println!("period {period:.5} s, theory {theory:.5} s (differs by {:.1e})", (period - theory).abs() / theory);
    let drift = energy.iter().map(|e| (e - energy[0]).abs()).fold(0.0, f64::max);
    println!("energy {:.6} J, largest drift {drift:.2e} J", energy[0]);
    Ok(())
}
