//! What to simulate and how: end time, output step, integration method and tolerances, assembly and
//! the physics watchdog's limits.

use crate::analysis::{AssemblySettings, EquilibriumSettings, PhysicsLimits};
use crate::integrate::{Method, Tolerances};

/// What to simulate and how.
#[derive(Clone, Copy, Debug)]
pub struct SimulationSettings {
    /// End time (s); the run starts at 0.
    pub t_end: f64,
    /// Spacing of the output times (s).
    pub output_step: f64,
    /// Error tolerances and step limits (every method reads them).
    pub tolerances: Tolerances,
    /// How the initial positions are assembled onto the constraints.
    pub assembly: AssemblySettings,
    /// Where the run starts: the assembled initial configuration, or the static equilibrium there.
    /// Default [`Start::Assembly`].
    pub start: Start,
    /// The integration method with its own settings. Default [`Method::Bdf`] with
    /// [`BdfConfig::default`](crate::integrate::BdfConfig::default).
    pub method: Method,
    /// When the physics watchdog warns and when it stops the run.
    pub physics_limits: PhysicsLimits,
    /// Runs a second simulation alongside, started 30 tolerances away, and warns where the two
    /// separate exponentially (chaotic motion): from there the global error is not held to the
    /// tolerance, and the warning names the time and the estimated Lyapunov exponent (docs/accuracy.md,
    /// *Chaotic motion*). It doubles the cost of a run. Not kept in a checkpoint; a
    /// [`set_state`](super::Simulation::set_state) ends it. Default off.
    pub divergence_check: bool,
    /// Runs a second simulation alongside from the same start at a tenth of the tolerances, and
    /// estimates the run's global error from their difference at the output times (times 10/9, the
    /// errors being proportional to the tolerance; Shampine's global error assessment by reintegration):
    /// [`SimulationReport::global_error`](super::SimulationReport::global_error), and a `tolerance`
    /// warning where it exceeds 10 tolerances, with the tolerance that would deliver the one asked
    /// (docs/accuracy.md, *The global error estimate*). It costs the finer run, about 1.6 to 2.5 times
    /// the run's. Not kept in a checkpoint; a [`set_state`](super::Simulation::set_state) ends it. Default off.
    pub global_error_estimate: bool,
    /// Global error control by reintegration: the global error is estimated (as with
    /// [`global_error_estimate`](Self::global_error_estimate)) against these tolerances, those asked for,
    /// and a run whose estimate exceeds 10 of them is run again from the start at the tolerances that
    /// bring it to about one ([`global_error_rerun`](super::global_error_rerun), at most
    /// [`MAX_RERUNS`](super::MAX_RERUNS) times; docs/accuracy.md, *Global error control*). The runs again
    /// are the callers': [`simulate`](super::simulate) does them (its observer sees each from t = 0), a
    /// [`Simulation`](super::Simulation) stepped by hand does not. Costs the estimate and the runs again.
    /// Default `None` (off).
    pub global_error_control: Option<super::GlobalErrorControl>,
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self {
            t_end: 1.0,
            output_step: 0.01,
            tolerances: Tolerances::default(),
            assembly: AssemblySettings::default(),
            start: Start::Assembly,
            method: Method::default(),
            physics_limits: PhysicsLimits::default(),
            divergence_check: false,
            global_error_estimate: false,
            global_error_control: None,
        }
    }
}

/// The initial positions of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Start {
    /// The model's initial configuration, assembled onto the constraints.
    #[default]
    Assembly,
    /// The static equilibrium at the start time ([`static_equilibrium`](crate::analysis::static_equilibrium),
    /// its assembly that of [`SimulationSettings::assembly`]); the velocities are the model's initial
    /// velocities (zero unless it gives some), made consistent by the velocity analysis.
    Equilibrium(EquilibriumSettings),
}

impl SimulationSettings {
    /// Checks the end time, the output step, the tolerance span and the watchdog's limits.
    pub(super) fn validate(&self) -> Result<(), String> {
        if !(self.t_end > 0.0 && self.t_end.is_finite()) {
            return Err(format!("t_end must be positive, got {}", self.t_end));
        }
        if !(self.output_step > 0.0 && self.output_step.is_finite()) {
            return Err(format!("output_step must be positive, got {}", self.output_step));
        }
        self.tolerances.span.validate()?;
        self.physics_limits.validate()
    }

    /// Output times on the grid `k · output_step` up to `t_end` (the one at 0 included).
    pub(super) fn grid_outputs(&self) -> usize {
        (self.t_end / self.output_step * (1.0 + 1e-12)).floor() as usize
    }

    /// The end time is not on the output grid, so it gets an output of its own.
    pub(super) fn end_off_grid(&self) -> bool {
        (self.grid_outputs() as f64 * self.output_step - self.t_end).abs() > 1e-9 * self.t_end
    }
}
