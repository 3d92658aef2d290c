//! Laws given as code (closures) in place of a model file's expressions, and a simulation's state set
//! between steps, through the library alone (as the Python package uses them): a controller written
//! as a closure runs the trajectory of the same law written as an expression; a driver's motion as a
//! closure that of the expression driver; a failing law stops the run naming itself and the time; a
//! checkpoint remembers its laws; set velocities and positions are made consistent and the motion after
//! them is that of a run started there.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use flexmb::analysis::{OutputTable, Simulation, SimulationFailure, SimulationSettings};
use flexmb::function::{UserFunction, UserMotion};
use flexmb::Model;
use flexmb_files::{load_model, parse_model, LoadedModel};

fn model_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models").join(name)
}

fn settings(loaded: &LoadedModel, t_end: f64, rtol: f64) -> SimulationSettings {
    let mut d = loaded.simulation;
    (d.t_end, d.rtol, d.atol) = (t_end, rtol, rtol);
    d.settings(&loaded.model, d.assembly())
}

fn run(model: Model, settings: SimulationSettings) -> OutputTable {
    let model = Arc::new(model);
    let mut table = OutputTable::new(&model);
    let mut simulation = Simulation::new(Arc::clone(&model), settings).unwrap();
    simulation.run(&mut table, &|| None).unwrap();
    table
}

/// The largest difference between the columns of two tables of the same model.
fn largest_difference(a: &OutputTable, b: &OutputTable) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut largest = 0.0_f64;
    for column in a.columns() {
        let (x, y) = (a.column(&column.name).unwrap(), b.column(&column.name).unwrap());
        largest = x.iter().zip(&y).fold(largest, |m, (x, y)| m.max((x - y).abs()));
    }
    largest
}

/// The PD controller of `models/pd_pendulum.toml` (k_p = 200, k_d = 20, θ_set = 0.5) as a closure.
fn pd_law(model: &Model) -> UserFunction {
    let measures = model.measure_ids(&["pivot_angle", "pivot_rate"]).unwrap();
    UserFunction::new("pd", measures, Arc::new(|_t, m: &[f64]| Ok(-200.0 * (m[0] - 0.5) - 20.0 * m[1]))).unwrap()
}

#[test]
fn a_controller_as_a_closure_runs_the_trajectory_of_the_same_expression_and_settles_at_the_static_offset() {
    let loaded = load_model(&model_file("pd_pendulum.toml")).unwrap();
    let settings = settings(&loaded, 3.0, 1e-8);
    let expression = run((*loaded.model).clone(), settings);
    let mut model = (*loaded.model).clone();
    model.set_force_law("controller", None, pd_law(&model)).unwrap();
    assert_eq!(model.user_laws(), ["pd"]);
    let closure = run(model, settings);
    let difference = largest_difference(&expression, &closure);
    assert!(difference < 1e-12, "largest difference {difference:e}");
    // Static equilibrium: k_p (θ_set − θ) = m g L sin θ, solved by fixed-point iteration.
    let (m, g, l, kp, theta_set) = (1.0, 9.81, 1.0, 200.0, 0.5_f64);
    let mut theta = theta_set;
    for _ in 0..50 {
        theta = theta_set - m * g * l * theta.sin() / kp;
    }
    let angle = closure.column("pivot_angle").unwrap();
    let last = *angle.last().unwrap();
    assert!((last - theta).abs() < 1e-6, "settled at {last}, static equilibrium {theta}");
    assert!((theta_set - theta - 0.02254).abs() < 1e-5, "offset {}", theta_set - theta);
}

