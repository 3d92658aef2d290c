//! Dynamic simulation: assembly, velocity analysis, initial accelerations, then BDF steps with results
//! at the requested output times taken from the method's interpolant.

use std::time::Instant;

use super::outputs::{constraint_residuals, evaluate_outputs, output_columns};
use super::watchdog::{PhysicsLimits, PhysicsMeasures, SimulationWarning, Unphysical, Watchdog};
use super::{
    assemble, velocity_analysis, AccelerationSolver, AssemblyError, AssemblyReport, AssemblySettings, State,
    VelocityReport,
};
use crate::data::Data;
use crate::integrate::{Bdf, BdfConfig, IntegrationError, Integrator, Method, Stats};
use crate::integrate::Adams;
use crate::integrate::{GeneralizedAlpha, GeneralizedAlphaConfig};
use crate::model::Model;
use crate::stage::{constraint_equations, energy, kinematics, nonconservative_power};

/// What to simulate and how.
#[derive(Clone, Copy, Debug)]
pub struct SimulationSettings {
    /// End time (s); the run starts at 0.
    pub t_end: f64,
    /// Spacing of the output times (s).
    pub output_step: f64,
    /// Tolerances and step limits (every method reads them; `max_order` is each method's own).
    pub integrator: BdfConfig,
    pub assembly: AssemblySettings,
    /// The integration method. Default [`Method::Bdf`].
    pub method: Method,
    /// When the physics watchdog warns and when it stops the run.
    pub physics_limits: PhysicsLimits,
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self {
            t_end: 1.0,
            output_step: 0.01,
            integrator: BdfConfig::default(),
            assembly: AssemblySettings::default(),
            method: Method::Bdf,
            physics_limits: PhysicsLimits::default(),
        }
    }
}

/// The outputs at one output time.
#[derive(Clone, Copy, Debug)]
pub struct OutputFrame<'a> {
    pub t: f64,
    /// One value per [`output_columns`] entry.
    pub values: &'a [f64],
    /// The positions `q` (per body `R, p, a`) at `t`.
    pub q: &'a [f64],
    /// The velocities `v` (per body `Ṙ, ω̄, ȧ`) at `t`.
    pub v: &'a [f64],
}

/// Everything a run reports, also for a run that failed midway.
#[derive(Clone, Debug, Default)]
pub struct SimulationReport {
    /// The integration method that ran (`bdf`, `adams`, `gen-alpha`).
    pub method: &'static str,
    pub assembly: Option<AssemblyReport>,
    pub velocity: Option<VelocityReport>,
    pub stats: Stats,
    /// Last time reached (s).
    pub t_reached: f64,
    /// Wall time of the integration (s).
    pub wall_time: f64,
    /// Largest position and velocity constraint residual over the accepted steps (the states the
    /// integrator solved for, to its Newton tolerance).
    pub max_position_residual: f64,
    pub max_velocity_residual: f64,
    /// Largest position and velocity constraint residual over the output times: the states the outputs
    /// were evaluated at, interpolated between steps by the method's dense output (larger than at the
    /// steps: the interpolant holds the constraints only to its own truncation error).
    pub max_output_position_residual: f64,
    pub max_output_velocity_residual: f64,
    /// Largest `|pᵀp − 1|` over the accepted steps.
    pub max_normalization_error: f64,
    /// Total mechanical energy at the start and at the last output (J).
    pub energy_initial: f64,
    pub energy_final: f64,
    /// Work of the non-conservative forces (dampers, actuators, applied loads, modal damping, drivers)
    /// from the start to the last output (J), by the trapezoidal rule over the output times: with a
    /// correct solution `energy_final − energy_initial − nonconservative_work` is the quadrature's
    /// error, small when the output step resolves the power.
    pub nonconservative_work: f64,
    /// Power of the non-conservative forces and time at the last output (W, s).
    pub last_power: (f64, f64),
    pub output_frames: usize,
    /// The physics watchdog's warnings, in the order they were raised.
    pub warnings: Vec<SimulationWarning>,
    /// The largest deflection and energy-balance error the watchdog measured.
    pub physics: PhysicsMeasures,
    /// Set when the run was stopped from outside before its end time.
    pub interrupted: Option<Interruption>,
}

