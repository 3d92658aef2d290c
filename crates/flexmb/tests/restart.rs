//! Restart: a simulation checkpointed after any step, the checkpoint written to JSON and read back,
//! and resumed in a new `Simulation`, continues with the same steps and the same outputs as the run
//! that was never stopped — for the BDF, the Adams method and the generalized-α method, on a rigid
//! closed loop (a slider-crank) and on a model with a flexible body.

mod support;

use std::sync::Arc;

use flexmb::analysis::{
    simulate, OutputSink, OutputTable, Simulation, SimulationCheckpoint, SimulationFailure, SimulationSettings,
};
use flexmb::integrate::adams::ConstraintHandling;
use flexmb::integrate::{AdamsConfig, CheckpointError, Method, Stats};
use flexmb::math::Vec3;
use flexmb::model::{Model, OutputKind};
use flexmb::integrate::IntegratorCheckpoint;
use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3};
use flexmb::model::BodyRef;
use support::{joint, lumped_flexible_pendulum, marker, rigid, settings, slider_crank_linkage};

/// Agreement asked of the split run: the resumed integrator has the same history, step size, order and
/// Jacobian, so its steps are the uninterrupted run's to round-off (they come out bitwise equal; the
/// bound leaves room for a different summation order of a platform's LU).
const TOLERANCE: f64 = 1e-10;

/// The state after every accepted step: time, positions, velocities.
#[derive(Default)]
struct Trajectory {
    steps: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

impl Trajectory {
    fn record(&mut self, simulation: &Simulation) {
        self.steps.push((simulation.time(), simulation.positions().to_vec(), simulation.velocities().to_vec()));
    }
}

/// Steps `simulation` to its end, recording every step.
fn finish(simulation: &mut Simulation, table: &mut dyn OutputSink, trajectory: &mut Trajectory) {
    while !simulation.is_finished() {
        simulation.step(table).unwrap();
        trajectory.record(simulation);
    }
}

/// One uninterrupted run: its steps, its outputs (with states), its final counters.
fn uninterrupted(model: &Arc<Model>, settings: SimulationSettings) -> (Trajectory, OutputTable, Stats) {
    let mut simulation = Simulation::new(model.clone(), settings).unwrap();
    let mut table = OutputTable::with_states(model);
    let mut trajectory = Trajectory::default();
    finish(&mut simulation, &mut table, &mut trajectory);
    (trajectory, table, *simulation.stats())
}

/// A run paused at the first step at or after `t_split`, checkpointed, the checkpoint sent through
/// JSON, and resumed in a new simulation.
fn split(model: &Arc<Model>, settings: SimulationSettings, t_split: f64) -> (Trajectory, OutputTable, Stats) {
    let mut table = OutputTable::with_states(model);
    let mut trajectory = Trajectory::default();
    let json = {
        let mut first = Simulation::new(model.clone(), settings).unwrap();
        // Step by step to record the trajectory (advance_to does the same steps).
        first.advance_to(0.0, &mut table).unwrap();
        while first.time() < t_split {
            first.step(&mut table).unwrap();
            trajectory.record(&first);
        }
        serde_json::to_string(&first.checkpoint().unwrap()).unwrap()
    };
    let checkpoint: SimulationCheckpoint = serde_json::from_str(&json).unwrap();
    let mut second = Simulation::resume(model.clone(), settings, &checkpoint).unwrap();
    assert_eq!(second.time(), checkpoint.t);
    finish(&mut second, &mut table, &mut trajectory);
    (trajectory, table, *second.stats())
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= TOLERANCE * (1.0 + x.abs()))
}

