//! The global error of a run estimated by reintegration (Shampine's global error assessment, as RKSUITE
//! offers it): a second run of the same model from the same initial state at a tenth of the tolerances
//! (the shadow), compared with the run at every output time.
//!
//! Where the error is proportional to the tolerance, the run's error is `e` and the shadow's `e/10`, so
//! their difference is `9e/10`: the run's global error is estimated as the difference times `10/9`. Local
//! error control does not see how the mechanism amplifies the local errors (a four-bar passing its top
//! position slowly, with little energy to spare, turns a small error of its energy into a shift of every
//! later passage); the difference of the two runs does, and the run warns (`tolerance`) when the estimate
//! exceeds the 10 tolerances the error control aims at, with the tolerance that would deliver what was
//! asked.
//!
//! The norm is that of docs/accuracy.md (*The global error and its norm*): over the position outputs
//! (`marker_position`, `node_position`), each output's largest difference over its largest value
//! (here the shadow's, the better solution). A model without position outputs is measured in its
//! positions and velocities, each coordinate's largest difference over `atol + rtol max|y|`.

use serde::{Deserialize, Serialize};

use super::shadow::{ShadowFrame, ShadowRun};
use super::{Simulation, SimulationReport, SimulationSettings};
use crate::analysis::watchdog::{SimulationWarning, WarningKind};
use crate::integrate::{Method, Tolerances};

/// The shadow's tolerances are the run's over this: one decade, so that the correction `10/9` is close
/// to 1 (where the shadow's error is not a tenth of the run's, the estimate is off by less than the
/// shadow's share) and the shadow costs `10^(1/k)` times the steps at order `k` (×1.6 at order 5).
const REFINEMENT: f64 = 10.0;
/// The estimate, in tolerances, beyond which the run warns: the promise of docs/accuracy.md.
pub(super) const PROMISED_TOLERANCES: f64 = 10.0;
/// The least ratio of the shadow's steps to the run's at which the steps are taken as set by the
/// tolerance (`10^(1/k)` at order `k`: 1.6 at order 5; measured 1.14 to 1.6 on the shipped models where
/// the estimate agrees with the error). Below it a floor holds the steps of both runs (the finest share of
/// a step over a long run at a fine tolerance, a largest step), their errors are not in proportion to
/// their tolerances, and their difference does not measure the error: the IFToMM A01 pendulum over
/// 2,000 s at rtol 1e-8 took 1,018,798 steps and its shadow 1,018,508, their difference 7.3 tolerances
/// against a true error of 796.
pub(super) const PROPORTIONAL_STEPS: f64 = 1.1;
/// The largest fraction of the shadow's steps that the BDF's fixed floor under a step's share may hold
/// ([`Stats::share_floor_steps`](crate::integrate::Stats::share_floor_steps)) for the estimate to be
/// trusted. A step held there makes an error of the floor, not of the shadow's tolerance, so a shadow held
/// there mostly is not ten times more accurate than the run. The IFToMM double four-bar over the run at
/// rtol 1e-9: its shadow at 1e-10 was held at every one of its 10,336 steps (1.11 times the run's, above
/// [`PROPORTIONAL_STEPS`]), its error 1.53e-8 m against the run's 1.66e-8 m, and their difference made an
/// estimate of 1.46 tolerances of an error of 16.6.
pub(super) const FLOOR_HELD_SHARE: f64 = 0.5;

/// In which norm the global error was estimated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GlobalErrorNorm {
    /// The position outputs: each output's largest difference over its largest value (relative).
    #[default]
    PositionOutputs,
    /// The positions and velocities (the model has no position output): each coordinate's largest
    /// difference over `atol + rtol max|y|`, times `rtol`.
    State,
}

impl GlobalErrorNorm {
    /// Its name in the summary.
    pub fn name(&self) -> &'static str {
        match self {
            Self::PositionOutputs => "position_outputs",
            Self::State => "state",
        }
    }
}

