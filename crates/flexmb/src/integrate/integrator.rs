//! What every time integrator offers the simulation driver: steps, the state, dense output, statistics.

use super::{CheckpointError, IntegrationError, IntegratorCheckpoint, Stats};
use crate::data::Data;

/// A time integrator of a model's equations of motion, started at a consistent state. `Send`, so that
/// a simulation may move between threads (a binding, a sweep).
pub trait Integrator: Send {
    /// Current time (s).
    fn t(&self) -> f64;
    /// Takes one accepted step, not passing `t_stop`; a failure says when and why.
    fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError>;
    /// Positions `q` and velocities `v` at the current time.
    fn state(&self) -> (&[f64], &[f64]);
    /// Positions and velocities at `t` within the last step, from the method's interpolant.
    fn interpolate(&mut self, t: f64, q: &mut [f64], v: &mut [f64]);
    /// The statistics so far.
    fn stats(&self) -> &Stats;
    /// Scratch data, for evaluating outputs between steps.
    fn data_mut(&mut self) -> &mut Data;
    /// The constraint rows in force (redundant rows switched off).
    fn active(&self) -> &[bool];
    /// The method's name for reports: `bdf`, `adams`, `gen-alpha`.
    fn name(&self) -> &'static str;
    /// The complete state between two steps (see [`IntegratorCheckpoint`]).
    fn checkpoint(&self) -> Result<IntegratorCheckpoint, CheckpointError>;
    /// Continues from `checkpoint`, taken of an integrator of the same method on the same model: the
    /// following steps are those the checkpointed integrator would have taken.
    fn restore(&mut self, checkpoint: &IntegratorCheckpoint) -> Result<(), CheckpointError>;
}
