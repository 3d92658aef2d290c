//! The five peer cases (models/peer, measured side by side with Exudyn 1.13.6's generalized-α at a
//! converged fixed step), each with every integrator at the peer's accuracy: the tolerance
//! (rtol = atol) that [`PEER_ACCURACY`] gives per case and integrator.

use flexmb::analysis::SimulationSettings;
use flexmb::Model;
use flexmb_files::SimulationDefaults;

use super::integrator::BenchIntegrator;

/// One of the five peer cases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PeerCase {
    /// models/peer/rigid_pendulum_3d.toml: a body on a revolute joint, 5 s (reference values from ADAMS).
    RigidPendulum3d,
    /// models/peer/heavy_top.toml: the heavy symmetric top on a spherical joint, 2 s.
    HeavyTop,
    /// models/peer/chain_n4.toml: four rods on spherical joints, 5 s.
    ChainN4,
    /// models/peer/slider_crank_3d.toml: the IFToMM spatial slider-crank (consistent initial
    /// velocities), 5 s.
    SliderCrank3d,
    /// models/peer/flexible_pendulum.toml: a steel beam pendulum with eight modes of the beam pinned at its
    /// hinge (those above 200 Hz damped, `high_mode_damping`), 1 s.
    FlexiblePendulum,
}

impl PeerCase {
    /// The five cases in the peer's order.
    pub const ALL: [PeerCase; 5] =
        [PeerCase::RigidPendulum3d, PeerCase::HeavyTop, PeerCase::ChainN4, PeerCase::SliderCrank3d, PeerCase::FlexiblePendulum];

    /// The case's name in the benchmark's table.
    pub fn name(self) -> &'static str {
        match self {
            PeerCase::RigidPendulum3d => "rigid-pendulum-3d",
            PeerCase::HeavyTop => "heavy-top",
            PeerCase::ChainN4 => "chain-n4",
            PeerCase::SliderCrank3d => "slider-crank-3d",
            PeerCase::FlexiblePendulum => "flexible-pendulum",
        }
    }

    /// The shipped model file, relative to `models/`.
    pub fn model_file(self) -> &'static str {
        match self {
            PeerCase::RigidPendulum3d => "peer/rigid_pendulum_3d.toml",
            PeerCase::HeavyTop => "peer/heavy_top.toml",
            PeerCase::ChainN4 => "peer/chain_n4.toml",
            PeerCase::SliderCrank3d => "peer/slider_crank_3d.toml",
            PeerCase::FlexiblePendulum => "peer/flexible_pendulum.toml",
        }
    }

    /// The tolerance (rtol = atol) at which `integrator` reaches the peer's accuracy on this case (the
    /// Adams method's for partitioning, not measured on its own).
    pub fn tolerance(self, integrator: BenchIntegrator) -> f64 {
        PEER_ACCURACY
            .iter()
            .find(|a| a.case == self && a.integrator == integrator.tolerances_of())
            .map_or(f64::NAN, |a| a.tolerance)
    }
}

/// The tolerance at which one integrator reaches the peer's accuracy on one case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeerAccuracy {
    /// The case.
    pub case: PeerCase,
    /// The integrator.
    pub integrator: BenchIntegrator,
    /// rtol = atol.
    pub tolerance: f64,
}

const fn accuracy(case: PeerCase, integrator: BenchIntegrator, tolerance: f64) -> PeerAccuracy {
    PeerAccuracy { case, integrator, tolerance }
}