/// The global error estimated by reintegration ([`SimulationSettings::global_error_estimate`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GlobalErrorEstimate {
    /// The estimate of the global error `E` (relative, in the norm [`norm`](Self::norm)).
    pub estimate: f64,
    /// The estimate in tolerances: `estimate / rtol`, `rtol` the one asked for (with
    /// [`SimulationSettings::global_error_control`], whose runs again take finer ones, the control's).
    pub tolerances: f64,
    /// The output time where the estimate's largest difference was (s).
    pub t: f64,
    /// The norm of the estimate.
    pub norm: GlobalErrorNorm,
    /// The shadow's relative tolerance (a tenth of the run's, or the finest tolerance).
    pub shadow_rtol: f64,
    /// The last output time compared (the end time, unless the shadow stopped before it).
    pub t_compared: f64,
    /// The shadow's accepted steps (its cost).
    pub shadow_steps: usize,
    /// Of those, the steps held to the BDF's fixed floor under a step's share (0 for the other methods).
    #[serde(default)]
    pub shadow_floor_steps: usize,
}

impl GlobalErrorEstimate {
    /// Whether the estimate measures the error of a run of `steps` accepted steps: the shadow took at least
    /// 1.1 times its steps (else a floor holds the steps of both) and at most half of the shadow's steps
    /// were held by the BDF's floor under a step's share (else the shadow's errors are the floor's, not a
    /// tenth of the run's). Where not, the difference of the two
    /// runs may be far below the run's error, and the run says so.
    pub fn is_trusted(&self, steps: usize) -> bool {
        self.shadow_steps as f64 >= PROPORTIONAL_STEPS * steps as f64 && self.shadow_floor_steps as f64 <= FLOOR_HELD_SHARE * self.shadow_steps as f64
    }
}

/// The shadow at the finer tolerance and the largest differences measured so far.
pub(super) struct Reintegration {
    shadow: ShadowRun,
    /// The run's tolerances.
    rtol: f64,
    atol: f64,
    /// The tolerances the estimate is measured against: the run's, or those global error control was asked for.
    asked: (f64, f64),
    /// `1 / (1 − r)`, `r` the shadow's tolerance over the run's: the difference times it is the run's error
    /// where the errors are proportional to the tolerance (10/9).
    correction: f64,
    norm: GlobalErrorNorm,
    /// The first column of each position output (three columns each); empty with [`GlobalErrorNorm::State`].
    groups: Vec<usize>,
    /// Per group (or coordinate): the largest `|y|` of the shadow so far.
    scale: Vec<f64>,
    /// Per group (or coordinate): the largest difference so far and the time of it.
    largest: Vec<(f64, f64)>,
    t_end: f64,
    /// The finest tolerance the run's method keeps over the run ([`super::finest_over_run`]).
    finest: f64,
    ended: bool,
}

impl Reintegration {
    /// The shadow of `run` at its tolerances over [`REFINEMENT`]: the same model, settings and start.
    /// `Err` with the reason where no estimate can be made (a fixed step, a tolerance already at the
    /// finest, a shadow that does not start).
    pub(super) fn start(run: &Simulation) -> Result<Self, String> {
        if let Method::GeneralizedAlpha(config) = &run.settings.method {
            if config.fixed_step.is_some() {
                return Err("the generalized-α method runs at a fixed step, which no tolerance changes".into());
            }
        }
        let (rtol, atol) = (run.settings.tolerances.rtol, run.settings.tolerances.atol);
        let tolerances = Tolerances { rtol: rtol / REFINEMENT, atol: atol / REFINEMENT, ..run.settings.tolerances };
        let settings = SimulationSettings {
            divergence_check: false,
            global_error_estimate: false,
            global_error_control: None,
            tolerances,
            ..run.settings
        };
        let shadow = Simulation::new(std::sync::Arc::clone(&run.model), settings)
            .map_err(|e| format!("the run at the finer tolerance did not start: {}", e.cause))?;
        // The shadow's tolerance as raised to the finest attainable.
        let shadow_rtol = shadow.settings.tolerances.rtol;
        let ratio = shadow_rtol / rtol;
        if ratio > 0.5 {
            return Err(format!(
                "rtol {rtol:e} leaves no finer tolerance to compare with (the finest attainable is {shadow_rtol:e})"
            ));
        }
        let model = &run.model;
        let groups = crate::analysis::position_output_columns(model);
        let (norm, n) = if groups.is_empty() {
            (GlobalErrorNorm::State, model.layout.nq + model.layout.nv)
        } else {
            (GlobalErrorNorm::PositionOutputs, groups.len())
        };
        Ok(Self {
            shadow: ShadowRun::new(shadow),
            rtol,
            atol,
            asked: run.settings.global_error_control.map_or((rtol, atol), |c| (c.rtol, c.atol)),
            correction: 1.0 / (1.0 - ratio),
            norm,
            groups,
            scale: vec![0.0; n],
            largest: vec![(0.0, 0.0); n],
            t_end: settings.t_end,
            finest: super::finest_over_run(&run.settings.method),
            ended: false,
        })
    }

