//! The floor under the share of the tolerance a step may spend.
//!
//! With error per unit step ([`Tolerances::step_share`]) a step of size `h` is held to `h / span` of the
//! tolerance, so its error estimate must fall faster than `h` when the step is shortened. Two parts of an
//! estimate do not, and would drive the step size to zero:
//!
//! - **the rest of the last step's Newton iteration.** An accepted state holds the constraints only to
//!   the Newton tolerance of its own share; the next corrector removes that rest whatever its step size.
//!   A step far shorter than the last sees it as an error that does not fall with the step (3-D
//!   slider-crank at rtol 1e-4, t = 0.46 s, where the rod's spin is nearly undetermined: the step size
//!   fell to 1e-14 s with the estimate at 135 shares). Hence a share of at least
//!   [`LAST_SHARE_FRACTION`] of the last accepted step's.
//! - **rounding amplified by ill-conditioning.** Near a singular position the corrector's solution is
//!   only resolved to many units of rounding (the same slider-crank at rtol 1e-10, t = 0.287 s: an
//!   estimate of ±1.7e-12 rad/s alternating in sign, 8,000 units of rounding, at every step size from
//!   1e-7 s to 1e-11 s; each step failed once, was shortened and passed). When an estimate does not fall
//!   below half its value at the first failure after the steps were shortened [`NOISE_STEP_RATIO`] times
//!   since, it is noise: the share is held at twice it (the step is
//!   accepted), a floor that then decays by [`NOISE_DECAY`] per accepted step.
//!
//! What these floors let through is bounded: the first by a geometric series, `0.1/(1 − 0.1)` of the
//! last step's share; the second by the resolution of the equations themselves.
//!
//! Under both lies a fixed floor, what one step resolves relative to the solution: `1e-12 / rtol` for the
//! Adams method ([`Tolerances::step_share`]), [`FINE_STEP_FLOOR`]` / rtol` for the BDF, or where the BDF
//! measured its estimate's noise, three times that noise down to 1.5e-14 (`integrate/noise_floor.rs`),
//! whose Newton floor is lower too, [`BDF_NEWTON_FLOOR`] (`Bdf::newton_tolerance` says where), and for the generalized-α
//! method, whose many second-order steps add up to the floor times their number
//! (`generalized_alpha::SHARE_FLOOR`). With error per
//! unit step below rtol 1e-8 a step's share `h / span` is below the floor, and the floor holds each local
//! error at that fraction of the solution: `N` steps then add up to about `N` times it, whatever the
//! tolerance (the 1e-12 floor held the BDF's error on the heavy top at 8.2e-10 over 22,700 steps, at
//! rtol 1e-9 and 1e-10 alike; the rigid pendulum's at 9.3e-11). The BDF counts the steps its floor
//! holds ([`Stats::share_floor_steps`]), and a run whose count times the floor exceeds rtol warns
//! ([`floor_warning`]).

use crate::integrate::tolerances::STEP_FLOOR;
use crate::integrate::{Stats, Tolerances};

/// The floor under a step's local error, relative to the solution, of the BDF and the generalized-α
/// method (`generalized_alpha::SHARE_FLOOR` says why there): a tenth of the Adams method's
/// [`STEP_FLOOR`]. For the BDF: Its estimate, the corrector's difference from an extrapolation of the history, is
/// resolved to about ten units of rounding of the solution times the predictor's gain, `2^(k+1)/(k + 1)`
/// (10.7 at order 5): about 2.4e-14, a quarter of this floor. Measured over the run at rtol 1e-10 with
/// the Newton floor lowered alike (ten units of rounding): 1e-13 gave the heavy top 1.2 tolerances in
/// 33,210 steps (the 1e-12 floor: 8.2 in 22,700), the rigid pendulum 0.13 in 3,216 (0.93 in 2,190);
/// 3e-14 gave 0.67 and 0.05 in 43,400 and 3,900 steps; with the Newton floor left at 100 units, 1e-13
/// rejected 811 steps of the heavy top (9), 3e-14 5,004 steps of 74,800: the increments' unresolved
/// part was then the estimate's noise.
///
/// Where the floor holds the steps (below rtol 1e-8 over a run of thousands of steps), each local error
/// is this fraction of the solution and the BDF's truncation errors add up coherently (they dissipate
/// energy): the 3-D slider-crank over 5 s lost 5.3e-10 J of its 0.77 J at rtol 1e-10 in 26,360 steps,
/// linearly in time, and the phase error it causes made `E` 7.2e-9 (72 tolerances), the same at 1e-9
/// and 1e-10. Lower floors were measured again with the Newton floor at 10 to 20 units: within 10
/// tolerances at 1e-10 needs 5e-15 to 1e-14 and 45,700 to 82,800 steps, and below 1e-13 the estimate
/// is no longer resolved: at rtol 1e-9, where 1e-14 does not hold the steps, the order fell to 3 and 4
/// on 38 % of 45,600 steps and `E` rose from 6.2 to 34 tolerances (Newton floor 20 units both); Andrews'
/// squeezer stopped at 1e-10 (step too small at t = 0.0199 s). What brought the slider-crank within 10
/// tolerances at 1e-10 instead is a bound on the longest of the steps the floor holds
/// ([`floor_step_cap`](super::floor_step_cap)).
pub(crate) const FINE_STEP_FLOOR: f64 = STEP_FLOOR / 10.0;

