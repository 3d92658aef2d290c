//! The rounding floor of the Newton increments: the level below which the increments of a step's
//! simplified Newton iteration are the rounding of its residual, amplified by the iteration matrix, and no
//! longer a correction.
//!
//! The increments of a converging iteration shrink with every iteration, and those of an iteration that
//! fails for want of convergence (a predictor too far from the solution, a stale matrix) shrink when the
//! step is shortened: the predictor's error falls as `h^(k+1)`. Increments that are rounding do neither.
//! Two cases measured before this floor existed, both with a matrix evaluated at the attempt's own
//! predictor:
//!
//! - **a singular position** (the IFToMM double four-bar, `models/benchmarks/double_four_bar.toml`, as its
//!   links come into line at t ≈ 0.714 s): at t = 0.7116 s the constraint Jacobian's smallest singular
//!   value has fallen to 4.6e-3 (largest 2.5). The velocity constraints' rounding, a few 1e-15 m/s, comes
//!   back from the solve divided by it in the velocities (about 2e-12 m/s) and by its square in the
//!   multipliers' impulses (`c Δλ` about 5e-10 N s): increments of 0.06 to 0.3 of the attempt's share of
//!   the tolerance (rtol = atol = 1e-12) against a Newton tolerance of 2.2e-3, rates of 0.3 to 1.5, the
//!   same at every step size from 4.5e-12 s down to 3.5e-14 s, where the BDF gave up;
//! - **large forces** (the hanging chain of 1024 rods at rtol 3e-10, t = 0.0997 s): the second increment
//!   stays at 2e-3 to 8e-3 of a tolerance at every step size from 5e-5 s to 4e-16 s, at rates of 0.7 to 1,
//!   in a velocity near the top and the multipliers of about 1e4 N, whose rounding per unit mass is
//!   ε × 1e4 ≈ 2e-12.
//!
//! Hence: when an attempt's iteration fails with a fresh matrix and the attempt at half the step fails
//! too, again with a fresh matrix, with its increments after the first no smaller than
//! [`STALL_RATIO`] of those of the longer step, the increments are rounding. Their level (the smallest
//! increment after the first, in tolerances) times [`FLOOR_MARGIN`] becomes the floor: an increment at or
//! below it has converged whatever its rate, as one below `1e-4` of the tolerance always has. The floor is
//! kept while iterations end at it and decays by [`FLOOR_DECAY`] for every step whose iteration converges
//! without it. Only increments below [`NOISE_CEILING`] of the solution, and below [`CHANGE_RATIO`] of the
//! step's own change of the solution, can be rounding.
//!
//! The second bound tells rounding from a motion that runs away (the flexible beam spun up past its
//! limits, crates/flexmb-cli/tests/commands/physics_watchdog.rs, at rtol 1e-6): its iterations fail at every step
//! size too, with increments of 1e-12 to 1e-9 of the solution, under the first bound, and pairs of them
//! stalled within [`STALL_RATIO`]. But they are what remains of a correction, and the step's change of the
//! solution (predictor minus last solution, in tolerances) shrinks with the step as they do: the stalled
//! increments were 2.5e-5 to 1.7 of it at the 70 pairs that passed as rounding. The rounding of the residual
//! is at the level of the solution's last digits, which a step moves by many of them: 1.2e-7 to 1.4e-6 of
//! the change at the double four-bar's floors (h = 6e-7 to 3e-5 s at rtol 1e-12).

/// An increment after the first that has not fallen below this fraction of the one of the attempt at
/// twice the step size has not shrunk with the step: a failing iteration's increments fall at least
/// eightfold when the step is halved (the predictor's error as `h^(k+1)`, `k ≥ 2`, and the rate with it).
const STALL_RATIO: f64 = 0.25;
/// The floor is this many times the level of the stalled increments: rounding scatters about its level
/// (the four-bar's increments by a factor of 4 between attempts).
const FLOOR_MARGIN: f64 = 4.0;
/// Factor of the floor for each step whose iteration converges without it.
const FLOOR_DECAY: f64 = 0.5;
/// Only increments below this fraction of the solution (in the error weights `atol + rtol |y|`, i.e.
/// `rtol` times the level in tolerances) can be rounding: 4.5e6 units of rounding. The four-bar's were
/// 5e-12 to 2e-11 up to 1 ms before its singular position, the chain's 2e-12; with 1e-8 a flexible beam
/// spun up past its limits (crates/flexmb-cli/tests/commands/physics_watchdog.rs), whose iteration fails because
/// the motion runs away, passed steps at 1e-8 as rounding.
pub(crate) const NOISE_CEILING: f64 = 1e-9;
/// Only increments below this fraction of the step's change of the solution can be rounding: the double
/// four-bar's were at most 1.4e-6 of it, a runaway's at least 2.5e-5 (see the module documentation).
pub(crate) const CHANGE_RATIO: f64 = 1e-5;

/// The rounding floor of the Newton increments of one integrator (see the module documentation); all
/// levels are weighted norms in tolerances (the error weights `atol + rtol |y|`), not in a step's share.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct RoundingFloor {
    /// Increments at or below this level have converged whatever their rate (0: no floor).
    pub floor: f64,
    /// The level of the stalled increments of the last attempt of this step whose iteration failed with a
    /// fresh matrix (0: none since the last accepted step).
    stalled: f64,
}

impl RoundingFloor {
    /// The floor as a fraction of a step's `share` of the tolerance, the measure of the convergence test.
    pub fn in_share(&self, share: f64) -> f64 {
        self.floor / share
    }

