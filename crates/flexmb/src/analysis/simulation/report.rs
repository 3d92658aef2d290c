//! What a run reports, and why a run stopped.

use serde::{Deserialize, Serialize};

use crate::analysis::{
    AssemblyError, AssemblyReport, EquilibriumError, EquilibriumReport, PhysicsMeasures, SimulationWarning, Unphysical, VelocityReport,
};
use crate::integrate::{CheckpointError, IntegrationError, Stats};

/// Everything a run reports, also for a run that failed midway.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct SimulationReport {
    /// The integration method that ran (`bdf`, `adams`, `gen-alpha`).
    #[serde(skip)]
    pub method: &'static str,
    /// What the assembly of the initial positions did.
    pub assembly: Option<AssemblyReport>,
    /// What the static equilibrium did, for a run started from it.
    #[serde(default)]
    pub equilibrium: Option<Box<EquilibriumReport>>,
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
    /// from the start to the last output (J), by a third-order rule (the trapezoid corrected by the
    /// parabola through three nodes, [`WorkAtStep::add`]) over the accepted steps and the output times
    /// together: with a correct solution `energy_final − energy_initial −
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
    /// The global error estimated by reintegration, over the output times compared so far
    /// ([`SimulationSettings::global_error_estimate`](super::SimulationSettings::global_error_estimate)).
    #[serde(default)]
    pub global_error: Option<super::GlobalErrorEstimate>,
    /// The runs that global error control ([`SimulationSettings::global_error_control`](super::SimulationSettings::global_error_control))
    /// ran again before this one, finer, in order (empty where the first run kept the tolerance asked
    /// for, or without the control). Filled by the caller that ran them ([`simulate`](super::simulate)).
    #[serde(default)]
    pub global_error_control: Vec<super::ControlledRun>,
}

/// The work of the non-conservative forces accumulated over the accepted steps and output times, the
/// nodes of the quadrature of their power (see [`add`](Self::add)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WorkAtStep {
    /// Time of the node (s).
    pub t: f64,
    /// Power of the non-conservative forces there (W).
    pub power: f64,
    /// Their work from the start to `t` (J).
    pub work: f64,
    /// Time and power of the node before, if there is one.
    #[serde(default)]
    pub previous: Option<(f64, f64)>,
}

impl WorkAtStep {
    /// The work up to the next node `t`, where the power is `power`: this node's plus the integral over
    /// `[self.t, t]` of the parabola through this node, the one before it and the next (the
    /// trapezoid less `h³/12` times the parabola's second derivative, third order), or the trapezoid
    /// from the first node. The trapezoid alone is second order and, on the nodes of the steps and the
    /// output times together, which are not evenly spaced, its errors do not cancel as they do on an
    /// even grid: a damped slider at rtol 1e-9 over 10 s (2,596 steps, outputs every 2 ms) had a
    /// quadrature error of 2.5e-7 J with the trapezoid, 4.7e-9 J with the parabola, against an
    /// integration error of the energy of 1e-9 J.
    pub fn add(&self, t: f64, power: f64) -> WorkAtStep {
        let h = t - self.t;
        let mut work = self.work + 0.5 * (self.power + power) * h;
        if let Some((t_before, power_before)) = self.previous {
            let second_derivative =
                2.0 * ((power - self.power) / h - (self.power - power_before) / (self.t - t_before)) / (t - t_before);
            if second_derivative.is_finite() {
                work -= h.powi(3) / 12.0 * second_derivative;
            }
        }
        WorkAtStep { t, power, work, previous: Some((self.t, self.power)) }
    }
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
    /// The static equilibrium to start from was not found.
    #[error(transparent)]
    Equilibrium(#[from] EquilibriumError),
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
    /// A law given as code failed ([`UserFunction`](crate::function::UserFunction)).
    #[error("at t = {t:.6} s the law `{law}` failed: {message}")]
    UserLaw {
        /// The law's name.
        law: String,
        /// Time of the evaluation that failed (s).
        t: f64,
        /// The law's message.
        message: String,
    },
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

#[cfg(test)]
mod tests {
    use super::WorkAtStep;

    /// The work of the power `p(t)` over `nodes` by [`WorkAtStep::add`] from the first node.
    fn work(p: impl Fn(f64) -> f64, nodes: &[f64]) -> f64 {
        let first = WorkAtStep { t: nodes[0], power: p(nodes[0]), work: 0.0, previous: None };
        nodes[1..].iter().fold(first, |w, &t| w.add(t, p(t))).work
    }

    /// On unevenly spaced nodes the rule integrates a parabola exactly after its first interval (there
    /// the trapezoid, off by `h³ p''/12`), and its error on a smooth power falls as `h³`: at least ×7
    /// per halving of the nodes' spacing (×8 in the limit), where the trapezoid's falls ×4.
    #[test]
    fn the_parabola_through_three_nodes_integrates_to_third_order() {
        let uneven = |n: usize| -> Vec<f64> {
            (0..=n).map(|k| k as f64 / n as f64).map(|x| x + 0.3 * x * (1.0 - x) * (7.0 * x).sin() / n as f64).collect()
        };
        let nodes = uneven(10);
        let parabola = |t: f64| 2.0 - 3.0 * t + 5.0 * t * t;
        let first_trapezoid_error = nodes[1].powi(3) / 12.0 * 10.0;
        let exact = 2.0 - 1.5 + 5.0 / 3.0;
        let off = work(parabola, &nodes) - exact - first_trapezoid_error;
        assert!(off.abs() < 1e-14, "{off:e}");
        let power = |t: f64| (4.0 * t).sin().powi(2);
        let exact = 0.5 - (8.0_f64).sin() / 16.0;
        let errors: Vec<f64> = [20, 40, 80, 160].iter().map(|&n| (work(power, &uneven(n)) - exact).abs()).collect();
        for pair in errors.windows(2) {
            assert!(pair[0] / pair[1] > 7.0, "errors {errors:?}");
        }
    }
}
