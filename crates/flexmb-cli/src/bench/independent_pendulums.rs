//! 1,000 independent spherical pendulums, each a rod on a spherical joint to ground: `check` (the
//! redundancy check, assembly and velocity analysis) plus a 0.01 s run, timed whole. A model of many
//! bodies whose equations do not couple: its cost must grow linearly with the bodies.

use flexmb::analysis::{SimulationError, SimulationSettings};
use flexmb::body::{InitialState, Marker, RigidBody};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, ModelBuilder, ModelError};
use flexmb::Model;
use flexmb_files::SimulationDefaults;

use super::integrator::BenchIntegrator;
use super::measurement::{measure_repeated, timed_simulation, CaseName, Clocks, Elapsed, Measurement, TimedRun};
use crate::check::check_model;

/// The number of pendulums.
pub const PENDULUMS: usize = 1000;

/// Simulated time (s).
pub const PENDULUM_SPAN: f64 = 0.01;

/// Distance between neighbouring pivots (m), more than a rod's length.
const PIVOT_SPACING: f64 = 1.0;

/// `n` pendulums: rod k (1 kg, 0.5 m, centre of mass 0.25 m along its x axis) hangs from a
/// spherical joint at (k, 0, 0), starts horizontal along x and turns about the vertical at
/// 1 + k/n rad/s (a conical motion, different for each); gravity 9.81 along −z.
pub fn independent_pendulums(n: usize) -> Result<Model, ModelError> {
    let mut b = ModelBuilder::new(format!("{n} independent spherical pendulums")).gravity(Vec3::new(0.0, 0.0, -9.81));
    for k in 0..n {
        let pivot = Vec3::new(k as f64 * PIVOT_SPACING, 0.0, 0.0);
        let spin = 1.0 + k as f64 / n as f64;
        let rod = b.add_body(RigidBody {
            name: format!("rod{k}"),
            mass: 1.0,
            center_of_mass: Vec3::new(0.25, 0.0, 0.0),
            inertia: Mat3::from_diagonal(&Vec3::new(1e-4, 0.5 * 0.5 / 12.0, 0.5 * 0.5 / 12.0)),
            initial: InitialState {
                position: pivot,
                orientation: EulerParameters::identity(),
                velocity: Some(Vec3::zeros()),
                angular_velocity: Some(Vec3::new(0.0, 0.0, spin)),
            },
        })?;
        let on_ground = b.add_marker(Marker { name: format!("pivot{k}"), body: BodyRef::Ground, origin: pivot, axes: Mat3::identity() })?;
        let on_rod = b.add_marker(Marker { name: format!("rod{k}_pivot"), body: BodyRef::Body(rod), origin: Vec3::zeros(), axes: Mat3::identity() })?;
        b.add_joint(Joint { name: format!("ball{k}"), kind: JointKind::Spherical, marker_i: on_ground, marker_j: on_rod })?;
    }
    b.build()
}

/// Checks the `n` pendulums as `flexmb check` does and runs them for [`PENDULUM_SPAN`] with
/// `integrator` at the model file's default tolerances, `repeat` times; the whole wall time holds the
/// check and the run (the run repeats the initial-condition analyses, as `flexmb run` does).
pub fn measure_pendulums(n: usize, integrator: BenchIntegrator, repeat: usize) -> Result<Measurement, String> {
    let defaults = SimulationDefaults { t_end: PENDULUM_SPAN, ..SimulationDefaults::default() };
    let model = independent_pendulums(n).map_err(|e| e.to_string())?;
    let settings = SimulationSettings { method: integrator.method(&defaults, &model), ..defaults.settings(&model, defaults.assembly()) };
    let name = CaseName { group: "pendulums", case: format!("pendulums-{n}"), integrator: integrator.name() };
    Ok(measure_repeated(name, &settings, repeat, &mut || {
        let whole = Clocks::start();
        if let Err(e) = check_model(&model, settings.assembly) {
            return TimedRun { outcome: Err(SimulationError { cause: e.into(), report: Box::default() }), whole: whole.elapsed(), integration: Elapsed::default() };
        }
        let mut run = timed_simulation(&model, &settings);
        run.whole = whole.elapsed();
        run
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmb::analysis::simulate;

    /// n pendulums on spherical joints have 3n degrees of freedom and no redundant constraint; the
    /// benchmark's run completes, and a run at rtol = atol = 1e-10 conserves the energy (no damping:
    /// 0.91 J, of which 0.036 J go from potential to kinetic in 0.01 s) to 1e-6 J per pendulum.
    #[test]
    fn pendulums_are_independent_and_conserve_energy() {
        let n = 10;
        let model = independent_pendulums(n).unwrap();
        let check = check_model(&model, Default::default()).unwrap();
        assert_eq!(check.assembly.degrees_of_freedom, 3 * n);
        assert!(check.assembly.redundant.is_empty());
        let m = measure_pendulums(n, BenchIntegrator::Bdf, 1).unwrap();
        assert!(m.failure.is_none(), "{:?}", m.failure);
        assert!(m.stats.steps > 0 && m.stats.newton_iterations >= m.stats.steps);
        let d = SimulationDefaults { t_end: PENDULUM_SPAN, rtol: 1e-10, atol: 1e-10, ..SimulationDefaults::default() };
        let report = simulate(&model, &d.settings(&model, d.assembly()), &mut |_| {}).unwrap();
        assert!((report.energy_final - report.energy_initial).abs() < 1e-6 * n as f64);
    }
}
