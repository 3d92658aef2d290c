//! `flexmb bench`: performance cases, reported as cost per step, per Newton iteration and per
//! simulated second, with the counts behind them (steps, rejections by cause, Newton iterations,
//! Jacobians, factorizations).
//!
//! Cases, in groups (`--case GROUP` or one case by name):
//! - `peer`: the five peer cases of models/peer, each with every integrator at the peer's accuracy
//!   ([`peer::PEER_ACCURACY`]);
//! - `chain`: the peer's chain of n = 4, 8, …, 1024 rods for 0.1 s ([`chain`]);
//! - `pendulums`: 1,000 independent spherical pendulums, check plus a 0.01 s run, timed whole
//!   ([`independent_pendulums`]);
//! - `flexible`: the peer's flexible pendulum, and the shipped flexible pendulum for 2 s with 4 and 10
//!   modes and made rigid ([`pendulums`]);
//! - `applications`: the shipped slider-crank for 10 s, a spatial chain of 20 bodies on spherical
//!   joints falling under gravity for 5 s, the seed's door (4N5S) and wiper for 2 s with their model
//!   files' settings ([`applications`]);
//! - `plate-modes`: the lowest 20 modes of a plate of about 50,000 dofs ([`plate_modes`]);
//! - `solid-reduction`: a solid of about 220,000 dofs reduced to 20 fixed-interface modes and the
//!   constraint modes of two interface nodes ([`solid_reduction`]).
//!
//! Each case runs `repeat` times; the fastest run is reported (the others measure the machine's
//! noise, not the code). `--json FILE` writes every measurement, so that runs can be compared.

pub mod applications;
pub mod chain;
pub mod independent_pendulums;
pub mod integrator;
pub mod measurement;
pub mod peer;
pub mod pendulums;
pub mod plate_modes;
pub mod shipped_models;
pub mod solid_reduction;

use std::path::PathBuf;

use flexmb::analysis::{AssemblySettings, SimulationSettings};
use flexmb::body::{InitialState, Marker, RigidBody};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, ModelBuilder, ModelError};
use flexmb::Model;

use flexmb_files::model_file::parse_model;
use flexmb_files::SimulationDefaults;

pub use integrator::BenchIntegrator;
use measurement::{measure_simulation, CaseName, Measurement};
use peer::PeerCase;

/// A benchmark case, or a group of cases.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchCase {
    /// Group: the five peer cases, each with every integrator at the peer's accuracy.
    Peer,
    /// Group: the peer's chain with 4, 8, …, 1024 rods for 0.1 s.
    Chain,
    /// Group: 1,000 independent spherical pendulums, check plus a 0.01 s run.
    Pendulums,
    /// Group: the peer's flexible pendulum and the shipped flexible pendulum (4 and 10 modes, rigid).
    Flexible,
    /// Group: slider-crank, chain20, door4n5s, wiper.
    Applications,
    /// models/peer/rigid_pendulum_3d.toml, 5 s.
    #[value(name = "peer-rigid-pendulum-3d")]
    PeerRigidPendulum3d,
    /// models/peer/heavy_top.toml, 2 s.
    PeerHeavyTop,
    /// models/peer/chain_n4.toml, 5 s.
    #[value(name = "peer-chain-n4")]
    PeerChainN4,
    /// models/peer/slider_crank_3d.toml, 5 s.
    #[value(name = "peer-slider-crank-3d")]
    PeerSliderCrank3d,
    /// models/peer/flexible_pendulum.toml, 1 s.
    PeerFlexiblePendulum,
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
    /// A 220,000-dof solid reduced to 20N12C (Craig–Bampton with two interface nodes).
    SolidReduction,
}

impl BenchCase {
    /// The cases a name stands for: a group's members, or the case itself.
    fn members(self) -> Vec<Job> {
        use BenchCase as C;
        match self {
            C::Peer => PeerCase::ALL.iter().map(|&c| Job::Peer(c)).collect(),
            C::Chain => chain::CHAIN_LINKS.iter().map(|&n| Job::Chain(n)).collect(),
            C::Pendulums => vec![Job::Pendulums],
            C::Flexible => [C::PeerFlexiblePendulum, C::FlexiblePendulum, C::FlexiblePendulum10n, C::RigidPendulum]
                .iter()
                .flat_map(|c| c.members())
                .collect(),
            C::Applications => vec![Job::Shipped(C::SliderCrank), Job::Shipped(C::Chain20), Job::Shipped(C::Door4n5s), Job::Shipped(C::Wiper)],
            C::PeerRigidPendulum3d => vec![Job::Peer(PeerCase::RigidPendulum3d)],
            C::PeerHeavyTop => vec![Job::Peer(PeerCase::HeavyTop)],
            C::PeerChainN4 => vec![Job::Peer(PeerCase::ChainN4)],
            C::PeerSliderCrank3d => vec![Job::Peer(PeerCase::SliderCrank3d)],
            C::PeerFlexiblePendulum => vec![Job::Peer(PeerCase::FlexiblePendulum)],
            C::PlateModes => vec![Job::PlateModes],
            C::SolidReduction => vec![Job::SolidReduction],
            other => vec![Job::Shipped(other)],
        }
    }

