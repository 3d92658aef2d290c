//! The BDF's fixed floor under a step's share of the tolerance, made of the error estimate's measured
//! noise.
//!
//! Where the share is so small that the Newton iteration stops at its floor
//! ([`BDF_NEWTON_FLOOR`](super::share_floor::BDF_NEWTON_FLOOR)), what the iteration leaves in the
//! accepted states is what the error estimates' noise is made of: the estimate is built from the
//! corrections, and the predictor carries the leftovers of the last `k + 1` states into it. One Newton
//! iteration more there (`Bdf::polish`, away from singular positions) applies that leftover and measures
//! it; its RMS times the gain by which the predictor carries it into the estimate is the noise, and
//! [`NOISE_MARGIN`] times it, within [`LOWEST_FLOOR`] … [`FINE_STEP_FLOOR`], the floor under the next
//! step's share. Where it was not measured (a step not polished: a share the fixed floor cannot hold, a
//! run whose held steps cannot yet spend a tenth of its tolerance, a singular position near; `Bdf::polishes`),
//! the floor is [`FINE_STEP_FLOOR`], as before the measurement.
//!
//! Measured (`python3 docs/accuracy/work_precision.py --integrators bdf --tolerance-span run`, medians
//! over rtol × 0.97 … 1.03, before → after): the 3-D slider-crank at 1e-9 6.2 → 4.8 tolerances, at 1e-10
//! 61 → 26 (23,400 → 29,500 steps); the heavy top 0.14 → 0.06 and 1.33 → 0.40 (32,800 → 41,000 steps);
//! the flyball governor at 1e-10 6.8 → 1.6; every row from 1e-3 to 1e-8 of the benchmarks unchanged; the
//! double four-bar without stops at 1e-9 … 1e-12 (21 runs each) and its spreads as before
//! (docs/accuracy.md, *The floor as the estimate's measured noise, kept*). A smaller margin and lowest
//! floor (1 and 5e-15) took the slider-crank at 1e-10 to 16 tolerances but stopped 6 of 7 of the double
//! four-bar's runs at 1e-9 and all at 1e-10, between its positions.

use crate::integrate::share_floor::FINE_STEP_FLOOR;

/// The floor as a multiple of the measured noise.
const NOISE_MARGIN: f64 = 3.0;
/// The lowest fixed floor, relative to the solution.
const LOWEST_FLOOR: f64 = 1.5e-14;
/// Factor of the measured noise level per accepted step.
const NOISE_LEVEL_DECAY: f64 = 0.9;

/// The measured noise of the BDF's error estimate and the fixed floor it makes (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct NoiseFloor {
    /// The estimate's noise relative to the solution, the largest of the last steps' measurements
    /// decayed by [`NOISE_LEVEL_DECAY`] per step; `None` since a step that did not measure it.
    pub level: Option<f64>,
}

impl NoiseFloor {
    /// The fixed floor for the next step, relative to the solution.
    pub fn floor(&self) -> f64 {
        self.level.map_or(FINE_STEP_FLOOR, |level| (NOISE_MARGIN * level).clamp(LOWEST_FLOOR, FINE_STEP_FLOOR))
    }

    /// A step was accepted, its estimate's noise measured as `noise` (relative to the solution), or not.
    pub fn accepted(&mut self, noise: Option<f64>) {
        self.level = noise.map(|noise| self.level.map_or(noise, |level| noise.max(NOISE_LEVEL_DECAY * level)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Unmeasured, the floor is the fine step floor; measured, three times the noise within the bounds.
    #[test]
    fn the_floor_is_three_times_the_measured_noise_within_its_bounds() {
        let mut noise = NoiseFloor::default();
        assert_eq!(noise.floor(), FINE_STEP_FLOOR);
        noise.accepted(Some(1e-14));
        assert!((noise.floor() - 3e-14).abs() < 1e-28, "{}", noise.floor());
        noise = NoiseFloor::default();
        noise.accepted(Some(1e-16));
        assert_eq!(noise.floor(), LOWEST_FLOOR);
        noise.accepted(Some(1e-12));
        assert_eq!(noise.floor(), FINE_STEP_FLOOR);
        noise.accepted(None);
        assert_eq!((noise.level, noise.floor()), (None, FINE_STEP_FLOOR), "a step that did not measure it");
    }

    /// A large measurement is forgotten by 0.9 per step, not at once: the floor follows the largest
    /// recent noise.
    #[test]
    fn a_large_measurement_decays_by_a_tenth_per_step() {
        let mut noise = NoiseFloor::default();
        noise.accepted(Some(2e-14));
        for _ in 0..3 {
            noise.accepted(Some(1e-15));
        }
        let expected = 2e-14 * NOISE_LEVEL_DECAY.powi(3);
        assert!((noise.level.unwrap() - expected).abs() < 1e-28, "{:?} against {expected}", noise.level);
        for _ in 0..60 {
            noise.accepted(Some(1e-15));
        }
        assert_eq!(noise.level, Some(1e-15), "decayed below the newest measurement");
    }
}