/// The peer's accuracy as a tolerance per case and integrator: the loosest of 1e-2, 1e-3, 1e-4, 3e-5,
/// 1e-5, … 1e-10 (half decades), 1e-11, 1e-12 whose deviation from a tight reference (BDF at
/// rtol = atol = 1e-11) is at most the converged peer result's own deviation from it. Measured
/// with the error per unit step over the run, the default since 26 November 2026 (the flexible
/// pendulum's model file holds each step to the whole tolerance, `tolerance_span = "step"`, which
/// reaches the peer's accuracy in 15,577 BDF steps against 25,071 at 1e-2 over the run); the peer
/// harness's `settings.txt`, docs/performance.md says how. Steps at the peer's accuracy, before (error
/// per step) and now: rigid pendulum BDF 290 → 334, Adams 131 → 160, gen-α 7,686 → 11,841; heavy top
/// 3,927 → 4,028, 685 → 1,066, 114,877 → 117,919; chain 6,496 → 4,414, 1,688 → 1,547, 377,024 → 377,121;
/// slider-crank 6,748 → 7,413, 1,594 → 1,620, 119,984 → 146,305. When the integrators' error control
/// changes, these must be measured again. (Generalized-α's predictor and Newton tolerance changed since:
/// its steps and its error at 1e-3 … 1e-6 are within 5 % of before, docs/accuracy.md, so its tolerances
/// stand. Its share's floor fell from `1e-12 / rtol` to `1e-13 / rtol` since: the chain at 1e-7 takes
/// 702,846 steps against 377,121, 6.0e-6 from the BDF at 1e-11 and 1.2e-5 from the converged peer result;
/// 3e-7 gives 469,695 steps and 1.79e-5 from the BDF's, too close to the peer's 1.8e-5 to hold.)
pub const PEER_ACCURACY: [PeerAccuracy; 15] = {
    use BenchIntegrator::{Adams, Bdf, GenAlpha};
    use PeerCase::{ChainN4, FlexiblePendulum, HeavyTop, RigidPendulum3d, SliderCrank3d};
    [
        accuracy(RigidPendulum3d, Bdf, 3e-5),
        accuracy(RigidPendulum3d, Adams, 3e-5),
        accuracy(RigidPendulum3d, GenAlpha, 3e-6),
        accuracy(HeavyTop, Bdf, 1e-4),
        accuracy(HeavyTop, Adams, 1e-4),
        accuracy(HeavyTop, GenAlpha, 1e-4),
        accuracy(ChainN4, Bdf, 1e-5),
        accuracy(ChainN4, Adams, 1e-5),
        accuracy(ChainN4, GenAlpha, 1e-7),
        accuracy(SliderCrank3d, Bdf, 1e-6),
        accuracy(SliderCrank3d, Adams, 1e-5),
        accuracy(SliderCrank3d, GenAlpha, 3e-6),
        // The beam's pinned-free modes (fe/beam_20x20_hinged.toml), those above 200 Hz damped (the model
        // file's `high_mode_damping`), each step the whole tolerance, against the undamped beam at 1e-9:
        // BDF 1e-6 (1,680 steps, 6.5e-6; 3e-6 gives 1.4e-5), Adams 1e-5 (3,756 steps, 4.0e-6; 3e-5 gives
        // 7.9e-6, too close to 8e-6 to hold), generalized-α 3e-8 (8,272 steps, 6.1e-6).
        accuracy(FlexiblePendulum, Bdf, 1e-6),
        accuracy(FlexiblePendulum, Adams, 1e-5),
        accuracy(FlexiblePendulum, GenAlpha, 3e-8),
    ]
};

/// The settings of `case` with `integrator` at the peer's accuracy: the model file's end time and
/// output step, as `flexmb run FILE --integrator NAME --rtol TOL --atol TOL` runs it.
pub fn peer_settings(case: PeerCase, integrator: BenchIntegrator, model: &Model, defaults: &SimulationDefaults) -> SimulationSettings {
    let tolerance = case.tolerance(integrator);
    let d = SimulationDefaults { rtol: tolerance, atol: tolerance, method: integrator.named_method(), ..*defaults };
    d.settings(model, d.assembly())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The accuracy table holds each case with each integrator exactly once, at a tolerance from the
    /// measured grid (1e-12 to 1e-2).
    #[test]
    fn every_case_has_one_tolerance_per_integrator() {
        for case in PeerCase::ALL {
            for integrator in BenchIntegrator::ALL {
                let n = PEER_ACCURACY.iter().filter(|a| a.case == case && a.integrator == integrator).count();
                assert_eq!(n, 1, "{case:?} {integrator:?}");
                let tol = case.tolerance(integrator);
                assert!((1e-12..=1e-2).contains(&tol), "{case:?} {integrator:?}: {tol}");
            }
        }
    }

    /// The settings carry the table's tolerance and the model file's end time.
    #[test]
    fn the_settings_are_the_tables_and_the_model_files() {
        let (model, defaults) = crate::bench::shipped_models::load_shipped(PeerCase::HeavyTop.model_file(), &crate::limits::load_options()).unwrap();
        let s = peer_settings(PeerCase::HeavyTop, BenchIntegrator::Adams, &model, &defaults);
        assert_eq!((s.tolerances.rtol, s.tolerances.atol, s.t_end), (1e-4, 1e-4, 2.0));
        assert_eq!(s.tolerances.span, flexmb::integrate::ToleranceSpan::Run, "the model file's tolerance_span");
        assert!(matches!(s.method, flexmb::integrate::Method::Adams(_)));
    }
}