#[test]
fn a_driver_motion_as_a_closure_runs_the_trajectory_of_the_expression_driver() {
    let loaded = load_model(&model_file("slider_crank.toml")).unwrap();
    let settings = settings(&loaded, 1.0, 1e-7);
    let expression = run((*loaded.model).clone(), settings);
    let mut model = (*loaded.model).clone();
    let omega = 2.0 * std::f64::consts::PI;
    model.set_driver_motion("crank_motion", UserMotion::new("crank", Arc::new(move |t| Ok([omega * t, omega, 0.0])))).unwrap();
    let closure = run(model, settings);
    let difference = largest_difference(&expression, &closure);
    assert!(difference < 1e-9, "largest difference {difference:e}");
}

#[test]
fn a_failing_law_stops_the_run_naming_itself_and_the_time_with_the_rows_before() {
    let loaded = load_model(&model_file("pd_pendulum.toml")).unwrap();
    let mut model = (*loaded.model).clone();
    let measures = model.measure_ids(&["pivot_angle"]).unwrap();
    let law = UserFunction::new("brake", measures, Arc::new(|t, m: &[f64]| if t < 0.5 { Ok(-200.0 * (m[0] - 0.5)) } else { Err("no brake".into()) }));
    model.set_force_law("controller", None, law.unwrap()).unwrap();
    let model = Arc::new(model);
    let mut table = OutputTable::new(&model);
    let mut simulation = Simulation::new(Arc::clone(&model), settings(&loaded, 3.0, 1e-8)).unwrap();
    let failure = simulation.run(&mut table, &|| None).unwrap_err();
    let SimulationFailure::UserLaw { law, t, message } = &failure else { panic!("{failure}") };
    assert_eq!((law.as_str(), message.as_str()), ("brake", "no brake"));
    assert!((0.5..0.6).contains(t), "failed at {t}");
    assert!(failure.to_string().starts_with("at t = 0.5"), "{failure}");
    let times = table.column("t").unwrap();
    assert!(times.len() >= 50 && *times.last().unwrap() < 0.5, "{} rows to {:?}", times.len(), times.last());
    // A new simulation of the same model starts afresh.
    let mut again = Simulation::new(Arc::clone(&model), settings(&loaded, 0.2, 1e-8)).unwrap();
    again.run(&mut OutputTable::new(&model), &|| None).unwrap();
}

#[test]
fn a_checkpoint_names_its_laws_and_resumes_only_with_them() {
    let loaded = load_model(&model_file("pd_pendulum.toml")).unwrap();
    let settings = settings(&loaded, 1.0, 1e-8);
    let mut model = (*loaded.model).clone();
    model.set_force_law("controller", None, pd_law(&model)).unwrap();
    let model = Arc::new(model);
    let mut simulation = Simulation::new(Arc::clone(&model), settings).unwrap();
    simulation.advance_to(0.5, &mut OutputTable::new(&model)).unwrap();
    let checkpoint = simulation.checkpoint().unwrap();
    assert_eq!(checkpoint.user_laws, ["pd"]);
    let Err(error) = Simulation::resume(Arc::clone(&loaded.model), settings, &checkpoint) else { panic!("resumed without the law") };
    assert!(error.to_string().contains("laws given as code [pd], the model given has []"), "{error}");
    assert!(Simulation::resume(model, settings, &checkpoint).is_ok());
}

/// The pendulum of `models/pendulum.toml` started with angular velocity `omega` (rad/s) about z.
fn spinning_pendulum(omega: f64) -> LoadedModel {
    let text = std::fs::read_to_string(model_file("pendulum.toml")).unwrap();
    let given = "angular_velocity = [0.0, 0.0, 0.0]";
    assert!(text.contains(given));
    parse_model(&text.replace(given, &format!("angular_velocity = [0.0, 0.0, {omega:?}]")), "pendulum.toml").unwrap()
}

