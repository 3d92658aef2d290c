//! The divergence of neighbouring trajectories: a second run of the same model (the shadow), started a
//! few tolerances away, whose separation from the run measures how the run's local errors are amplified.
//!
//! A local error made at `s` reaches the end amplified as a perturbation of the state at `s` is. Where
//! neighbouring trajectories separate exponentially (chaotic motion, or the escape from an unstable
//! equilibrium) no error control holds the global error to the tolerance past a few Lyapunov times
//! `1/Λ`: the check says so, by a `tolerance` warning that names the time from which the amplification
//! exceeds 10 (the promise of docs/accuracy.md) and the exponent `Λ` fitted to the separation's growth.
//! Growth that is not exponential (a phase drifting linearly, as in every conservative oscillation whose
//! period depends on its energy) does not warn.

use super::shadow::{ShadowFrame, ShadowRun};
use super::{Simulation, SimulationSettings};
use crate::analysis::watchdog::{SimulationWarning, WarningKind};

/// The shadow's initial distance from the run, in the tolerance's weighted RMS norm (the weights
/// `atol + rtol |y|` over positions and velocities): far above the global errors of both runs (about one
/// tolerance each, so a few tolerances apart), so that their difference measures the growth of the
/// perturbation; small enough that it grows a thousandfold and more before it leaves the linear range at
/// `rtol` ≤ 3e-6 (a hundredfold at 3e-5; coarser tolerances leave it no room to be judged).
const INITIAL_SEPARATION: f64 = 30.0;
/// The amplification beyond which the global error is not promised within 10 tolerances.
const PROMISED_AMPLIFICATION: f64 = 10.0;
/// The amplification from which the growth is judged exponential or not.
const JUDGED_AMPLIFICATION: f64 = 30.0;
/// The least gain of `ln A` over the second half of the time since `A` passed 10, as a fraction of its
/// gain over the first half, that counts as exponential growth (1 for an exact exponential).
const EXPONENTIAL_GAIN: f64 = 0.8;
/// The separation, relative to the state's scale, from which it no longer grows as a perturbation
/// (the trajectories are no longer neighbours): the shadow stops there.
const NONLINEAR_SEPARATION: f64 = 0.1;

/// The shadow run and the growth of its separation from the run, one entry per output time.
pub(super) struct DivergenceCheck {
    shadow: ShadowRun,
    /// `rtol`, `atol` of the weighted norm.
    tolerances: (f64, f64),
    /// The largest `|y|` of each position and velocity of the run so far: the weights are
    /// `atol + rtol max|y|`, so that a coordinate passing through zero does not weigh its separation by
    /// `atol` alone there (the separation of an oscillating coordinate would spike at every crossing).
    scale: Vec<f64>,
    /// The separation at time 0 (weighted RMS norm); 0 until measured.
    initial: f64,
    /// `(t, ln A)`: the logarithm of the separation over the initial one at each output time compared
    /// (its envelope: the largest so far).
    growth: Vec<(f64, f64)>,
    /// Where the check ended (the shadow stopped or failed, or the run's end): no more comparisons.
    ended: bool,
    t_end: f64,
}