    /// The iteration of an attempt failed with a matrix evaluated at its own predictor, its increments
    /// after the first no smaller than `stalled` (in tolerances; infinite when it failed before a second
    /// one), and `change` the weighted norm of the step's change of the solution, predictor minus last
    /// solution, in tolerances (infinite for a method that does not measure it: generalized-α). True when
    /// they are rounding: an attempt at a step at least twice as long failed the same way at a level not
    /// [`STALL_RATIO`] above it. The floor is then raised to [`FLOOR_MARGIN`] times the larger of the two
    /// levels, and the attempt may be repeated as it is.
    pub fn failed_with_fresh_matrix(&mut self, stalled: f64, change: f64, rtol: f64) -> bool {
        if !stalled.is_finite() || stalled * rtol > NOISE_CEILING || stalled > CHANGE_RATIO * change {
            self.stalled = 0.0;
            return false;
        }
        let previous = std::mem::replace(&mut self.stalled, stalled);
        if previous > 0.0 && stalled >= STALL_RATIO * previous {
            let floor = FLOOR_MARGIN * stalled.max(previous);
            if floor > self.floor {
                self.floor = floor;
                return true;
            }
        }
        false
    }

    /// Whether a local error estimate of `error` tolerances is within the floor: the corrector's solution
    /// is resolved no finer, so the estimate, a difference of it and the predictor, is its rounding as much
    /// as it is error, and a shorter step would not make it smaller.
    pub fn covers(&self, error: f64) -> bool {
        error <= self.floor
    }

    /// A step was accepted; `at_floor` when its iteration converged by the floor rather than by its rate.
    pub fn accepted(&mut self, at_floor: bool) {
        self.stalled = 0.0;
        if !at_floor {
            self.floor *= FLOOR_DECAY;
        }
    }

    /// The state to store in a checkpoint.
    pub fn stored(&self) -> [f64; 2] {
        [self.floor, self.stalled]
    }

    /// The floor stored in a checkpoint by [`stored`](Self::stored).
    pub fn restored(stored: [f64; 2]) -> Self {
        Self { floor: stored[0], stalled: stored[1] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Increments that do not shrink when the step is halved are rounding and raise the floor to
    /// `FLOOR_MARGIN` times their level; increments that shrink eightfold are a convergence failure and
    /// leave it; one failure alone says nothing.
    #[test]
    fn increments_that_do_not_shrink_with_the_step_raise_the_floor() {
        let mut floor = RoundingFloor::default();
        assert!(!floor.failed_with_fresh_matrix(0.06, f64::INFINITY, 1e-12), "one failure alone");
        assert!(floor.failed_with_fresh_matrix(0.05, f64::INFINITY, 1e-12), "the four-bar: 0.06 then 0.05");
        assert_eq!(floor.floor, FLOOR_MARGIN * 0.06);
        assert_eq!(floor.in_share(0.5), 2.0 * FLOOR_MARGIN * 0.06);
        floor.accepted(true);
        assert_eq!(floor.floor, FLOOR_MARGIN * 0.06, "kept while iterations end at it");
        floor.accepted(false);
        assert_eq!(floor.floor, FLOOR_DECAY * FLOOR_MARGIN * 0.06);

        let mut floor = RoundingFloor::default();
        assert!(!floor.failed_with_fresh_matrix(0.8, f64::INFINITY, 1e-6));
        assert!(!floor.failed_with_fresh_matrix(0.1, f64::INFINITY, 1e-6), "fell eightfold with the step: not rounding");
        assert_eq!(floor.floor, 0.0);
    }

    /// Large increments are never rounding, however little they shrink, nor is an iteration that failed
    /// before its second increment; an acceptance forgets the failures of its step.
    #[test]
    fn large_or_missing_increments_are_not_rounding() {
        let mut floor = RoundingFloor::default();
        assert!(!floor.failed_with_fresh_matrix(0.5, f64::INFINITY, 1e-6));
        assert!(!floor.failed_with_fresh_matrix(0.5, f64::INFINITY, 1e-6), "5e-7 of the solution is not rounding");
        let mut floor = RoundingFloor::default();
        assert!(!floor.failed_with_fresh_matrix(f64::INFINITY, f64::INFINITY, 1e-12));
        assert!(!floor.failed_with_fresh_matrix(0.1, f64::INFINITY, 1e-12));
        floor.accepted(false);
        assert!(!floor.failed_with_fresh_matrix(0.1, f64::INFINITY, 1e-12), "the failure of an earlier step is forgotten");
        assert_eq!(RoundingFloor::restored(floor.stored()), floor);
    }

    /// Increments that are a sizeable fraction of the step's change of the solution are what remains of a
    /// correction, not rounding, however little they shrink: the spun-up beam's (7.2e-4 and 4.0e-4
    /// tolerances at rtol 1e-6, changes of 12 and 25), against the double four-bar's (2.7 and 2.8
    /// tolerances at rtol 1e-12, changes of 2.4e6 and 3.3e7).
    #[test]
    fn increments_large_against_the_step_change_are_not_rounding() {
        let mut floor = RoundingFloor::default();
        assert!(!floor.failed_with_fresh_matrix(4.0e-4, 25.0, 1e-6));
        assert!(!floor.failed_with_fresh_matrix(7.2e-4, 12.0, 1e-6), "the runaway: 6e-5 of the change");
        assert_eq!(floor.floor, 0.0);
        assert!(!floor.failed_with_fresh_matrix(2.8, 3.3e7, 1e-12));
        assert!(floor.failed_with_fresh_matrix(2.7, 2.4e6, 1e-12), "the four-bar: 1.1e-6 of the change");
        assert_eq!(floor.floor, FLOOR_MARGIN * 2.8);
    }
}
