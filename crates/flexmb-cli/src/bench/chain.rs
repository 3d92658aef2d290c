//! The chain of the peer case (models/peer/chain_n4.toml) with n = 4, 8, …, 1024 rods, built in code:
//! how the cost per step and per Newton iteration grows with the model. Long chains run for a short
//! span ([`CHAIN_SPAN`]) so the benchmark stays short; the cost per step is what it measures.

use flexmb::body::{InitialState, Marker, RigidBody};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, ModelBuilder, ModelError};
use flexmb::Model;

use super::integrator::BenchIntegrator;

/// The numbers of rods: 4 to 1024, doubling.
pub const CHAIN_LINKS: [usize; 9] = [4, 8, 16, 32, 64, 128, 256, 512, 1024];

/// Simulated time of every chain (s): the chain falls from the horizontal, at rest, for this span.
pub const CHAIN_SPAN: f64 = 0.1;

/// The tolerance (rtol = atol) per integrator: the BDF's and the Adams method's reached the peer's
/// accuracy on the chain of four rods over 5 s with the error per step (`PEER_ACCURACY` had them so
/// until the error per unit step over the run became the default); the generalized-α method's
/// is looser than its peer accuracy (1e-12), which would take some 75,000 steps per simulated second.
pub const CHAIN_TOLERANCE: [(BenchIntegrator, f64); 3] =
    [(BenchIntegrator::Bdf, 3e-10), (BenchIntegrator::Adams, 3e-9), (BenchIntegrator::GenAlpha, 1e-8)];

/// The chain's tolerance for `integrator` ([`CHAIN_TOLERANCE`]; partitioning at the Adams method's).
pub fn chain_tolerance(integrator: BenchIntegrator) -> f64 {
    CHAIN_TOLERANCE.iter().find(|(i, _)| *i == integrator.tolerances_of()).map_or(f64::NAN, |(_, tol)| *tol)
}

/// Rod length (m).
const ROD_LENGTH: f64 = 0.5;
/// Rod mass (kg).
const ROD_MASS: f64 = 1.0;
/// Axial moment of inertia of a rod (kg m²): a thin rod has none, but the mass matrix must be
/// regular; every joint force acts on the rod's axis, so it does not enter the motion.
const ROD_AXIAL_INERTIA: f64 = 1e-4;

/// The peer's chain of `n` rods (1 kg, 0.5 m, body frame at the rod's centre, x along the rod),
/// straight along +x and horizontal at rest, rod 0 on a spherical joint to ground at the origin, each
/// rod's end on a spherical joint to the next rod's start; gravity 9.81 along −z. For n = 4 it is
/// models/peer/chain_n4.toml without its outputs.
pub fn peer_chain(n: usize) -> Result<Model, ModelError> {
    let half = ROD_LENGTH / 2.0;
    let transverse = ROD_MASS * ROD_LENGTH * ROD_LENGTH / 12.0;
    let mut b = ModelBuilder::new(format!("chain_n{n}")).gravity(Vec3::new(0.0, 0.0, -9.81));
    let mut ends = Vec::with_capacity(n);
    for k in 0..n {
        let rod = b.add_body(RigidBody {
            name: format!("rod{k}"),
            mass: ROD_MASS,
            center_of_mass: Vec3::zeros(),
            inertia: Mat3::from_diagonal(&Vec3::new(ROD_AXIAL_INERTIA, transverse, transverse)),
            initial: InitialState {
                position: Vec3::new((k as f64 + 0.5) * ROD_LENGTH, 0.0, 0.0),
                orientation: EulerParameters::identity(),
                velocity: Some(Vec3::zeros()),
                angular_velocity: Some(Vec3::zeros()),
            },
        })?;
        let marker = |name: String, x: f64| Marker { name, body: BodyRef::Body(rod), origin: Vec3::new(x, 0.0, 0.0), axes: Mat3::identity() };
        let start = b.add_marker(marker(format!("rod{k}_start"), -half))?;
        let end = b.add_marker(marker(format!("rod{k}_end"), half))?;
        ends.push((start, end));
    }
    let anchor = b.add_marker(Marker { name: "anchor".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() })?;
    let mut previous = anchor;
    for (k, &(start, end)) in ends.iter().enumerate() {
        b.add_joint(Joint { name: format!("s{k}"), kind: JointKind::Spherical, marker_i: previous, marker_j: start })?;
        previous = end;
    }
    b.build()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::shipped_models::load_shipped;
    use flexmb::analysis::simulate;
    use flexmb_files::SimulationDefaults;

    /// The chain built in code is the shipped peer model: the same coordinates and constraints, and
    /// a run of 0.2 s takes the same steps to the same energy.
    #[test]
    fn the_chain_of_four_is_the_shipped_peer_chain() {
        let (shipped, _) = load_shipped("peer/chain_n4.toml", &crate::limits::load_options()).unwrap();
        let built = peer_chain(4).unwrap();
        let (a, b) = (shipped.layout(), built.layout());
        assert_eq!((a.nq, a.nv, a.nc), (b.nq, b.nv, b.nc));
        let d = SimulationDefaults { t_end: 0.2, rtol: 1e-8, atol: 1e-8, ..SimulationDefaults::default() };
        let run = |m: &Model| simulate(m, &d.settings(m, d.assembly()), &mut |_| {}).unwrap();
        let (ra, rb) = (run(&shipped), run(&built));
        assert_eq!(ra.stats.steps, rb.stats.steps);
        assert_eq!(ra.stats.newton_iterations, rb.stats.newton_iterations);
        // Falling from the horizontal at rest: the energy is conserved to the tolerance.
        assert!((ra.energy_final - rb.energy_final).abs() <= 1e-12 * ra.energy_initial.abs().max(1.0));
        assert!((rb.energy_final - rb.energy_initial).abs() <= 1e-5 * (4.0 * 9.81 * 1.0));
    }

    /// Every chain has n rods: 7n positions, 6n velocities, three constraint rows per spherical
    /// joint, so 3n degrees of freedom; the sizes double from 4 to 1024.
    #[test]
    fn chains_double_from_4_to_1024_rods() {
        assert_eq!(CHAIN_LINKS.first(), Some(&4));
        assert_eq!(CHAIN_LINKS.last(), Some(&1024));
        assert!(CHAIN_LINKS.windows(2).all(|w| w[1] == 2 * w[0]));
        let m = peer_chain(8).unwrap();
        assert_eq!((m.layout().nq, m.layout().nv, m.layout().nc), (56, 48, 24));
        for integrator in BenchIntegrator::ALL {
            assert!(chain_tolerance(integrator) > 0.0);
        }
    }
}