    /// What `flexmb bench` runs without `--case`: every group, then the plate's modes.
    pub const EVERYTHING: [BenchCase; 6] =
        [BenchCase::Peer, BenchCase::Chain, BenchCase::Pendulums, BenchCase::Flexible, BenchCase::Applications, BenchCase::PlateModes];
}

/// One case to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Job {
    Peer(PeerCase),
    Chain(usize),
    Pendulums,
    /// One of the cases on the shipped and seed models with their own settings.
    Shipped(BenchCase),
    PlateModes,
    SolidReduction,
}

/// What `flexmb bench` is asked to run.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchOptions {
    /// Cases and groups; empty: [`BenchCase::EVERYTHING`].
    pub cases: Vec<BenchCase>,
    /// Integrators; empty: every integrator for the peer cases and the chains, the BDF for the rest
    /// (the shipped cases with their model files' settings).
    pub integrators: Vec<BenchIntegrator>,
    /// Runs per case; the fastest is reported.
    pub repeat: usize,
    /// Where to write every measurement as JSON.
    pub json: Option<PathBuf>,
    /// The longest chain of the `chain` group (rods); `None`: all of them, up to 1024.
    pub max_links: Option<usize>,
    /// The `chain` group as the one chain of this many rods; `None`: 4 to 1024 doubling.
    pub links: Option<usize>,
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

/// The settings of a shipped case: its end time, output every 0.01 s, the model file's default
/// tolerances and the BDF for the model.
fn default_settings(model: &Model, t_end: f64) -> SimulationSettings {
    let d = SimulationDefaults { t_end, output_step: 0.01, ..SimulationDefaults::default() };
    d.settings(model, AssemblySettings::default())
}

/// A shipped case's name, model and settings with the BDF.
fn shipped_case(case: BenchCase) -> Result<(&'static str, Model, SimulationSettings), String> {
    let bdf = |model: Model, t_end: f64| {
        let settings = default_settings(&model, t_end);
        (model, settings)
    };
    let (name, (model, settings)) = match case {
        BenchCase::SliderCrank => {
            let loaded = parse_model(SLIDER_CRANK, "models/slider_crank.toml").map_err(|e| e.to_string())?;
            ("slider-crank", bdf(std::sync::Arc::unwrap_or_clone(loaded.model), 10.0))
        }
        BenchCase::Chain20 => ("chain-20", bdf(spherical_chain_model(20).map_err(|e| e.to_string())?, 5.0)),
        BenchCase::RigidPendulum => ("rigid-pend.", bdf(pendulums::rigid_pendulum()?, 2.0)),
        BenchCase::FlexiblePendulum => ("flex-pend. 4N", bdf(pendulums::flexible_pendulum(None)?, 2.0)),
        BenchCase::FlexiblePendulum10n => ("flex-pend. 10N", bdf(pendulums::flexible_pendulum(Some("10N"))?, 2.0)),
        BenchCase::Door4n5s => ("door 4N5S", applications::door_4n5s()?),
        BenchCase::Wiper => ("wiper", applications::wiper()?),
        other => return Err(format!("{other:?} is not a case on a shipped model")),
    };
    Ok((name, model, settings))
}

/// Runs one job with each of `integrators` (empty: the job's own), printing a row per measurement.
fn run_job(job: Job, integrators: &[BenchIntegrator], repeat: usize, out: &mut Vec<Measurement>) -> Result<(), String> {
    let chosen = |default: &[BenchIntegrator]| if integrators.is_empty() { default.to_vec() } else { integrators.to_vec() };
    let mut record = |m: Measurement| {
        println!("{}", m.row());
        out.push(m);
    };
    match job {
        Job::Peer(case) => {
            let (model, defaults) = shipped_models::load_shipped(case.model_file(), &crate::limits::load_options())?;
            for integrator in chosen(&BenchIntegrator::ALL) {
                let settings = peer::peer_settings(case, integrator, &model, &defaults);
                let name = CaseName { group: "peer", case: case.name().to_string(), integrator: integrator.name() };
                record(measure_simulation(name, &model, &settings, repeat));
            }
        }
        Job::Chain(n) => {
            let model = chain::peer_chain(n).map_err(|e| e.to_string())?;
            for integrator in chosen(&BenchIntegrator::ALL) {
                let tolerance = chain::chain_tolerance(integrator);
                let d = SimulationDefaults { t_end: chain::CHAIN_SPAN, rtol: tolerance, atol: tolerance, method: integrator.named_method(), ..SimulationDefaults::default() };
                let settings = d.settings(&model, d.assembly());
                let name = CaseName { group: "chain", case: format!("chain-{n}"), integrator: integrator.name() };
                record(measure_simulation(name, &model, &settings, repeat));
            }
        }
        Job::Pendulums => {
            for integrator in chosen(&[BenchIntegrator::Bdf]) {
                record(independent_pendulums::measure_pendulums(independent_pendulums::PENDULUMS, integrator, repeat)?);
            }
        }
        Job::Shipped(case) => {
            let (name, model, settings) = shipped_case(case)?;
            let group = if matches!(case, BenchCase::SliderCrank | BenchCase::Chain20 | BenchCase::Door4n5s | BenchCase::Wiper) { "applications" } else { "flexible" };
            // The case's own settings are the BDF's (with its model file's order limit, if any).
            let with = |i: BenchIntegrator| match i {
                BenchIntegrator::Bdf => settings,
                other => SimulationSettings { method: other.method(&SimulationDefaults::default(), &model), ..settings },
            };
            let runs: Vec<(&'static str, SimulationSettings)> = if integrators.is_empty() {
                vec![("bdf", settings)]
            } else {
                integrators.iter().map(|&i| (i.name(), with(i))).collect()
            };
            for (integrator, settings) in runs {
                let m = measure_simulation(CaseName { group, case: name.to_string(), integrator }, &model, &settings, repeat);
                if case == BenchCase::Door4n5s && m.failure.is_none() {
                    println!(
                        "  door 4N5S: the seed reports {} s of CPU (Prime 750) for the same 2 s: {:.0} times this run",
                        applications::SEED_DOOR_4N5S_CPU,
                        applications::SEED_DOOR_4N5S_CPU / m.whole.best()
                    );
                }
                record(m);
            }
        }
        Job::PlateModes => plate_modes::run(repeat)?,
        Job::SolidReduction => solid_reduction::run(repeat)?,
    }
    Ok(())
}

