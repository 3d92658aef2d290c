//! What a run reports, and why a run stopped.

use serde::{Deserialize, Serialize};

use crate::analysis::{AssemblyError, AssemblyReport, PhysicsMeasures, SimulationWarning, Unphysical, VelocityReport};
use crate::integrate::{CheckpointError, IntegrationError, Stats};

/// Everything a run reports, also for a run that failed midway.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct SimulationReport {
    /// The integration method that ran (`bdf`, `adams`, `gen-alpha`).
    #[serde(skip)]
    pub method: &'static str,
    /// What the assembly of the initial positions did.
    pub assembly: Option<AssemblyReport>,
    /// What the velocity analysis of the initial velocities did.
    pub velocity: Option<VelocityReport>,
    /// The integrator's counters.
    pub stats: Stats,
    /// Last time reached (s).
    pub t_reached: f64,
    /// Wall time of the integration (s).
    pub wall_time: f64,
    /// Largest position constraint residual over the accepted steps (the states the integrator solved
    /// for, to its Newton tolerance).
    pub max_position_residual: f64,
    /// Largest velocity constraint residual over the accepted steps.
    pub max_velocity_residual: f64,
    /// Largest position constraint residual over the output times: the states the outputs were
    /// evaluated at, interpolated between steps by the method's dense output (larger than at the
    /// steps: the interpolant holds the constraints only to its own truncation error).
    pub max_output_position_residual: f64,
    /// Largest velocity constraint residual over the output times.
    pub max_output_velocity_residual: f64,
    /// Largest `|pᵀp − 1|` over the accepted steps.
    pub max_normalization_error: f64,
    /// Total mechanical energy at the start (J).
    pub energy_initial: f64,
    /// Total mechanical energy at the last output (J).
    pub energy_final: f64,
    /// Work of the non-conservative forces (dampers, actuators, applied loads, modal damping, drivers)
    /// from the start to the last output (J), by the trapezoidal rule over the accepted steps and the
    /// output times together: with a correct solution `energy_final − energy_initial −
    /// nonconservative_work` is the quadrature's error, small because the steps resolve the motion
    /// and the outputs refine it. (Over the output times alone, a transient shorter than the output
    /// step was missed: a spring released far from its length dissipated 1.7 kJ in its damper in the
    /// first 0.01 s without the balance seeing it.)
    pub nonconservative_work: f64,
    /// The work of the non-conservative forces up to the last node of that rule (an accepted step or
    /// an output time), and the power there.
    pub work_at_step: WorkAtStep,
    /// Output frames reported.
    pub output_frames: usize,
    /// The physics watchdog's warnings, in the order they were raised.
    pub warnings: Vec<SimulationWarning>,
    /// The largest deflection and energy-balance error the watchdog measured.
    pub physics: PhysicsMeasures,
    /// Set when the run was stopped from outside before its end time.
    pub interrupted: Option<Interruption>,
}

/// The work of the non-conservative forces accumulated over the accepted steps and output times.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WorkAtStep {
    /// Time of the node (s).
    pub t: f64,
    /// Power of the non-conservative forces there (W).
    pub power: f64,
    /// Their work from the start to `t` (J).
    pub work: f64,
}

/// A run stopped from outside (a signal, a user) after an accepted step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Interruption {
    /// Time of the last accepted step (s); the output times up to it were all reported.
    pub t: f64,
    /// What stopped it, as the caller named it (e.g. `SIGINT`).
    pub reason: String,
}

/// Why a simulation stopped.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum SimulationFailure {
    /// The initial positions or velocities could not be made consistent.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// The integrator failed.
    #[error(transparent)]
    Integration(#[from] IntegrationError),
    /// The accelerations at an output time (or at the start) could not be solved.
    #[error("at t = {t:.6} s the accelerations cannot be solved: the mass matrix or the constraint Jacobian is singular{detail}")]
    SingularAccelerations {
        /// Time (s).
        t: f64,
        /// What more is known (may be empty).
        detail: String,
    },
    /// The physics watchdog stopped the run.
    #[error(transparent)]
    Unphysical(#[from] Unphysical),
    /// An output sink failed to take a frame.
    #[error("the output at t = {t:.6} s could not be written: {message}")]
    Output {
        /// Time of the frame (s).
        t: f64,
        /// The sink's message.
        message: String,
    },
    /// A checkpoint could not be taken or restored.
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    /// Invalid settings, or a simulation used after it failed.
    #[error("{0}")]
    Invalid(String),
}

/// A failed simulation with what it had done.
#[derive(Clone, Debug, thiserror::Error)]
#[error("{cause}")]
pub struct SimulationError {
    /// Why it stopped.
    pub cause: SimulationFailure,
    /// What it had done until then.
    pub report: Box<SimulationReport>,
}