/// What the BDF's Newton increments resolve, relative to the solution, where the conditioning does not
/// amplify the rounding: 20 units of rounding, a fifth of the other methods' floor
/// ([`NEWTON_FLOOR`](super::tolerances::NEWTON_FLOOR)). With 100 the corrector's unresolved part, up to
/// 2.2e-14 of the solution, is as large as a step's local error at [`FINE_STEP_FLOOR`], and it was the
/// estimate's noise: the 3-D slider-crank at rtol 1e-10 rejected 373 steps of 26,360 (84 of 23,416 with
/// 20), the heavy top 811 of 34,764 (23 of 32,838), Bricard's mechanism 138 of 6,582 (8 of 4,339), and
/// the slider-crank's `E` fell from 8.0 to 6.2 tolerances at 1e-9 and from 72 to 61 at 1e-10. At ten
/// units, the round-off level of an increment, a run driven into a lock (a distance pulled past its reach
/// at t = 1 s) crept towards it for millions of accepted steps of 1e-11 s, its increments converging in
/// the rounding there; at 20 it fails at the lock within 3,600 steps, naming the joint.
pub(crate) const BDF_NEWTON_FLOOR: f64 = 20.0 * f64::EPSILON;

/// The warning of the step that makes the steps held to the fixed floor of a run spend more than its
/// tolerance, `None` at every other step: such steps spent `spent_before` of the solution before the step
/// that ended at `t` and [`Stats::share_floor_spent`] after it, of a run of `t_end` seconds whose tolerance is `rtol` over each
/// `span` seconds ([`Tolerances::span`], the run's length by default). Each of those steps is held to
/// [`Stats::share_floor`] of the solution (their mean floor) however short it is, and their local errors add up
/// (coherently for the BDF, whose truncation errors dissipate energy: the 3-D slider-crank at rtol
/// 1e-10, 26,000 steps at 1e-13, lost 5.3e-10 J of 0.77 J and ended 72 tolerances off): once their number
/// times the floor exceeds the run's tolerance, `rtol` times its number of spans, the tolerance is no
/// longer kept by the error control, and the run says so, once. The message names the floor, the steps,
/// what they add up to so far and at this rate by the end, and what to do.
pub(crate) fn floor_warning(spent_before: f64, stats: &Stats, rtol: f64, span: f64, t: f64, t_end: f64) -> Option<String> {
    let (held, floor) = (stats.share_floor_steps, stats.share_floor);
    let allowed = rtol * (t_end / span).max(1.0);
    let crossed = spent_before <= allowed && stats.share_floor_spent() > allowed;
    crossed.then(|| {
        let at_end = held as f64 * (t_end / t).max(1.0);
        format!(
            "tolerance finer than the BDF keeps over this run: {held} steps up to t = {t:.4} s were each held to what one \
             step resolves, {floor:.0e} of the solution (the floor under a step's share of the tolerance), and their local \
             errors, each up to that floor, can add up over the run (the BDF's dissipate energy) to {sum:.1e} of the \
             solution, more than rtol {allowed:e} (at this rate about {at_end:.0} such steps and {sum_end:.1e} by t = \
             {t_end} s): the error can reach several tolerances; for a finer tolerance use the Adams method (integrator = \"adams\"), which keeps \
             rtol 1e-10 on the benchmarks of docs/accuracy.md but the double four-bar through its singular positions (there to \
             1e-9); the statistics share_floor_steps and share_floor count \
             these steps and give the floor",
            sum = held as f64 * floor,
            sum_end = at_end * floor,
        )
    })
}

/// A step's share of the tolerance is at least this fraction of the last accepted step's.
const LAST_SHARE_FRACTION: f64 = 0.1;
/// A step shortened this many times within one step without its estimate falling by half is noise.
const NOISE_STEP_RATIO: f64 = 8.0;
/// Only an estimate below this fraction of the solution can be noise: the rounding seen is thousands of
/// units (1.7e-12 on the slider-crank), an estimate that does not fall with the step above it is a stiff
/// component's (the BDF's pendulum on a 1e7 N/m spring) and must not pass.
const NOISE_LEVEL: f64 = 1e-10;
/// Factor of the noise floor per accepted step.
const NOISE_DECAY: f64 = 0.95;

/// The floor under a step's share of the tolerance (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct ShareFloor {
    /// The share of the last accepted step.
    pub accepted: f64,
    /// The share learnt from an estimate that was noise.
    pub noise: f64,
    /// The step size and estimate (in tolerances, not shares) of the first failed attempt since the steps
    /// were last as long.
    probe: Option<(f64, f64)>,
}

impl ShareFloor {
    /// The share of the tolerance a step of size `h` may spend.
    pub fn share(&self, tolerances: &Tolerances, h: f64) -> f64 {
        self.share_above(tolerances, h, STEP_FLOOR)
    }

