//! The BDF's step where the floor under a step's share holds it (error per unit step below rtol 1e-8
//! over a run of thousands of steps, [`share_floor`](super::share_floor)).
//!
//! There the error test holds each local error to the floor, what one step's estimate resolves, not to
//! the step's own share `h / span`, which is smaller; the steps are chosen so that the estimate meets
//! the floor, and the estimate is then resolved only to its noise (about a third of the floor). Of
//! such steps the longest make the error: the 3-D slider-crank over 5 s at rtol 1e-10 took 29,501
//! steps (mean 1.7e-4 s, the longest 3.3e-4 s) and was 2.6e-9 off (26 tolerances); the same run with
//! its steps bounded by `--max-step 2.5e-4` was 1.3e-9 off in 32,447 steps, by `1.8e-4` 6.8e-10 in
//! 37,201, by `1.2e-4` 1.6e-10 in 47,310. Bounding the steps near singular positions only, or away
//! from them only, halved the error; both, a sixteenth. Shortening each step by what its own estimate
//! predicts (the truncation of order `k` meeting the step's share) did not: those estimates are the
//! noise that the floor is there to ignore, and the steps shrank without end where it was trusted
//! further (4 million steps at orders 2 and 3).
//!
//! So the steps the floor holds are bounded by the mean of the steps the estimates chose there over the
//! last [`WINDOW`] selections (at orders from [`LOWEST_ORDER`], away from the rounding that the
//! conditioning amplifies): a step the estimate lets grow above the recent mean is held to it. The mean
//! is of the chosen steps, not of the bounded ones, so it does not shrink by its own bound. Measured
//! over the run at rtol 1e-10 (`docs/accuracy.md`, *The floor's longest steps*): the slider-crank 5.6
//! tolerances in 35,605 steps, the flyball governor 0.14 in 12,188 (1.6 in 10,273).

/// The lowest order whose steps are bounded (the floor holds the smooth motion's steps at orders 4 and
/// 5; a lower order is a start, a restart or a passage).
const LOWEST_ORDER: usize = 4;
/// The number of selections the mean is taken over (an exponential mean; the plain mean of the first
/// ones): about 300 steps at order 5. The run's whole mean took 2.4 times the steps on the flyball
/// governor, whose steps vary along the run.
const WINDOW: f64 = 50.0;

/// The bound on the steps the floor holds (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct FloorStepCap {
    /// The mean of the steps the estimates chose where the floor held them.
    mean_chosen: f64,
    /// The number of those selections.
    selections: f64,
}

impl FloorStepCap {
    /// The step after a selection that chose `h_chosen` at order `order`; `held`: the floor holds the
    /// chosen step and the conditioning does not amplify the rounding.
    pub fn step(&mut self, h_chosen: f64, order: usize, held: bool) -> f64 {
        if !held || order < LOWEST_ORDER {
            return h_chosen;
        }
        self.selections += 1.0;
        self.mean_chosen += (h_chosen - self.mean_chosen) / self.selections.min(WINDOW);
        h_chosen.min(self.mean_chosen)
    }

    /// The state kept in a checkpoint: the mean and the number of selections.
    pub fn stored(&self) -> [f64; 2] {
        [self.mean_chosen, self.selections]
    }

    /// The state of [`stored`](Self::stored) (zeros: none yet).
    pub fn restored(stored: [f64; 2]) -> Self {
        Self { mean_chosen: stored[0], selections: stored[1] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chosen step above the recent mean is held to it, one below stays; the mean is of the chosen
    /// steps and forgets the old ones; where the floor does not hold, or at orders below 4, nothing is
    /// bounded or counted.
    #[test]
    fn a_step_above_the_recent_mean_of_the_chosen_steps_is_held_to_it() {
        let mut c = FloorStepCap::default();
        assert_eq!(c.step(1e-3, 5, true), 1e-3);
        assert!((c.step(3e-3, 5, true) - 2e-3).abs() < 1e-15, "the mean of 1 and 3 ms");
        assert_eq!(c.step(0.5e-3, 5, true), 0.5e-3);
        assert_eq!(c.stored()[1], 3.0);
        assert_eq!(c.step(5e-3, 5, false), 5e-3);
        assert_eq!(c.step(5e-3, 3, true), 5e-3);
        assert_eq!(c.stored()[1], 3.0);
        // After many selections of 1 ms, one of 10 ms moves the mean by a WINDOW-th of the difference.
        for _ in 0..1000 {
            c.step(1e-3, 5, true);
        }
        let h = c.step(10e-3, 5, true);
        assert!((h - (1e-3 + 9e-3 / WINDOW)).abs() < 1e-12, "{h}");
        assert_eq!(FloorStepCap::restored(c.stored()), c);
    }
}
