//! `flexmb bench`: performance cases, reported as cost per step and per simulated second.
//!
//! Cases: the shipped slider-crank for 10 s, a spatial chain of 20 bodies on spherical joints falling
//! under gravity for 5 s, the shipped flexible pendulum for 2 s with 4 and 10 modes and made rigid
//! ([`pendulums`]), the seed's door (4N5S) and wiper for 2 s with their model files' settings
//! ([`applications`]), and the lowest 20 modes of a plate of about 50,000 dofs ([`plate_modes`]).
//! Each case runs `repeat` times; the fastest run is reported (the others measure the machine's
//! noise, not the code).

pub mod applications;
pub mod pendulums;
pub mod plate_modes;

use std::time::Instant;

use flexmb::analysis::{simulate, AssemblySettings, SimulationReport, SimulationSettings};
use flexmb::body::{InitialState, Marker, RigidBody};
use flexmb::integrate::{BdfConfig, Method};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, ModelBuilder, ModelError};
use flexmb::Model;

use flexmb_files::model_file::parse_model;

/// A benchmark case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchCase {
    /// models/slider_crank.toml for 10 s.
    SliderCrank,
    /// 20 links on spherical joints falling under gravity for 5 s.
    Chain20,
    /// models/flexible_pendulum.toml (4 modes) for 2 s.
    FlexiblePendulum,
    /// The same with 10 modes.
    FlexiblePendulum10n,
    /// The same strip made rigid, for 2 s.
    RigidPendulum,
    /// models/door/door.toml with mode set 4N5S for 2 s (the seed: 7281 s of CPU).
    Door4n5s,
    /// models/wiper/wiper.toml (flexible arms) for 2 s.
    Wiper,
    /// The lowest 20 modes of a 90 × 90 shell plate (about 49,000 dofs).
    PlateModes,
}

const SLIDER_CRANK: &str = include_str!("../../../../models/slider_crank.toml");

/// A chain of `n` slender links (0.1 m, 0.1 kg) on spherical joints, horizontal along x at rest, first
/// link on a spherical joint to ground; gravity −z.
pub fn spherical_chain(n: usize) -> Model {
    spherical_chain_model(n).expect("the chain model is valid")
}

fn spherical_chain_model(n: usize) -> Result<Model, ModelError> {
    let (l, m) = (0.1, 0.1);
    let i_axial = 1e-6;
    let i_transverse = m * l * l / 12.0;
    let mut b = ModelBuilder::new(format!("chain of {n} links")).gravity(Vec3::new(0.0, 0.0, -9.81));
    let mut previous = b.add_marker(Marker { name: "anchor".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() })?;
    for k in 0..n {
        let body = b.add_body(RigidBody {
            name: format!("link{k}"),
            mass: m,
            center_of_mass: Vec3::new(l / 2.0, 0.0, 0.0),
            inertia: Mat3::from_diagonal(&Vec3::new(i_axial, i_transverse, i_transverse)),
            initial: InitialState {
                position: Vec3::new(k as f64 * l, 0.0, 0.0),
                orientation: EulerParameters::identity(),
                velocity: None,
                angular_velocity: None,
            },
        })?;
        let start = b.add_marker(Marker { name: format!("link{k}_start"), body: BodyRef::Body(body), origin: Vec3::zeros(), axes: Mat3::identity() })?;
        b.add_joint(Joint { name: format!("ball{k}"), kind: JointKind::Spherical, marker_i: previous, marker_j: start })?;
        previous = b.add_marker(Marker {
            name: format!("link{k}_end"),
            body: BodyRef::Body(body),
            origin: Vec3::new(l, 0.0, 0.0),
            axes: Mat3::identity(),
        })?;
    }
    b.build()
}

struct CaseResult {
    report: SimulationReport,
    wall: f64,
    t_end: f64,
}

/// The BDF with its defaults for `model`, output every 0.01 s.
fn default_settings(model: &Model, t_end: f64) -> SimulationSettings {
    SimulationSettings {
        t_end,
        output_step: 0.01,
        method: Method::Bdf(BdfConfig::for_model(model)),
        assembly: AssemblySettings::default(),
        ..Default::default()
    }
}