/// The split runs at `splits` equal the uninterrupted run: every step (time, q, v), every output row
/// (time, values, q, v), the counters.
fn assert_restart_continues(name: &str, model: Model, settings: SimulationSettings, splits: &[f64]) {
    let model = Arc::new(model);
    let (reference, table, stats) = uninterrupted(&model, settings);
    assert!(reference.steps.len() > 20, "{name}: only {} steps", reference.steps.len());
    for &t_split in splits {
        let (trajectory, split_table, split_stats) = split(&model, settings, t_split);
        let what = format!("{name}, split at {t_split} s");
        assert_eq!(trajectory.steps.len(), reference.steps.len(), "{what}: number of steps");
        for (k, ((t, q, v), (t_ref, q_ref, v_ref))) in trajectory.steps.iter().zip(&reference.steps).enumerate() {
            assert!(close(&[*t], &[*t_ref]), "{what}: step {k} ends at {t}, uninterrupted at {t_ref}");
            assert!(close(q, q_ref) && close(v, v_ref), "{what}: state after step {k} (t = {t}) differs");
        }
        assert_eq!(split_table.len(), table.len(), "{what}: number of outputs");
        for i in 0..table.len() {
            let row = split_table.row(i).unwrap();
            assert!(close(row, table.row(i).unwrap()), "{what}: output row {i} (t = {}) differs", row[0]);
            assert!(close(split_table.positions(i).unwrap(), table.positions(i).unwrap()), "{what}: q of row {i}");
            assert!(close(split_table.velocities(i).unwrap(), table.velocities(i).unwrap()), "{what}: v of row {i}");
        }
        assert_eq!(split_stats, stats, "{what}: counters");
    }
}

