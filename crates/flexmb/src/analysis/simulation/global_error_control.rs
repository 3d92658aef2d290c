//! Global error control by reintegration: a run whose global error estimate
//! ([`SimulationSettings::global_error_estimate`]) exceeds the 10 tolerances the error control aims at is
//! run again from the start at the tolerances that, the errors being proportional to the tolerance,
//! bring its global error to the tolerance asked for.
//!
//! Local error control spends the tolerance on the run's steps; a mechanism that amplifies the local
//! errors (a four-bar passing its top position slowly, a pendulum revolving over its top with little
//! energy to spare) turns them into a global error of many tolerances. The estimate measures that
//! amplification `N` (in tolerances); the run again at `rtol / N` and `atol / N` is then about one
//! tolerance off, and its own estimate, measured against the tolerances first asked for, says whether it
//! is. At most [`MAX_RERUNS`] runs again: an amplification that grows as the tolerance falls is not
//! chased further (the last run's warning says so, with the tolerance it would take).

use serde::{Deserialize, Serialize};

use super::{SimulationReport, SimulationSettings};
use crate::integrate::Tolerances;

/// The runs again after the first, at most: where the amplification does not depend on the tolerance, one
/// suffices (the four-bar of `models/`: 18.3 tolerances at rtol 1e-6, 0.92 at the 5.5e-8 asked); a second
/// corrects an amplification that grew.
pub const MAX_RERUNS: usize = 2;

/// Global error control ([`SimulationSettings::global_error_control`]): the tolerances the global error is
/// to meet, those first asked for, whatever finer ones the runs again take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlobalErrorControl {
    /// The relative tolerance asked for.
    pub rtol: f64,
    /// The absolute tolerance asked for.
    pub atol: f64,
}

/// A run that global error control ran again, finer: its tolerances, its estimate and its cost.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ControlledRun {
    /// Its relative tolerance.
    pub rtol: f64,
    /// Its absolute tolerance.
    pub atol: f64,
    /// Its global error estimate (relative, [`GlobalErrorEstimate::estimate`](super::GlobalErrorEstimate::estimate)).
    pub estimate: f64,
    /// The estimate in the tolerances asked for.
    pub tolerances: f64,
    /// Its accepted steps.
    pub steps: usize,
    /// The accepted steps of its run at the finer tolerance (the estimate's cost).
    pub shadow_steps: usize,
}

/// The run global error control takes after the run of `settings` that reported `report`, and the record
/// of that run, if it asks for one: with [`SimulationSettings::global_error_control`] on, after a run that
/// reached its end time with an estimate over every output time that exceeds 10 of the tolerances asked for
/// and is to be trusted ([`GlobalErrorEstimate::is_trusted`](super::GlobalErrorEstimate::is_trusted): the finer run took at least 1.1 times its
/// steps, at most half of them held by the BDF's floor under a step's share), fewer than [`MAX_RERUNS`] runs
/// again so far (`earlier`), and tolerances `rtol / N`, `atol / N` (`N` the estimate over the tolerance
/// asked for) not below [`Tolerances::FINEST`], and finer than this run's once the method has raised them to
/// the finest it keeps over the run (the BDF's 1e-10, generalized-α's 1e-7). The settings are `settings`
/// with those tolerances.
pub fn global_error_rerun(
    settings: &SimulationSettings,
    report: &SimulationReport,
    earlier: usize,
) -> Option<(SimulationSettings, ControlledRun)> {
    settings.global_error_control?;
    let estimate = report.global_error?;
    let t_end = settings.t_end;
    let ended = report.interrupted.is_none() && report.t_reached >= t_end * (1.0 - 1e-12);
    let compared = estimate.t_compared >= t_end * (1.0 - 1e-12);
    let trusted = estimate.is_trusted(report.stats.steps);
    if !(ended && compared && trusted) || estimate.tolerances <= super::global_error::PROMISED_TOLERANCES || earlier >= MAX_RERUNS {
        return None;
    }
    let n = estimate.tolerances;
    let (rtol, atol) = (settings.tolerances.rtol, settings.tolerances.atol);
    if rtol / n < Tolerances::FINEST || atol / n < Tolerances::FINEST {
        return None;
    }
    let tolerances = Tolerances { rtol: rtol / n, atol: atol / n, ..settings.tolerances };
    // Where the method raises the finer tolerance to its finest over the run and that is no finer than
    // this run's, running again gives the same run.
    let (attainable, _) = super::attainable_by_method(&tolerances, &settings.method);
    if attainable.rtol > 0.5 * rtol && attainable.atol > 0.5 * atol {
        return None;
    }
    let run = ControlledRun { rtol, atol, estimate: estimate.estimate, tolerances: n, steps: report.stats.steps, shadow_steps: estimate.shadow_steps };
    Some((SimulationSettings { tolerances, ..*settings }, run))
}

/// Runs `run` with `settings`, then again from the start at the finer settings [`global_error_rerun`]
/// asks for, as long as it asks: the one loop of global error control, whatever a run writes to (the
/// engine's [`simulate_interruptible`](super::simulate_interruptible), the result files, the Python
/// package's tables). `run` returns its outcome and, where the run completed and may be made again, its
/// report. Returns the last run's outcome, its settings and the runs made again before it.
pub fn run_under_global_error_control<T>(
    settings: &SimulationSettings,
    mut run: impl FnMut(&SimulationSettings) -> (T, Option<SimulationReport>),
) -> (T, SimulationSettings, Vec<ControlledRun>) {
    let (mut settings, mut earlier) = (*settings, Vec::new());
    loop {
        let (outcome, completed) = run(&settings);
        match completed.and_then(|report| global_error_rerun(&settings, &report, earlier.len())) {
            Some((finer, this)) => {
                settings = finer;
                earlier.push(this);
            }
            None => return (outcome, settings, earlier),
        }
    }
}