fn run_case(model: &Model, settings: &SimulationSettings, repeat: usize) -> Result<CaseResult, String> {
    let t_end = settings.t_end;
    let mut best: Option<CaseResult> = None;
    for _ in 0..repeat {
        let start = Instant::now();
        let report = simulate(model, settings, &mut |_| {}).map_err(|e| e.to_string())?;
        let wall = start.elapsed().as_secs_f64();
        if best.as_ref().is_none_or(|b| wall < b.wall) {
            best = Some(CaseResult { report, wall, t_end });
        }
    }
    best.ok_or_else(|| "no run".to_string())
}

/// Runs the chosen cases (all when `None`) and prints a table.
pub fn run_benchmarks(case: Option<BenchCase>, repeat: usize) -> Result<(), String> {
    let cases: Vec<BenchCase> = match case {
        Some(BenchCase::PlateModes) => return plate_modes::run(repeat),
        Some(c) => vec![c],
        None => vec![
            BenchCase::SliderCrank,
            BenchCase::Chain20,
            BenchCase::RigidPendulum,
            BenchCase::FlexiblePendulum,
            BenchCase::FlexiblePendulum10n,
            BenchCase::Door4n5s,
            BenchCase::Wiper,
        ],
    };
    println!(
        "{:<15} {:>6} {:>7} {:>9} {:>10} {:>11} {:>12} {:>13}",
        "case", "t_end", "steps", "rms h", "wall [s]", "us/step", "res.ev/step", "wall/sim [-]"
    );
    let mut door_note = None;
    for c in cases {
        let with_defaults = |model: Model, t_end: f64| {
            let settings = default_settings(&model, t_end);
            (model, settings)
        };
        let (name, (model, settings)) = match c {
            BenchCase::SliderCrank => {
                let loaded = parse_model(SLIDER_CRANK, "models/slider_crank.toml").map_err(|e| e.to_string())?;
                ("slider-crank", with_defaults(std::sync::Arc::unwrap_or_clone(loaded.model), 10.0))
            }
            BenchCase::Chain20 => ("chain-20", with_defaults(spherical_chain(20), 5.0)),
            BenchCase::RigidPendulum => ("rigid-pend.", with_defaults(pendulums::rigid_pendulum()?, 2.0)),
            BenchCase::FlexiblePendulum => ("flex-pend. 4N", with_defaults(pendulums::flexible_pendulum(None)?, 2.0)),
            BenchCase::FlexiblePendulum10n => {
                ("flex-pend. 10N", with_defaults(pendulums::flexible_pendulum(Some("10N"))?, 2.0))
            }
            BenchCase::Door4n5s => ("door 4N5S", applications::door_4n5s()?),
            BenchCase::Wiper => ("wiper", applications::wiper()?),
            BenchCase::PlateModes => unreachable!("run on its own above"),
        };
        let r = run_case(&model, &settings, repeat)?;
        let s = &r.report.stats;
        println!(
            "{:<15} {:>6.1} {:>7} {:>9.3e} {:>10.4} {:>11.1} {:>12.1} {:>13.4}",
            name,
            r.t_end,
            s.steps,
            s.rms_step(),
            r.wall,
            r.wall / s.steps as f64 * 1e6,
            s.residual_evaluations as f64 / s.steps as f64,
            r.wall / r.t_end,
        );
        if c == BenchCase::Door4n5s {
            door_note = Some(r.wall);
        }
    }
    println!("(best of {repeat} runs each; wall time includes assembly and the output frames)");
    if let Some(wall) = door_note {
        println!(
            "door 4N5S: the seed reports {} s of CPU (Prime 750) for the same 2 s: {:.0} times this run",
            applications::SEED_DOOR_4N5S_CPU,
            applications::SEED_DOOR_4N5S_CPU / wall
        );
    }
    if case.is_none() {
        println!();
        plate_modes::run(repeat)?;
    }
    Ok(())
}
