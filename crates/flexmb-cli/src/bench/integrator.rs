//! The integrators a benchmark runs, by the names `flexmb run --integrator` takes.

use flexmb::integrate::adams::ConstraintHandling;
use flexmb::integrate::{AdamsConfig, Method};
use flexmb::Model;
use flexmb_files::SimulationDefaults;

/// The generalized-α method's spectral radius at infinity in the benchmarks: `flexmb run`'s default (0.8;
/// the peer's, Exudyn's default, is 0.9).
pub const SPECTRAL_RADIUS: f64 = flexmb::integrate::GeneralizedAlphaConfig::DEFAULT_SPECTRAL_RADIUS;

/// An integration method of the engine, as a benchmark names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum BenchIntegrator {
    /// The BDF (variable order 1–5) with the settings for the model (the default integrator).
    Bdf,
    /// The Adams method (variable order 1–12).
    Adams,
    /// The generalized-α method with `flexmb run`'s default ρ∞ (0.8).
    GenAlpha,
    /// The Adams method with generalized coordinate partitioning (the DADS way, a library option that
    /// `flexmb run` does not offer), at the Adams method's tolerances: how the partition's cost grows.
    AdamsPartitioning,
}

impl BenchIntegrator {
    /// Every integrator, the default first.
    pub const ALL: [BenchIntegrator; 3] = [BenchIntegrator::Bdf, BenchIntegrator::Adams, BenchIntegrator::GenAlpha];

    /// The name `flexmb run --integrator` takes (`adams-partitioning`: the benchmark's own).
    pub fn name(self) -> &'static str {
        match self {
            BenchIntegrator::Bdf => "bdf",
            BenchIntegrator::Adams => "adams",
            BenchIntegrator::GenAlpha => "gen-alpha",
            BenchIntegrator::AdamsPartitioning => "adams-partitioning",
        }
    }

    /// The integrator whose tolerances this one runs at: the Adams method's for partitioning.
    pub fn tolerances_of(self) -> BenchIntegrator {
        match self {
            BenchIntegrator::AdamsPartitioning => BenchIntegrator::Adams,
            other => other,
        }
    }

    /// The method as a model file's `[simulation] integrator` names it (the BDF with its default
    /// settings, made the model's by [`SimulationDefaults::method_for`]).
    pub fn named_method(self) -> Method {
        match self {
            BenchIntegrator::Bdf => Method::default(),
            BenchIntegrator::Adams => Method::Adams(AdamsConfig::default()),
            BenchIntegrator::GenAlpha => Method::generalized_alpha(SPECTRAL_RADIUS),
            BenchIntegrator::AdamsPartitioning => {
                Method::Adams(AdamsConfig { constraints: ConstraintHandling::Partitioning, ..AdamsConfig::default() })
            }
        }
    }

    /// The method for `defaults` (a model file's `[simulation]`, e.g. its BDF order limit) and
    /// `model` (the BDF's stability limits for flexible bodies), as `flexmb run --integrator` sets it.
    pub fn method(self, defaults: &SimulationDefaults, model: &Model) -> Method {
        SimulationDefaults { method: self.named_method(), ..*defaults }.method_for(model)
    }
}