    /// [`share`](Self::share) with the fixed floor `floor / rtol` (`floor` relative to the solution:
    /// [`FINE_STEP_FLOOR`] for the BDF).
    pub fn share_above(&self, tolerances: &Tolerances, h: f64, floor: f64) -> f64 {
        tolerances.step_share_above(h, floor).max(LAST_SHARE_FRACTION * self.accepted).max(self.noise)
    }

    /// An attempt at step size `h` failed the error test with the estimate `error` (in tolerances). True
    /// when the estimate is noise (it has not fallen by half since the first failure, in this step or the
    /// shorter steps after it, while the step was shortened [`NOISE_STEP_RATIO`] times): the floor is then
    /// raised to twice it, and the attempt passes.
    pub fn is_noise(&mut self, h: f64, error: f64, rtol: f64) -> bool {
        if error * rtol > NOISE_LEVEL {
            return false;
        }
        match self.probe {
            None => {
                self.probe = Some((h, error));
                false
            }
            Some((h_first, error_first)) if h_first >= NOISE_STEP_RATIO * h => {
                if error >= 0.5 * error_first {
                    self.noise = self.noise.max(2.0 * error);
                    true
                } else {
                    // It fell: an error, resolved by shorter steps; the next comparison starts here.
                    self.probe = Some((h, error));
                    false
                }
            }
            Some(_) => false,
        }
    }

    /// A step of size `h` was accepted with the share `share`. The first failure is forgotten once the
    /// steps are as long again.
    pub fn accepted(&mut self, h: f64, share: f64) {
        self.accepted = share;
        self.noise *= NOISE_DECAY;
        if self.probe.is_some_and(|(h_first, _)| h >= h_first) {
            self.probe = None;
        }
    }

    /// The floors `[accepted, noise]`, for a checkpoint.
    pub fn stored(&self) -> [f64; 2] {
        [self.accepted, self.noise]
    }

    /// The floors of a checkpoint.
    pub fn restored(stored: [f64; 2]) -> Self {
        Self { accepted: stored[0], noise: stored[1], probe: None }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The warning comes once, at the step whose held steps times the floor first exceed the run's
    /// tolerance (rtol times the spans in the run), and names the floor, the steps and what they add up to.
    #[test]
    fn the_warning_comes_at_the_step_that_makes_the_floor_spend_more_than_the_tolerance() {
        let held = |steps| Stats { share_floor_steps: steps, share_floor: FINE_STEP_FLOOR, ..Stats::default() };
        let warning = |before: usize, after| floor_warning(before as f64 * FINE_STEP_FLOOR, &held(after), 1e-10, 5.0, 2.0, 5.0);
        assert_eq!(warning(999, 1000), None, "1,000 steps at 1e-13 make rtol exactly");
        let message = warning(1000, 1001).expect("1,001 steps exceed it");
        assert!(message.contains("1001 steps up to t = 2.0000 s") && message.contains("1e-13"), "{message}");
        assert!(message.contains("about 2502 such steps and 2.5e-10 by t = 5 s"), "{message}");
        assert_eq!(warning(1001, 1002), None, "once");
        // Over a span of 1 s, a run of 5 s may spend five tolerances.
        assert_eq!(floor_warning(4000.0 * FINE_STEP_FLOOR, &held(4001), 1e-10, 1.0, 2.0, 5.0), None);
        assert!(floor_warning(5000.0 * FINE_STEP_FLOOR, &held(5001), 1e-10, 1.0, 2.0, 5.0).is_some());
    }

    /// An estimate that falls with the step is never noise; one that stays while the step is cut eight
    /// times is, and then passes at the floor it sets; a short step after a long one may spend a tenth
    /// of the long one's share.
    #[test]
    fn an_estimate_that_does_not_fall_with_the_step_is_noise() {
        let tolerances = Tolerances { span: crate::integrate::ToleranceSpan::Seconds(1.0), ..Tolerances::new(1e-6, 1e-6) };
        let mut floor = ShareFloor::default();
        let mut h = 1e-3;
        for _ in 0..6 {
            assert!(!floor.is_noise(h, 1e-3 * (h / 1e-3).powi(3), 1e-8));
            h *= 0.25;
        }
        let mut floor = ShareFloor::default();
        let steps = [1e-3, 5e-4, 2e-4, 1.3e-4];
        assert!(steps.iter().all(|&h| !floor.is_noise(h, 3e-6, 1e-8)));
        assert!(floor.is_noise(1e-4, 3e-6, 1e-8));
        assert!(!ShareFloor::default().is_noise(1e-4, 3e-2, 1e-8), "an estimate of 3e-10 of the solution is not noise");
        assert_eq!(floor.share(&tolerances, 1e-9), 6e-6);
        assert!(3e-6 / floor.share(&tolerances, 1e-9) <= 1.0);
        floor.accepted(2e-3, 2e-3);
        assert_eq!(floor.share(&tolerances, 1e-9), 2e-4);
        assert_eq!(floor.share(&tolerances, 1e-2), 1e-2);
    }
}