impl DivergenceCheck {
    /// A shadow of `run` at its start: the same model and settings, its velocities moved by
    /// [`INITIAL_SEPARATION`] tolerances (each by its own factor of the golden-ratio sequence, projected
    /// onto the velocity constraints, then scaled to that distance). `None` where the shadow cannot be started or
    /// the constraints leave the velocities no freedom (a fully driven mechanism).
    pub(super) fn start(run: &Simulation) -> Option<Self> {
        let settings = SimulationSettings { divergence_check: false, global_error_estimate: false, global_error_control: None, ..run.settings };
        let mut shadow = Simulation::new(std::sync::Arc::clone(&run.model), settings).ok()?;
        let (rtol, atol) = (settings.tolerances.rtol, settings.tolerances.atol);
        let (nq, nv) = (run.model.layout.nq, run.model.layout.nv);
        let v0 = run.velocities();
        // Factors in (−1, 1), each different (the golden-ratio sequence), so that no two components cancel
        // in the projection (as equal signs on `Ṙ` and `ω` would across a pendulum's hinge).
        let factor = |i: usize| ((i + 1) as f64 * 0.618_033_988_749_895).fract() * 2.0 - 1.0;
        let moved: Vec<f64> = v0.iter().enumerate().map(|(i, &v)| v + INITIAL_SEPARATION * (atol + rtol * v.abs()) * factor(i)).collect();
        shadow.set_state(None, Some(&moved)).ok()?;
        // The projection removed the part across the constraints: the rest scaled back to the distance.
        let weighted = |a: &[f64]| {
            let sum: f64 = a.iter().zip(v0).map(|(a, b)| ((a - b) / (atol + rtol * b.abs())).powi(2)).sum();
            (sum / (nq + nv) as f64).sqrt()
        };
        let projected = weighted(shadow.velocities());
        if projected.is_nan() || projected <= 1e-3 * INITIAL_SEPARATION {
            return None;
        }
        let factor = INITIAL_SEPARATION / projected;
        let moved: Vec<f64> = shadow.velocities().iter().zip(v0).map(|(a, b)| b + (a - b) * factor).collect();
        shadow.set_state(None, Some(&moved)).ok()?;
        Some(Self {
            shadow: ShadowRun::new(shadow),
            tolerances: (rtol, atol),
            scale: vec![0.0; nq + nv],
            initial: 0.0,
            growth: Vec::with_capacity(settings.grid_outputs() + 2),
            ended: false,
            t_end: settings.t_end,
        })
    }

    /// Compares the run's state `(q, v)` at the output time `t` with the shadow's there, advancing the
    /// shadow to it; at the run's end time (or where the separation stops being a perturbation) ends
    /// the check and, if the separation grew exponentially, adds its warning to `warnings`.
    pub(super) fn compare(&mut self, t: f64, q: &[f64], v: &[f64], warnings: &mut Vec<SimulationWarning>) {
        if self.ended {
            return;
        }
        match self.shadow.frame_at(t) {
            ShadowFrame::At => {}
            ShadowFrame::Missing => return, // an output time of the run that the shadow does not have
            ShadowFrame::Ended => return self.end(warnings),
        }
        let (rtol, atol) = self.tolerances;
        for (scale, y) in self.scale.iter_mut().zip(q.iter().chain(v)) {
            *scale = scale.max(y.abs());
        }
        let pairs = self.shadow.q().iter().chain(self.shadow.v()).zip(q.iter().chain(v)).zip(&self.scale);
        let (sum, largest) = pairs.fold((0.0, 0.0_f64), |(s, m), ((a, b), scale)| {
            let d = (a - b) / (atol + rtol * scale);
            (s + d * d, m.max((a - b).abs() / (1.0 + scale)))
        });
        let separation = (sum / self.scale.len() as f64).sqrt();
        if self.initial == 0.0 {
            self.initial = separation;
            if separation < 1e-3 * INITIAL_SEPARATION {
                self.ended = true; // no separation to follow
                return;
            }
        }
        // In tolerances at each time: an error of one tolerance at the start (in the weights there) grows
        // to `amplification` tolerances at `t` (in the weights at `t`).
        let amplification = separation / self.initial;
        // The envelope of ln A (its largest so far): the separation of oscillating coordinates oscillates.
        let envelope = self.growth.last().map_or(0.0, |&(_, a)| a);
        self.growth.push((t, amplification.ln().max(envelope)));
        if largest > NONLINEAR_SEPARATION || t >= self.t_end * (1.0 - 1e-12) {
            self.end(warnings);
        }
    }

    /// Ends the check, with its warning if the growth measured was exponential.
    fn end(&mut self, warnings: &mut Vec<SimulationWarning>) {
        self.ended = true;
        if let Some(growth) = exponential_growth(&self.growth) {
            warnings.push(SimulationWarning { t: growth.from, kind: WarningKind::Tolerance, message: growth.message() });
        }
    }
}

/// The exponential separation of neighbouring trajectories, measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ExponentialGrowth {
    /// The first time the amplification exceeded 10 (s): the tolerance is not promised from there.
    pub from: f64,
    /// The exponent `Λ` fitted to `ln A` from `from` to `last` (1/s).
    pub exponent: f64,
    /// The last time compared (s) and the amplification there.
    pub last: f64,
    pub amplification: f64,
}