#[test]
fn velocities_set_at_the_start_run_the_trajectory_of_a_run_started_with_them() {
    let fresh = spinning_pendulum(2.0);
    let settings = settings(&fresh, 2.0, 1e-9);
    let mut start = Simulation::new(Arc::clone(&fresh.model), settings).unwrap();
    let v0 = start.velocities().to_vec();
    let expected = {
        let mut table = OutputTable::new(&fresh.model);
        start.run(&mut table, &|| None).unwrap();
        table
    };
    let at_rest = load_model(&model_file("pendulum.toml")).unwrap();
    let mut simulation = Simulation::new(Arc::clone(&at_rest.model), settings).unwrap();
    let projection = simulation.set_state(None, Some(&v0)).unwrap();
    assert!(projection.velocity_change < 1e-12 && projection.velocity_residual < 1e-12, "{projection:?}");
    let mut table = OutputTable::new(&at_rest.model);
    simulation.run(&mut table, &|| None).unwrap();
    let difference = largest_difference(&expected, &table);
    assert!(difference < 1e-9, "largest difference {difference:e}");
}

#[test]
fn the_motion_after_a_state_set_mid_run_is_that_of_a_run_started_there() {
    // The pendulum is autonomous: set back to its initial state at t_s, it repeats its motion shifted by t_s.
    let loaded = load_model(&model_file("pendulum.toml")).unwrap();
    let span = 1.5;
    let mut reference = Simulation::new(Arc::clone(&loaded.model), settings(&loaded, span, 1e-10)).unwrap();
    let (q0, v0) = (reference.positions().to_vec(), reference.velocities().to_vec());
    reference.run(&mut OutputTable::new(&loaded.model), &|| None).unwrap();
    let mut simulation = Simulation::new(Arc::clone(&loaded.model), settings(&loaded, 10.0, 1e-10)).unwrap();
    let mut table = OutputTable::new(&loaded.model);
    simulation.advance_to(0.73, &mut table).unwrap();
    let (t_s, steps_before) = (simulation.time(), simulation.stats().steps);
    let projection = simulation.set_state(Some(&q0), Some(&v0)).unwrap();
    assert_eq!(projection.assembly_iterations, 0, "{projection:?}");
    let mut rest = Simulation::resume(Arc::clone(&loaded.model), settings(&loaded, t_s + span, 1e-10), &simulation.checkpoint().unwrap()).unwrap();
    rest.run(&mut table, &|| None).unwrap();
    assert!(rest.stats().steps > steps_before, "the counters go on");
    let largest = rest.positions().iter().zip(reference.positions()).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(largest < 1e-7, "positions differ by {largest:e}");
    // The energy the change of state added is kept out of the balance.
    let report = rest.report();
    let balance = report.energy_final - report.energy_initial - report.nonconservative_work;
    assert!(balance.abs() < 1e-6, "balance error {balance:e} (initial {}, final {})", report.energy_initial, report.energy_final);
}

#[test]
fn positions_off_the_constraints_are_projected_and_wrong_lengths_refused() {
    let loaded = load_model(&model_file("pendulum.toml")).unwrap();
    let mut simulation = Simulation::new(Arc::clone(&loaded.model), settings(&loaded, 1.0, 1e-8)).unwrap();
    let mut q = simulation.positions().to_vec();
    q[0] += 0.1; // the pivot moved off the ground marker
    let projection = simulation.set_state(Some(&q), None).unwrap();
    assert!(projection.assembly_iterations > 0 && projection.position_residual < 1e-9, "{projection:?}");
    assert!((projection.position_change - 0.1).abs() < 1e-3, "{projection:?}");
    assert!(simulation.positions()[0].abs() < 1e-9, "back on the pivot: {:?}", simulation.positions());
    let error = simulation.set_state(Some(&q[..5]), None).unwrap_err();
    assert!(error.to_string().starts_with("the positions must have 7 entries"), "{error}");
    let error = simulation.set_state(None, Some(&[f64::NAN; 6])).unwrap_err();
    assert!(error.to_string().contains("the velocities must be finite, entry 0 is NaN"), "{error}");
    let mut table = OutputTable::new(&loaded.model);
    simulation.run(&mut table, &|| None).unwrap();
    assert_eq!(table.len(), 101);
}