/// A run stopped from outside (a signal, a user) after an accepted step.
#[derive(Clone, Debug, PartialEq)]
pub struct Interruption {
    /// Time of the last accepted step (s); the output times up to it were all reported.
    pub t: f64,
    /// What stopped it, as the caller named it (e.g. `SIGINT`).
    pub reason: String,
}

/// Why a simulation stopped.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum SimulationFailure {
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Integration(#[from] IntegrationError),
    #[error("at t = {t:.6} s the accelerations cannot be solved: the mass matrix or the constraint Jacobian is singular{detail}")]
    SingularAccelerations { t: f64, detail: String },
    #[error(transparent)]
    Unphysical(#[from] Unphysical),
    #[error("{0}")]
    Invalid(String),
}

/// A failed simulation with what it had done.
#[derive(Clone, Debug, thiserror::Error)]
#[error("{cause}")]
pub struct SimulationError {
    pub cause: SimulationFailure,
    pub report: Box<SimulationReport>,
}

/// Runs a simulation and hands every output frame to `observer` as soon as it is computed.
pub fn simulate(
    model: &Model,
    settings: &SimulationSettings,
    observer: &mut dyn FnMut(&OutputFrame),
) -> Result<SimulationReport, SimulationError> {
    simulate_interruptible(model, settings, observer, &|| None)
}

/// [`simulate`], asking `interrupt` after every accepted step (once its output frames are reported)
/// whether to stop; when it answers with a reason, the run ends there and its report carries
/// [`SimulationReport::interrupted`].
pub fn simulate_interruptible(
    model: &Model,
    settings: &SimulationSettings,
    observer: &mut dyn FnMut(&OutputFrame),
    interrupt: &dyn Fn() -> Option<String>,
) -> Result<SimulationReport, SimulationError> {
    let mut report = SimulationReport::default();
    match run(model, settings, observer, interrupt, &mut report) {
        Ok(()) => Ok(report),
        Err(cause) => Err(SimulationError { cause, report: Box::new(report) }),
    }
}

fn run(
    model: &Model,
    settings: &SimulationSettings,
    observer: &mut dyn FnMut(&OutputFrame),
    interrupt: &dyn Fn() -> Option<String>,
    report: &mut SimulationReport,
) -> Result<(), SimulationFailure> {
    if !(settings.t_end > 0.0 && settings.t_end.is_finite()) {
        return Err(SimulationFailure::Invalid(format!("t_end must be positive, got {}", settings.t_end)));
    }
    if !(settings.output_step > 0.0 && settings.output_step.is_finite()) {
        return Err(SimulationFailure::Invalid(format!("output_step must be positive, got {}", settings.output_step)));
    }
    settings.physics_limits.validate().map_err(SimulationFailure::Invalid)?;
    let mut watchdog = Watchdog::new(model, settings.physics_limits, settings.integrator.atol);
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    report.assembly = Some(assemble(model, &mut data, &mut state, settings.assembly)?);
    report.velocity = Some(velocity_analysis(model, &mut data, &mut state)?);
    let mut acc_solver = AccelerationSolver::new(model);
    let acc = acc_solver
        .solve(model, &mut data, state.t, &state.q, &state.v, &state.active)
        .map_err(|_| SimulationFailure::SingularAccelerations { t: state.t, detail: String::new() })?
        .clone();
    let mut integrator: Box<dyn Integrator + '_> = match settings.method {
        Method::Bdf => Box::new(Bdf::new(model, &state, &acc, settings.integrator)?),
        Method::Adams(config) => {
            config.validate().map_err(SimulationFailure::Invalid)?;
            Box::new(Adams::new(model, &state, &acc, settings.integrator, config)?)
        }
        Method::GeneralizedAlpha { spectral_radius } => {
            let config = GeneralizedAlphaConfig { spectral_radius, ..Default::default() };
            config.validate().map_err(SimulationFailure::Invalid)?;
            Box::new(GeneralizedAlpha::new(model, &state, &acc, settings.integrator, config)?)
        }
    };
    report.method = integrator.name();

    let n_out = output_columns(model).len();
    let mut values = vec![0.0; n_out];
    let (nq, nv) = (model.layout.nq, model.layout.nv);
    let (mut q, mut v) = (vec![0.0; nq], vec![0.0; nv]);
    // The rows in force do not change during a run; copied once so that no step allocates.
    let active = integrator.active().to_vec();
    let mut frame = |integrator: &mut dyn Integrator, t: f64, q: &[f64], v: &[f64], values: &mut [f64], report: &mut SimulationReport| {
        let data = integrator.data_mut();
        let acc = acc_solver
            .solve(model, data, t, q, v, &active)
            .map_err(|_| SimulationFailure::SingularAccelerations { t, detail: String::new() })?;
        let power = nonconservative_power(model, data, t, &acc.lambda);
        evaluate_outputs(model, data, q, v, acc, &active, values);
        let (p, vel) = constraint_residuals(model, data, &active);
        report.max_output_position_residual = report.max_output_position_residual.max(p);
        report.max_output_velocity_residual = report.max_output_velocity_residual.max(vel);
        let e = energy(model, data, q, v);
        if report.output_frames == 0 {
            report.energy_initial = e.total();
        } else {
            let (p0, t0) = report.last_power;
            report.nonconservative_work += 0.5 * (p0 + power) * (t - t0);
        }
        report.last_power = (power, t);
        report.energy_final = e.total();
        let balance_error = report.energy_final - report.energy_initial - report.nonconservative_work;
        Watchdog::check_finite_frame(model, (t, q, v), &e, power)?;
        report.output_frames += 1;
        observer(&OutputFrame { t, values, q, v });
        watchdog.check_frame(model, data, (t, q, v), (&e, balance_error, power), &mut report.warnings, &mut report.physics)?;
        Ok::<(), SimulationFailure>(())
    };

    copy_state(integrator.as_ref(), &mut q, &mut v);
    frame(integrator.as_mut(), 0.0, &q, &v, &mut values, report)?;
    let n_frames = (settings.t_end / settings.output_step * (1.0 + 1e-12)).floor() as usize;
    let mut next = 1;
    let start = Instant::now();
    while integrator.t() < settings.t_end {
        let step = integrator.step(settings.t_end);
        report.stats = *integrator.stats();
        report.t_reached = integrator.t();
        report.wall_time = start.elapsed().as_secs_f64();
        step?;
        copy_state(integrator.as_ref(), &mut q, &mut v);
        Watchdog::check_finite(model, integrator.t(), &q, &v)?;
        check_step(model, integrator.as_mut(), &q, &v, &active, report);
        while next <= n_frames && next as f64 * settings.output_step <= integrator.t() * (1.0 + 1e-12) {
            let t_out = next as f64 * settings.output_step;
            let t_eval = t_out.min(integrator.t());
            integrator.interpolate(t_eval, &mut q, &mut v);
            frame(integrator.as_mut(), t_out, &q, &v, &mut values, report)?;
            next += 1;
        }
        if let Some(reason) = interrupt() {
            report.interrupted = Some(Interruption { t: integrator.t(), reason });
            report.wall_time = start.elapsed().as_secs_f64();
            return Ok(());
        }
    }
    // The end time itself when it is not on the output grid.
    if (n_frames as f64 * settings.output_step - settings.t_end).abs() > 1e-9 * settings.t_end {
        copy_state(integrator.as_ref(), &mut q, &mut v);
        frame(integrator.as_mut(), settings.t_end, &q, &v, &mut values, report)?;
    }
    report.wall_time = start.elapsed().as_secs_f64();
    Ok(())
}

fn copy_state(integrator: &dyn Integrator, q: &mut [f64], v: &mut [f64]) {
    let (qi, vi) = integrator.state();
    q.copy_from_slice(qi);
    v.copy_from_slice(vi);
}

/// Records the constraint residuals and the Euler-parameter normalization at an accepted step.
fn check_step(model: &Model, integrator: &mut dyn Integrator, q: &[f64], v: &[f64], active: &[bool], report: &mut SimulationReport) {
    let t = integrator.t();
    let data = integrator.data_mut();
    kinematics(model, data, q, v);
    constraint_equations(model, data, t);
    let (p, vel) = constraint_residuals(model, data, active);
    report.max_position_residual = report.max_position_residual.max(p);
    report.max_velocity_residual = report.max_velocity_residual.max(vel);
    for b in 0..model.bodies.len() {
        let qo = model.layout.q_offset[b];
        let norm2: f64 = (3..7).map(|k| q[qo + k].powi(2)).sum();
        report.max_normalization_error = report.max_normalization_error.max((norm2 - 1.0).abs());
    }
}