    /// Compares the run's frame at the output time `t` (its output `values`, positions `q` and velocities
    /// `v`) with the shadow's there, advancing the shadow to it, and keeps the estimate in `report`; at
    /// the end time (or where the shadow stopped) ends the estimate, with its warning if it exceeds
    /// [`PROMISED_TOLERANCES`].
    pub(super) fn compare(&mut self, t: f64, (values, q, v): (&[f64], &[f64], &[f64]), report: &mut SimulationReport) {
        if self.ended {
            return;
        }
        match self.shadow.frame_at(t) {
            ShadowFrame::At => {}
            ShadowFrame::Missing => return,
            ShadowFrame::Ended => return self.end(report),
        }
        let mut update = |k: usize, scale: f64, difference: f64| {
            self.scale[k] = self.scale[k].max(scale);
            if difference > self.largest[k].0 {
                self.largest[k] = (difference, t);
            }
        };
        match self.norm {
            GlobalErrorNorm::PositionOutputs => {
                let shadow = self.shadow.values();
                for (k, &c) in self.groups.iter().enumerate() {
                    let scale = (c..c + 3).fold(0.0_f64, |m, i| m.max(shadow[i].abs()));
                    let difference = (c..c + 3).fold(0.0_f64, |m, i| m.max((values[i] - shadow[i]).abs()));
                    update(k, scale, difference);
                }
            }
            GlobalErrorNorm::State => {
                let shadow = self.shadow.q().iter().chain(self.shadow.v());
                for (k, (a, b)) in shadow.zip(q.iter().chain(v)).enumerate() {
                    update(k, a.abs(), (a - b).abs());
                }
            }
        }
        report.global_error = Some(self.estimate(t));
        if t >= self.t_end * (1.0 - 1e-12) {
            self.end(report);
        }
    }

    /// The estimate over the output times compared up to `t_compared`.
    fn estimate(&self, t_compared: f64) -> GlobalErrorEstimate {
        let (rtol, atol) = self.asked;
        let weight = |scale: f64| match self.norm {
            GlobalErrorNorm::PositionOutputs if scale > 0.0 => rtol * scale,
            GlobalErrorNorm::PositionOutputs => rtol,
            GlobalErrorNorm::State => atol + rtol * scale,
        };
        let (tolerances, t) = self
            .scale
            .iter()
            .zip(&self.largest)
            .map(|(&scale, &(difference, t))| (self.correction * difference / weight(scale), t))
            .fold((0.0, 0.0), |best, x| if x.0 > best.0 { x } else { best });
        GlobalErrorEstimate {
            estimate: tolerances * rtol,
            tolerances,
            t,
            norm: self.norm,
            shadow_rtol: self.shadow.simulation().settings.tolerances.rtol,
            t_compared,
            shadow_steps: self.shadow.simulation().stats().steps,
            shadow_floor_steps: self.shadow.simulation().stats().share_floor_steps,
        }
    }