/// Runs the chosen cases, prints a table row per case and integrator, and writes the JSON file if asked.
pub fn run_benchmarks(options: &BenchOptions) -> Result<(), String> {
    let asked: &[BenchCase] = if options.cases.is_empty() { &BenchCase::EVERYTHING } else { &options.cases };
    let mut jobs: Vec<Job> = Vec::new();
    for job in asked.iter().flat_map(|c| c.members()) {
        let job = match (job, options.links) {
            (Job::Chain(_), Some(n)) => Job::Chain(n),
            _ => job,
        };
        let too_long = matches!(job, Job::Chain(n) if options.max_links.is_some_and(|max| n > max));
        if !jobs.contains(&job) && !too_long {
            jobs.push(job);
        }
    }
    let repeat = options.repeat.max(1);
    let load_before = load_average();
    println!("{}", Measurement::header());
    let mut measured = Vec::new();
    for job in jobs {
        if matches!(job, Job::PlateModes | Job::SolidReduction) {
            println!();
        }
        run_job(job, &options.integrators, repeat, &mut measured)?;
    }
    let load_after = load_average();
    println!(
        "(fastest of {repeat} runs each; rej.N, rej.E: steps rejected for Newton failures and by the error test; \
         us/step, us/Newton, s/sim.s: the integration's time per accepted step, per Newton iteration and per \
         simulated second; setup s: the initial-condition analyses before it, for the pendulums also the check; \
         times are {})",
        if measurement::thread_cpu_time().is_some() { "the thread's CPU time (wall times in the JSON file)" } else { "wall times" }
    );
    if let (Some(a), Some(b)) = (&load_before, &load_after) {
        println!("load average (1, 5, 15 min): {a:?} before, {b:?} after");
    }
    if let Some(path) = &options.json {
        let document = serde_json::json!({
            "flexmb_version": env!("CARGO_PKG_VERSION"),
            "unix_time_s": std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs()),
            "repeat": repeat,
            "load_average_before": load_before,
            "load_average_after": load_after,
            "measurements": measured.iter().map(Measurement::to_json).collect::<Vec<_>>(),
        });
        let text = serde_json::to_string_pretty(&document).map_err(|e| e.to_string())?;
        std::fs::write(path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
        println!("measurements written to {}", path.display());
    }
    Ok(())
}

/// The machine's load average over 1, 5 and 15 minutes (Linux), if it can be read.
fn load_average() -> Option<[f64; 3]> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    let mut fields = text.split_whitespace().map(|f| f.parse::<f64>().ok());
    Some([fields.next()??, fields.next()??, fields.next()??])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The groups stand for their members: five peer cases, nine chains, one pendulum case, four
    /// flexible cases; a case named twice runs once.
    #[test]
    fn groups_expand_to_their_cases() {
        assert_eq!(BenchCase::Peer.members().len(), 5);
        assert_eq!(BenchCase::Chain.members(), chain::CHAIN_LINKS.iter().map(|&n| Job::Chain(n)).collect::<Vec<_>>());
        assert_eq!(BenchCase::Pendulums.members(), vec![Job::Pendulums]);
        let flexible = BenchCase::Flexible.members();
        assert_eq!(flexible.len(), 4);
        assert!(flexible.contains(&Job::Peer(PeerCase::FlexiblePendulum)));
        assert!(BenchCase::Applications.members().iter().all(|j| matches!(j, Job::Shipped(_))));
        assert_eq!(BenchCase::PeerHeavyTop.members(), vec![Job::Peer(PeerCase::HeavyTop)]);
    }
}
