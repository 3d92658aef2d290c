//! The complete state of a simulation between two steps, as plain data that serializes (serde): what
//! [`Simulation::resume`](super::Simulation::resume) needs to continue the run with the same steps
//! and the same outputs as if it had not stopped.

use serde::{Deserialize, Serialize};

use super::SimulationReport;
use crate::analysis::WatchdogCheckpoint;
use crate::integrate::IntegratorCheckpoint;

/// Version of the checkpoint's layout; a checkpoint of another version is refused. Version 2: the
/// generalized-α method keeps its stiffness and damping on the linearization's pattern.
pub const CHECKPOINT_VERSION: u32 = 2;

/// A simulation's complete state after an accepted step.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SimulationCheckpoint {
    /// [`CHECKPOINT_VERSION`] when it was taken.
    pub version: u32,
    /// Time of the last accepted step (s).
    pub t: f64,
    /// Positions `q` at `t`.
    pub q: Vec<f64>,
    /// Velocities `v` at `t`.
    pub v: Vec<f64>,
    /// Lagrange multipliers `λ` at `t` (one per constraint row; zero on rows switched off).
    pub multipliers: Vec<f64>,
    /// The constraint rows in force.
    pub active: Vec<bool>,
    /// The integrator's history, order, step size and counters.
    pub integrator: IntegratorCheckpoint,
    /// The report so far: counters, residuals, energies, the work of the non-conservative forces,
    /// the watchdog's warnings and measures.
    pub report: SimulationReport,
    /// The watchdog's running sums.
    pub watchdog: WatchdogCheckpoint,
    /// The current value of each parameter of the model (changed or not).
    pub parameters: Vec<f64>,
    /// Index of the next output time on the grid `k · output_step` (0: the initial state).
    pub next_output: usize,
    /// The output step of that grid (s); a run resumed with another output step takes up its own grid
    /// after `t`.
    pub output_step: f64,
    /// Whether the output at the end time (off the grid) was reported.
    pub end_reported: bool,
    /// The names of the model's laws given as code ([`Model::user_laws`](crate::Model::user_laws)):
    /// they are not in the checkpoint, and the model it resumes must have the same.
    #[serde(default)]
    pub user_laws: Vec<String>,
    /// The counters of the integrators a [`set_state`](super::Simulation::set_state) replaced.
    #[serde(default)]
    pub restarted_stats: crate::integrate::Stats,
    /// The output values of the last row reported: the Euler-angle outputs continue from them past
    /// ±π (empty in a checkpoint from before they were kept: the angles then restart from their
    /// principal values).
    #[serde(default)]
    pub last_output_row: Vec<f64>,
}