    /// Ends the estimate, with its warning where it exceeds [`PROMISED_TOLERANCES`].
    fn end(&mut self, report: &mut SimulationReport) {
        self.ended = true;
        let Some(estimate) = report.global_error.as_mut() else { return };
        let shadow_stats = self.shadow.simulation().stats();
        (estimate.shadow_steps, estimate.shadow_floor_steps) = (shadow_stats.steps, shadow_stats.share_floor_steps);
        if estimate.tolerances > PROMISED_TOLERANCES {
            let message = warning(estimate, (self.rtol, self.atol), self.asked.0, self.t_end, self.finest);
            report.warnings.push(SimulationWarning { t: estimate.t, kind: WarningKind::Tolerance, message });
        }
        // A mechanism without degrees of freedom moves as its drivers say, and one at rest stays where it
        // is, whatever the tolerance: both runs the same to the last digit, and nothing to estimate.
        let free = report.assembly.as_ref().is_none_or(|a| a.degrees_of_freedom > 0);
        let (steps, shadow_steps) = (report.stats.steps, estimate.shadow_steps);
        if free && estimate.estimate > 0.0 && !estimate.is_trusted(steps) {
            let held = estimate.shadow_floor_steps;
            let why = if (shadow_steps as f64) < PROPORTIONAL_STEPS * steps as f64 {
                format!("took {shadow_steps} steps against the run's {steps}, so a floor holds the steps of both (over a long run at a fine tolerance, the finest share of a step; a largest step)")
            } else {
                format!("had {held} of its {shadow_steps} steps held to the floor under a step's share (the BDF's {floor:.0e} of the solution per step), not to its tolerance", floor = shadow_stats.share_floor)
            };
            let message = format!(
                "global error estimate not to be trusted: the run at the finer tolerance (rtol {shadow:.2e}) {why}, and their errors \
                 are not in proportion to their tolerances: their difference, {e:.2e} ({n:.1} tolerances), does not measure the global error and may be far below it",
                shadow = estimate.shadow_rtol,
                e = estimate.estimate,
                n = estimate.tolerances,
            );
            report.warnings.push(SimulationWarning { t: estimate.t_compared, kind: WarningKind::Tolerance, message });
        }
    }
}

/// The warning of an estimate beyond the promise, with the tolerances that would deliver `asked` (the run's
/// `rtol`, or the one global error control was asked for) from the run's `(rtol, atol)`: under
/// proportionality the error falls with the tolerances, so `rtol / N` and `atol / N` for an estimate of
/// `N` tolerances.
fn warning(estimate: &GlobalErrorEstimate, (rtol, atol): (f64, f64), asked: f64, t_end: f64, finest: f64) -> String {
    let n = estimate.tolerances;
    let (asked_rtol, asked_atol) = (rtol / n, atol / n);
    let norm = match estimate.norm {
        GlobalErrorNorm::PositionOutputs => "relative, in the position outputs",
        GlobalErrorNorm::State => "in the positions and velocities, the model having no position output",
    };
    let compared = if estimate.t_compared < t_end * (1.0 - 1e-12) {
        format!(" (compared up to t = {:.3} s, where the run at the finer tolerance stopped)", estimate.t_compared)
    } else {
        String::new()
    };
    let ask = if asked_rtol < finest {
        format!(
            "about rtol {asked_rtol:.1e} would be needed for an error of {asked:e}, finer than the finest tolerance \
             this method keeps over the run ({finest:e}; the Adams method keeps {adams:e}): no tolerance of this \
             method delivers it",
            adams = Tolerances::FINEST
        )
    } else {
        format!("ask rtol {asked_rtol:.1e} and atol {asked_atol:.1e} for an error of about {asked:e}")
    };
    format!(
        "global error estimated at {e:.2e} ({n:.1} tolerances, {norm}) at t = {t:.3} s{compared}, beyond the 10 tolerances \
         the error control aims at: a second run from the same start at rtol {shadow:.2e} differs by that much (times \
         {correction:.3}, the errors being proportional to the tolerance); the mechanism amplifies the local errors more \
         than error per unit step allows for; {ask}",
        e = estimate.estimate,
        t = estimate.t,
        shadow = estimate.shadow_rtol,
        correction = 1.0 / (1.0 - estimate.shadow_rtol / rtol),
    )
}