impl ExponentialGrowth {
    fn message(&self) -> String {
        format!(
            "tolerance not promised from t = {from:.3} s: neighbouring trajectories separate exponentially here (chaotic \
             motion, or the escape from an unstable equilibrium), as e^(Λt) with Λ ≈ {exponent:.3} 1/s (a Lyapunov time \
             of {lyapunov:.3} s), measured by a second run started {INITIAL_SEPARATION} tolerances away, whose separation \
             grew {amplification:.1e}-fold by t = {last:.3} s; the local errors grow alike, so the global error exceeds \
             10 tolerances from t = {from:.3} s whatever the tolerance: what holds beyond is the error per unit step \
             (a nearby trajectory) and the invariants (energy)",
            from = self.from,
            exponent = self.exponent,
            lyapunov = 1.0 / self.exponent,
            amplification = self.amplification,
            last = self.last,
        )
    }
}

/// Whether the amplifications `growth` (`(t, ln A)`, in the order of time) grew exponentially: beyond
/// [`JUDGED_AMPLIFICATION`], and over the second half of the time since they passed
/// [`PROMISED_AMPLIFICATION`] by at least [`EXPONENTIAL_GAIN`] of what they gained (in `ln A`) over the
/// first. Growth linear in time fails that test wherever it reaches 30 (from 10 at `t₁`, `A = 30` at
/// `3 t₁`: `ln(3/2) = 0.41` in the second half against `ln 2 = 0.69` in the first, 0.58 of it, and less
/// further on); exponential growth gains the same in both.
/// The exponent is the least-squares slope of `ln A` on `t` from the first passage of 10 on.
pub(crate) fn exponential_growth(growth: &[(f64, f64)]) -> Option<ExponentialGrowth> {
    let promised = PROMISED_AMPLIFICATION.ln();
    let first = growth.iter().position(|&(_, a)| a > promised)?;
    let from = growth[first].0;
    let judged = growth.iter().enumerate().skip(first).any(|(k, &(t, a))| {
        a > JUDGED_AMPLIFICATION.ln() && {
            let middle = 0.5 * (from + t);
            let half = growth[first..=k].iter().find(|&&(s, _)| s >= middle).map_or(a, |&(_, m)| m);
            a - half >= EXPONENTIAL_GAIN * (half - promised)
        }
    });
    if !judged {
        return None;
    }
    let tail = &growth[first..];
    let n = tail.len() as f64;
    let (mt, ma) = tail.iter().fold((0.0, 0.0), |(st, sa), &(t, a)| (st + t / n, sa + a / n));
    let (stt, sta) = tail.iter().fold((0.0, 0.0), |(stt, sta), &(t, a)| (stt + (t - mt) * (t - mt), sta + (t - mt) * (a - ma)));
    let exponent = if stt > 0.0 { sta / stt } else { 0.0 };
    let &(last, a_last) = growth.last()?;
    (exponent > 0.0).then_some(ExponentialGrowth { from, exponent, last, amplification: a_last.exp() })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ln A` sampled every 0.01 s up to `t_end`.
    fn sampled(ln_a: impl Fn(f64) -> f64, t_end: f64) -> Vec<(f64, f64)> {
        (0..=(t_end * 100.0) as usize).map(|k| k as f64 * 0.01).map(|t| (t, ln_a(t))).collect()
    }

    #[test]
    fn exponential_growth_is_found_with_its_exponent() {
        // A = cosh(λ t), λ = 3: ln A → λ t − ln 2; A passes 10 at acosh(10)/3 = 0.998 s.
        let g = exponential_growth(&sampled(|t| (3.0 * t).cosh().ln(), 4.0)).expect("exponential");
        assert!((g.from - (10.0_f64).acosh() / 3.0).abs() < 0.011, "{g:?}");
        assert!((g.exponent - 3.0).abs() < 1e-3, "{g:?}");
    }

    #[test]
    fn growth_linear_or_bounded_is_not_exponential() {
        // A phase drifting linearly: A = 1 + 50 t reaches 10,001 by 200 s.
        assert_eq!(exponential_growth(&sampled(|t| (1.0 + 50.0 * t).ln(), 200.0)), None);
        // A bounded oscillation of the separation, as of a linear oscillator's perturbation.
        assert_eq!(exponential_growth(&sampled(|t| (2.0 + (5.0 * t).sin()).ln(), 20.0)), None);
    }
}