/// The slider-crank (a closed loop: revolute, spherical, universal, translational) started spinning,
/// under gravity across the slide, with the slider's position, the crank's reaction and the energy as
/// outputs.
fn slider_crank() -> Model {
    let mut b = flexmb::ModelBuilder::new("slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    let crank = slider_crank_linkage(&mut b, 0.1, 0.3, Some(Vec3::new(0.0, 0.0, 12.0)));
    b.add_output("slider", OutputKind::MarkerPosition(crank.slider_pin)).unwrap();
    b.add_output("crank", OutputKind::JointReaction(crank.crank_joint)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    b.build().unwrap()
}

/// The lumped flexible pendulum (3 modes, 2 % damping) with the tip's position, the modal coordinates
/// and the energy as outputs.
fn flexible_pendulum() -> Model {
    let (mut b, beam, tip) = lumped_flexible_pendulum([400.0, 3000.0, 9000.0], [0.1, 0.0, 0.0]);
    b.add_output("tip", OutputKind::MarkerPosition(tip)).unwrap();
    b.add_output("modes", OutputKind::ModalCoordinates(beam)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    b.build().unwrap()
}

fn with_method(mut settings: SimulationSettings, method: Method) -> SimulationSettings {
    settings.method = method;
    settings
}

/// Splits: before the first step's end (at 0: a checkpoint of the started integrator), before the
/// first output, mid-interval between outputs, on an output time, late in the run.
const SPLITS: [f64; 5] = [0.0, 0.003, 0.137, 0.2, 0.41];

#[test]
fn bdf_restart_continues_the_same_steps_on_a_closed_loop() {
    assert_restart_continues("bdf, slider-crank", slider_crank(), settings(0.5, 0.05, 1e-7), &SPLITS);
}

#[test]
fn bdf_restart_continues_the_same_steps_on_a_flexible_body() {
    let model = flexible_pendulum();
    let mut s = settings(0.5, 0.05, 1e-7);
    s.method = Method::Bdf(flexmb::integrate::BdfConfig { stability_limits: true, ..Default::default() });
    assert_restart_continues("bdf, flexible pendulum", model, s, &SPLITS);
}

#[test]
fn adams_restart_continues_the_same_steps_on_a_closed_loop() {
    let s = with_method(settings(0.5, 0.05, 1e-7), Method::Adams(AdamsConfig::default()));
    assert_restart_continues("adams, slider-crank", slider_crank(), s, &SPLITS);
}

#[test]
fn adams_restart_continues_the_same_steps_on_a_flexible_body() {
    let s = with_method(settings(0.5, 0.05, 1e-7), Method::Adams(AdamsConfig::default()));
    assert_restart_continues("adams, flexible pendulum", flexible_pendulum(), s, &SPLITS);
}

#[test]
fn generalized_alpha_restart_continues_the_same_steps_on_a_closed_loop() {
    let s = with_method(settings(0.5, 0.05, 1e-6), Method::generalized_alpha(0.8));
    assert_restart_continues("gen-alpha, slider-crank", slider_crank(), s, &SPLITS);
}

#[test]
fn generalized_alpha_restart_continues_the_same_steps_on_a_flexible_body() {
    let s = with_method(settings(0.5, 0.05, 1e-6), Method::generalized_alpha(0.8));
    assert_restart_continues("gen-alpha, flexible pendulum", flexible_pendulum(), s, &SPLITS);
}

/// The peer's chain of `n` rods (1 kg, 0.5 m) on spherical joints, falling from the horizontal: a
/// chaotic motion, in which a difference in the last bit grows to the tolerance within the run.
fn chain(n: usize) -> Model {
    let mut b = flexmb::ModelBuilder::new("chain").gravity(Vec3::new(0.0, 0.0, -9.81));
    let length = 0.5;
    let inertia = Mat3::from_diagonal(&Vec3::new(1e-4, length * length / 12.0, length * length / 12.0));
    let mut end = marker(&mut b, "anchor", BodyRef::Ground, Vec3::zeros());
    for i in 0..n {
        let position = Vec3::new((i as f64 + 0.5) * length, 0.0, 0.0);
        let rod = b.add_body(rigid(&format!("rod{i}"), 1.0, Vec3::zeros(), inertia, position, EulerParameters::identity(), None, None)).unwrap();
        let start = marker(&mut b, &format!("rod{i}_start"), BodyRef::Body(rod), Vec3::new(-0.5 * length, 0.0, 0.0));
        joint(&mut b, &format!("s{i}"), JointKind::Spherical, end, start);
        end = marker(&mut b, &format!("rod{i}_end"), BodyRef::Body(rod), Vec3::new(0.5 * length, 0.0, 0.0));
    }
    b.add_output("tip", OutputKind::MarkerPosition(end)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    b.build().unwrap()
}

/// The iteration matrices of the chain of 8 rods (160 unknowns for the BDF, 96 for generalized-α), and
/// the dependent coordinates' matrix of the Adams method's partition on the chain of 12 (48 rows), are
/// refactored on kept pivots, which the checkpoint carries: a run split anywhere takes the uninterrupted
/// run's steps to the last bit, every state after every step equal.
fn assert_chain_restart_is_bitwise(name: &str, rods: usize, settings: SimulationSettings, pivots: usize) {
    let model = Arc::new(chain(rods));
    let (reference, _, stats) = uninterrupted(&model, settings);
    assert!(reference.steps.len() > 50, "{name}: only {} steps", reference.steps.len());
    for t_split in [0.003, 0.137, 0.2] {
        let mut first = Simulation::new(model.clone(), settings).unwrap();
        first.advance_to(t_split, &mut OutputTable::new(&model)).unwrap();
        let kept = match &first.checkpoint().unwrap().integrator {
            IntegratorCheckpoint::Bdf(c) => c.kept_pivots.clone(),
            IntegratorCheckpoint::GeneralizedAlpha(c) => c.kept_pivots.clone(),
            IntegratorCheckpoint::Adams(c) => c.partition.as_ref().and_then(|p| p.kept_pivots().map(<[usize]>::to_vec)),
        };
        assert_eq!(kept.map(|p| p.len()), Some(pivots), "{name}: the checkpoint keeps the pivots");
        let (trajectory, _, split_stats) = split(&model, settings, t_split);
        assert_eq!(trajectory.steps.len(), reference.steps.len(), "{name}, split at {t_split} s: number of steps");
        let first_difference = trajectory.steps.iter().zip(&reference.steps).position(|(a, b)| a != b);
        assert_eq!(first_difference, None, "{name}, split at {t_split} s: the first step that differs in a bit");
        assert_eq!(split_stats, stats, "{name}, split at {t_split} s: counters");
    }
}

#[test]
fn bdf_restart_of_a_chain_continues_bitwise_on_the_kept_pivots() {
    assert_chain_restart_is_bitwise("bdf", 8, settings(0.3, 0.05, 1e-8), 160);
}

#[test]
fn generalized_alpha_restart_of_a_chain_continues_bitwise_on_the_kept_pivots() {
    assert_chain_restart_is_bitwise("gen-alpha", 8, with_method(settings(0.3, 0.05, 1e-6), Method::generalized_alpha(0.8)), 96);
}

#[test]
fn adams_with_partitioning_restart_of_a_chain_continues_bitwise_on_the_kept_pivots() {
    let partitioning = AdamsConfig { constraints: ConstraintHandling::Partitioning, ..Default::default() };
    assert_chain_restart_is_bitwise("adams with partitioning", 12, with_method(settings(0.3, 0.05, 1e-8), Method::Adams(partitioning)), 48);
}

/// The `simulate` wrapper is the `Simulation` run to its end: the same outputs, the same counters.
#[test]
fn simulate_is_a_simulation_run_to_its_end() {
    let model = slider_crank();
    let s = settings(0.5, 0.05, 1e-7);
    let mut rows = Vec::new();
    let report = simulate(&model, &s, &mut |f| rows.push([&[f.t][..], f.values].concat())).unwrap();
    let model = Arc::new(model);
    let (_, table, stats) = uninterrupted(&model, s);
    assert_eq!(report.stats, stats);
    assert_eq!(rows.len(), table.len());
    assert!((0..rows.len()).all(|i| rows[i] == table.row(i).unwrap()));
}

/// A run resumed with a later end time continues past the old one; its outputs take up the grid where
/// the first run left it.
#[test]
fn a_finished_run_resumes_to_a_later_end_time() {
    let model = Arc::new(slider_crank());
    let short = settings(0.3, 0.05, 1e-7);
    let mut first = Simulation::new(model.clone(), short).unwrap();
    let mut table = OutputTable::new(&model);
    first.advance_to(1.0, &mut table).unwrap();
    assert!(first.is_finished() && first.time() == 0.3);
    let checkpoint = first.checkpoint().unwrap();
    let long = SimulationSettings { t_end: 0.5, ..short };
    let mut second = Simulation::resume(model.clone(), long, &checkpoint).unwrap();
    second.advance_to(0.5, &mut table).unwrap();
    let t = table.column("t").unwrap();
    let expected: Vec<f64> = (0..=10).map(|k| k as f64 * 0.05).collect();
    assert!(close(&t, &expected), "output times {t:?}");
    assert!(second.report().output_frames == 11 && second.is_finished());
}

/// What cannot be resumed says why: a checkpoint of another method, or of the Adams method with another
/// constraint handling.
#[test]
fn checkpoints_that_cannot_be_resumed_say_why() {
    let model = Arc::new(slider_crank());
    let bdf = settings(0.2, 0.05, 1e-7);
    let mut simulation = Simulation::new(model.clone(), bdf).unwrap();
    simulation.advance_to(0.1, &mut |_: &flexmb::analysis::OutputFrame| {}).unwrap();
    let checkpoint = simulation.checkpoint().unwrap();
    let gen_alpha = with_method(bdf, Method::generalized_alpha(0.8));
    let error = Simulation::resume(model.clone(), gen_alpha, &checkpoint).err().unwrap();
    assert_eq!(
        error.cause,
        SimulationFailure::Checkpoint(CheckpointError::Method { expected: "gen-alpha", found: "bdf" })
    );
    assert_eq!(error.to_string(), "the checkpoint is of the bdf method, the simulation uses gen-alpha");

    let partitioning = AdamsConfig { constraints: ConstraintHandling::Partitioning, ..Default::default() };
    let projection = with_method(bdf, Method::Adams(AdamsConfig::default()));
    let mut simulation = Simulation::new(model.clone(), projection).unwrap();
    simulation.advance_to(0.1, &mut |_: &flexmb::analysis::OutputFrame| {}).unwrap();
    let checkpoint = simulation.checkpoint().unwrap();
    let error = Simulation::resume(model, with_method(bdf, Method::Adams(partitioning)), &checkpoint).err().unwrap();
    assert!(matches!(error.cause, SimulationFailure::Checkpoint(CheckpointError::Unsupported(_))), "{error}");
}

/// The Adams method with generalized coordinate partitioning: the partition, its factors and the last
/// evaluation travel with the checkpoint, and the resumed run takes the same steps.
#[test]
fn adams_with_partitioning_restart_continues_the_same_steps() {
    let partitioning = AdamsConfig { constraints: ConstraintHandling::Partitioning, ..Default::default() };
    let s = with_method(settings(0.5, 0.05, 1e-7), Method::Adams(partitioning));
    assert_restart_continues("adams with partitioning, slider-crank", slider_crank(), s, &SPLITS);
    assert_restart_continues("adams with partitioning, flexible pendulum", flexible_pendulum(), s, &SPLITS);
}

/// A simulation is `Send`: started on one thread and finished on another (as a Python binding or a
/// sweep may do), it takes the steps of a run on one thread.
#[test]
fn a_simulation_finishes_on_another_thread() {
    let model = Arc::new(flexible_pendulum());
    let s = settings(0.3, 0.05, 1e-7);
    let (reference, _, stats) = uninterrupted(&model, s);
    let mut simulation = Simulation::new(model.clone(), s).unwrap();
    simulation.advance_to(0.1, &mut |_: &flexmb::analysis::OutputFrame| {}).unwrap();
    let finished = std::thread::spawn(move || {
        simulation.advance_to(1.0, &mut |_: &flexmb::analysis::OutputFrame| {}).unwrap();
        simulation
    })
    .join()
    .unwrap();
    let (t, q, v) = reference.steps.last().unwrap();
    assert_eq!((finished.time(), finished.positions(), finished.velocities()), (*t, &q[..], &v[..]));
    assert_eq!(*finished.stats(), stats);
}

/// The command line's path: `run` stopped by its interrupt after some steps (as by SIGINT), the
/// checkpoint taken there, and `run` again on the resumed simulation; the outputs together are those of
/// the uninterrupted run, the report of the resumed run is not marked interrupted.
#[test]
fn a_run_checkpointed_at_an_interruption_resumes_to_the_uninterrupted_results() {
    let model = Arc::new(flexible_pendulum());
    let s = settings(0.5, 0.05, 1e-7);
    let (_, reference, stats) = uninterrupted(&model, s);
    let mut table = OutputTable::with_states(&model);
    let mut first = Simulation::new(model.clone(), s).unwrap();
    let calls = std::cell::Cell::new(0);
    let interrupt = || {
        calls.set(calls.get() + 1);
        (calls.get() == 37).then(|| "SIGINT".to_string())
    };
    first.run(&mut table, &interrupt).unwrap();
    let interruption = first.report().interrupted.clone().unwrap();
    assert_eq!((interruption.t, interruption.reason.as_str()), (first.time(), "SIGINT"));
    assert!(first.time() < 0.5 && !first.is_finished());
    let json = serde_json::to_string(&first.checkpoint().unwrap()).unwrap();
    let mut second = Simulation::resume(model, s, &serde_json::from_str(&json).unwrap()).unwrap();
    second.run(&mut table, &|| None).unwrap();
    assert!(second.is_finished() && second.report().interrupted.is_none());
    assert_eq!(*second.stats(), stats);
    assert_eq!(table.len(), reference.len());
    assert!((0..table.len()).all(|i| close(table.row(i).unwrap(), reference.row(i).unwrap())));
}

/// A checkpoint of one model does not resume on another: the sizes are checked and named.
#[test]
fn a_checkpoint_of_another_model_is_refused() {
    let s = settings(0.2, 0.05, 1e-7);
    let mut simulation = Simulation::new(Arc::new(slider_crank()), s).unwrap();
    simulation.advance_to(0.1, &mut |_: &flexmb::analysis::OutputFrame| {}).unwrap();
    let checkpoint = simulation.checkpoint().unwrap();
    let error = Simulation::resume(Arc::new(flexible_pendulum()), s, &checkpoint).err().unwrap();
    assert_eq!(
        error.to_string(),
        "the checkpoint does not fit the model: it has 21 values for the positions, the model 10"
    );
}

/// A run resumed with another output step reports on its own grid after the checkpoint's time; the
/// output step does not change the steps, so those rows are the rows of a run on that grid throughout.
#[test]
fn a_run_resumes_with_another_output_step() {
    let model = Arc::new(slider_crank());
    let coarse = settings(0.5, 0.05, 1e-7);
    let fine = SimulationSettings { output_step: 0.02, ..coarse };
    let (_, reference, stats) = uninterrupted(&model, fine);
    let mut first = Simulation::new(model.clone(), coarse).unwrap();
    let mut table = OutputTable::with_states(&model);
    first.advance_to(0.21, &mut table).unwrap();
    let t_split = first.time();
    let before = table.len();
    let mut second = Simulation::resume(model.clone(), fine, &first.checkpoint().unwrap()).unwrap();
    second.advance_to(0.5, &mut table).unwrap();
    assert_eq!(*second.stats(), stats);
    let t = table.column("t").unwrap();
    assert!(t[..before].iter().enumerate().all(|(k, t)| (t - k as f64 * 0.05).abs() < 1e-12), "{t:?}");
    let first_fine = (t_split / 0.02).floor() as usize + 1;
    assert_eq!(table.len() - before, reference.len() - first_fine);
    for (i, j) in (before..table.len()).zip(first_fine..) {
        assert!(close(table.row(i).unwrap(), reference.row(j).unwrap()), "row {i} (t = {}) against {}", t[i], reference.row(j).unwrap()[0]);
    }
}

/// Taking a checkpoint (and reading the multipliers, accelerations and linearization) between steps does
/// not disturb the run: one that does so after every step takes the steps of one that does not.
#[test]
fn checkpoints_and_readings_between_steps_leave_the_run_unchanged() {
    for (name, model, method) in [
        ("bdf, flexible pendulum", flexible_pendulum(), Method::default()),
        ("adams, slider-crank", slider_crank(), Method::Adams(AdamsConfig::default())),
        ("gen-alpha, slider-crank", slider_crank(), Method::generalized_alpha(0.8)),
    ] {
        let model = Arc::new(model);
        let s = with_method(settings(0.3, 0.05, 1e-7), method);
        let (reference, table, stats) = uninterrupted(&model, s);
        let mut simulation = Simulation::new(model.clone(), s).unwrap();
        let mut observed = OutputTable::with_states(&model);
        let mut trajectory = Trajectory::default();
        while !simulation.is_finished() {
            simulation.step(&mut observed).unwrap();
            trajectory.record(&simulation);
            simulation.checkpoint().unwrap();
            simulation.accelerations().unwrap();
            simulation.linearize().unwrap();
        }
        assert_eq!(*simulation.stats(), stats, "{name}: counters");
        assert!(trajectory.steps.iter().zip(&reference.steps).all(|(a, b)| a == b), "{name}: steps");
        assert!((0..table.len()).all(|i| observed.row(i).unwrap() == table.row(i).unwrap()), "{name}: outputs");
    }
}
