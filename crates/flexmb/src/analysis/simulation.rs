//! Dynamic simulation: assembly, velocity analysis, initial accelerations, then BDF steps with results
//! at the requested output times taken from the method's interpolant.

use std::time::Instant;

use super::outputs::{constraint_residuals, evaluate_outputs, output_columns};
use super::{
    assemble, velocity_analysis, AccelerationSolver, AssemblyError, AssemblyReport, AssemblySettings, State,
    VelocityReport,
};
use crate::data::Data;
use crate::integrate::{Bdf, BdfConfig, IntegrationError, Stats};
use crate::model::Model;
use crate::stage::{constraint_equations, energy, kinematics, YLayout};

/// What to simulate and how.
#[derive(Clone, Copy, Debug)]
pub struct SimulationSettings {
    /// End time (s); the run starts at 0.
    pub t_end: f64,
    /// Spacing of the output times (s).
    pub output_step: f64,
    pub integrator: BdfConfig,
    pub assembly: AssemblySettings,
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
    pub assembly: Option<AssemblyReport>,
    pub velocity: Option<VelocityReport>,
    pub stats: Stats,
    /// Last time reached (s).
    pub t_reached: f64,
    /// Wall time of the integration (s).
    pub wall_time: f64,
    /// Largest position and velocity constraint residual over the accepted steps.
    pub max_position_residual: f64,
    pub max_velocity_residual: f64,
    /// Largest `|pᵀp − 1|` over the accepted steps.
    pub max_normalization_error: f64,
    /// Total mechanical energy at the start and at the last output (J).
    pub energy_initial: f64,
    pub energy_final: f64,
    pub output_frames: usize,
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
    let mut report = SimulationReport::default();
    match run(model, settings, observer, &mut report) {
        Ok(()) => Ok(report),
        Err(cause) => Err(SimulationError { cause, report: Box::new(report) }),
    }
}

fn run(
    model: &Model,
    settings: &SimulationSettings,
    observer: &mut dyn FnMut(&OutputFrame),
    report: &mut SimulationReport,
) -> Result<(), SimulationFailure> {
    if !(settings.t_end > 0.0 && settings.t_end.is_finite()) {
        return Err(SimulationFailure::Invalid(format!("t_end must be positive, got {}", settings.t_end)));
    }
    if !(settings.output_step > 0.0 && settings.output_step.is_finite()) {
        return Err(SimulationFailure::Invalid(format!("output_step must be positive, got {}", settings.output_step)));
    }
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    report.assembly = Some(assemble(model, &mut data, &mut state, settings.assembly)?);
    report.velocity = Some(velocity_analysis(model, &mut data, &mut state)?);
    let mut acc_solver = AccelerationSolver::new(model);
    let acc = acc_solver
        .solve(model, &mut data, state.t, &state.q, &state.v, &state.active)
        .map_err(|_| SimulationFailure::SingularAccelerations { t: state.t, detail: String::new() })?
        .clone();
    let mut bdf = Bdf::new(model, &state, &acc, settings.integrator)?;

    let yl = YLayout::new(model);
    let n_out = output_columns(model).len();
    let mut values = vec![0.0; n_out];
    let mut y = vec![0.0; yl.len()];
    // The rows in force do not change during a run; copied once so that no step allocates.
    let active = bdf.active().to_vec();
    let mut y_step = vec![0.0; yl.len()];
    let mut frame = |bdf: &mut Bdf, t: f64, y: &[f64], values: &mut [f64], report: &mut SimulationReport| {
        let (q, v) = (&y[yl.q.clone()], &y[yl.v.clone()]);
        let data = bdf.data_mut();
        let acc = acc_solver
            .solve(model, data, t, q, v, &active)
            .map_err(|_| SimulationFailure::SingularAccelerations { t, detail: String::new() })?;
        evaluate_outputs(model, data, q, v, acc, &active, values);
        let e = energy(model, data, q, v).total();
        if report.output_frames == 0 {
            report.energy_initial = e;
        }
        report.energy_final = e;
        report.output_frames += 1;
        observer(&OutputFrame { t, values, q, v });
        Ok::<(), SimulationFailure>(())
    };

    y.copy_from_slice(bdf.y());
    frame(&mut bdf, 0.0, &y, &mut values, report)?;
    let n_frames = (settings.t_end / settings.output_step * (1.0 + 1e-12)).floor() as usize;
    let mut next = 1;
    let start = Instant::now();
    while bdf.t() < settings.t_end {
        let step = bdf.step(settings.t_end);
        report.stats = bdf.stats;
        report.t_reached = bdf.t();
        report.wall_time = start.elapsed().as_secs_f64();
        step?;
        y_step.copy_from_slice(bdf.y());
        check_step(model, &mut bdf, &yl, &y_step, &active, report);
        while next <= n_frames && next as f64 * settings.output_step <= bdf.t() * (1.0 + 1e-12) {
            let t_out = next as f64 * settings.output_step;
            bdf.interpolate(t_out.min(bdf.t()), &mut y);
            frame(&mut bdf, t_out, &y, &mut values, report)?;
            next += 1;
        }
    }
    // The end time itself when it is not on the output grid.
    if (n_frames as f64 * settings.output_step - settings.t_end).abs() > 1e-9 * settings.t_end {
        y.copy_from_slice(bdf.y());
        frame(&mut bdf, settings.t_end, &y, &mut values, report)?;
    }
    report.wall_time = start.elapsed().as_secs_f64();
    Ok(())
}

/// Records the constraint residuals and the Euler-parameter normalization at an accepted step.
fn check_step(model: &Model, bdf: &mut Bdf, yl: &YLayout, y: &[f64], active: &[bool], report: &mut SimulationReport) {
    let t = bdf.t();
    let (q, v) = (&y[yl.q.clone()], &y[yl.v.clone()]);
    let data = bdf.data_mut();
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
