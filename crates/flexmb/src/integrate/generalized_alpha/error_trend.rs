//! The trend of the local error estimates, by which the generalized-α method chooses its next step for
//! where the motion will be rather than where its estimate saw it (a predictive step-size controller, in
//! the spirit of Gustafsson's, 1994).
//!
//! The estimate of a step measures the motion behind the step it chooses: its velocity part takes the
//! accelerations' curvature over the step and the two before it, so the steps follow the motion about two
//! steps late. In a conservative mechanism that lag is what makes the method's energy drift. A step-size
//! change moves the O(h²) offset between the method's conserved quantity and the energy (the trapezoidal
//! rule, `ρ∞ = 1`, conserves `E + h²/12 H''(f, f) + …` where the energy is quadratic), and steps that shrink
//! and grow with the motion pump energy in proportion to the area the pair (offset, h²) encloses over a
//! cycle: zero for steps that are a function of the state alone, not zero for steps that lag it. On the
//! IFToMM double four-bar (10 s, five cycles) at rtol 1e-3 the lagging steps lost 7.5e-4 J a cycle and
//! put B0 10.1 tolerances off its exact path, while a fixed step with as many steps (2,326, 4.3e-3 s) was
//! 1.9 tolerances off; the same fixed step varied by ±30 % with a period of 1 s, correlated with the
//! motion, 14 tolerances off with any `ρ∞` (0.8 or 1), varied with periods of 0.2 s or 0.05 s not at all.
//! Extrapolating the estimate two steps ahead along its trend removes most of the lag: B0 6.6 tolerances
//! off in 2,316 steps with the trend forgotten near the ten singular positions, 4.8 followed through
//! them (which at rtol 1e-7 ran the steps into the second position: not kept); docs/accuracy.md,
//! *Generalized-α's steps lagging the motion*.
//!
//! The trend is that of the error constant `C = ‖e‖ / h^p` (`p` the power the step selection takes the
//! root of), its logarithm's step-to-step change averaged exponentially with weight
//! [`TREND_WEIGHT`]: the raw change, extrapolated, doubled the estimates' noise and the rejections (the
//! slider-crank at rtol 1e-5: 25,982 rejected steps in 93,322 against 8 in 82,404). The trend is forgotten
//! near singular positions, where an estimate may not measure the truncation error (within the rounding)
//! and the steps follow the conditioning; after a rejected step it is not used to grow the step.

/// How many steps ahead the estimate is extrapolated: the lag of its velocity part (the accelerations'
/// curvature over the step and the two before it). On the double four-bar at rtol 1e-3 (B0 against its
/// exact path, tolerances): 1 step 7.3, 2 steps 3.3 (raw trend) and 4.8 (averaged; 6.6 forgotten near the
/// singular positions, as kept), 3 steps (raw) stopped the run at 5.1 s, the extrapolation amplifying the
/// estimates' noise.
const STEPS_AHEAD: f64 = 2.0;
/// Weight of the latest change of `ln C` in its exponential average.
const TREND_WEIGHT: f64 = 0.3;

/// The last error constant and the averaged trend of its logarithm per step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ErrorTrend {
    /// `‖e‖ / h^p` of the last step whose estimate measured the truncation error (0: none).
    constant: f64,
    /// The exponential average of `ln(C_n / C_{n−1})`.
    slope: f64,
}

impl ErrorTrend {
    /// The estimate `error_norm` of an accepted step of size `h` (error power `power`), extrapolated
    /// [`STEPS_AHEAD`] steps along the trend, which it then joins.
    pub fn predicted(&mut self, error_norm: f64, h: f64, power: f64) -> f64 {
        let constant = error_norm / h.powf(power);
        if !(constant > 0.0 && constant.is_finite()) {
            *self = Self::default();
            return error_norm;
        }
        if self.constant > 0.0 {
            self.slope = (1.0 - TREND_WEIGHT) * self.slope + TREND_WEIGHT * (constant / self.constant).ln();
        }
        self.constant = constant;
        error_norm * (STEPS_AHEAD * self.slope).exp()
    }

    /// Forgets the trend: the last estimate did not measure the truncation error, or the steps followed a
    /// singular position's conditioning rather than the motion.
    pub fn forget(&mut self) {
        *self = Self::default();
    }

    /// The state for a checkpoint.
    pub fn stored(&self) -> [f64; 2] {
        [self.constant, self.slope]
    }

    /// The state of a checkpoint (`[0, 0]` from one written before the trend was kept: none).
    pub fn restored(stored: [f64; 2]) -> Self {
        Self { constant: stored[0], slope: stored[1] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_constant_growing_steadily_is_extrapolated_two_steps_ahead() {
        let mut trend = ErrorTrend::default();
        let (h, power) = (1e-3, 2.0);
        // The first estimate has no trend; then C grows by 10 % a step.
        assert_eq!(trend.predicted(0.5, h, power), 0.5);
        let mut predicted = 0.0;
        for k in 1..60 {
            predicted = trend.predicted(0.5 * 1.1_f64.powi(k), h, power);
        }
        let last = 0.5 * 1.1_f64.powi(59);
        // The averaged trend has converged to ln 1.1 per step.
        assert!((predicted / last - 1.1_f64.powi(2)).abs() < 1e-9, "{predicted} {last}");
        // A constant C has no trend, whatever the step sizes.
        let mut steady = ErrorTrend::default();
        for k in 0..40 {
            let h = 1e-3 * (1.0 + 0.01 * k as f64);
            let e = 0.7 * (h / 1e-3).powf(power);
            assert!((steady.predicted(e, h, power) / e - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_forgotten_trend_starts_again_and_a_checkpoint_keeps_it() {
        let mut trend = ErrorTrend::default();
        trend.predicted(0.5, 1e-3, 2.0);
        trend.predicted(1.0, 1e-3, 2.0);
        let copy = ErrorTrend::restored(trend.stored());
        assert_eq!(copy, trend);
        trend.forget();
        assert_eq!(trend.predicted(0.8, 1e-3, 2.0), 0.8);
        // A zero estimate says nothing of the trend.
        let mut zero = copy;
        assert_eq!(zero.predicted(0.0, 1e-3, 2.0), 0.0);
        assert_eq!(zero, ErrorTrend::default());
    }
}
