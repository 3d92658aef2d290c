//! The convergence test of the simplified Newton iterations of the implicit methods (the BDF and the
//! generalized-α method): the rate-based test of Shampine (Hairer and Wanner, *Solving Ordinary
//! Differential Equations II*, section IV.8), with an absolute test for increments lost in round-off.

/// What an iteration does with its increment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// The iteration does not converge in the iterations left: drop the increment and fail.
    Diverging,
    /// Apply the increment and iterate again.
    Continue,
    /// Apply the increment; the iteration has converged.
    Converged,
}

/// Below this fraction of the tolerance an increment is round-off: IDA's test (`PT0001 * toldel`).
const NEGLIGIBLE: f64 = 1e-4;

/// The test over the iterations of one Newton solve.
pub(crate) struct ConvergenceTest {
    tolerance: f64,
    max_iterations: usize,
    last: Option<f64>,
    /// The slowest contraction rate `‖Δₖ‖ / ‖Δₖ₋₁‖` seen so far.
    pub slowest: f64,
}

impl ConvergenceTest {
    pub fn new(tolerance: f64, max_iterations: usize) -> Self {
        Self { tolerance, max_iterations, last: None, slowest: 0.0 }
    }

    /// The verdict on the weighted norm of the increment of iteration `k` (from 0). With the rate
    /// `ρ = ‖Δₖ‖ / ‖Δₖ₋₁‖` it converges when `ρ/(1 − ρ) ‖Δₖ‖ < tol` (the error left) and diverges when
    /// `ρ ≥ 1` or when the iterations left cannot bring the error below the tolerance. A second
    /// increment as small as `1e-4 tol` has converged whatever the rate: at that level the increments
    /// are round-off that does not shrink, and their ratio, about 1, says nothing (a body at rest on a
    /// fixed joint failed every step, down to h = 1e-307, with increments of 4e-8 of the tolerance).
    pub fn assess(&mut self, k: usize, norm: f64) -> Verdict {
        if norm == 0.0 || (k > 0 && norm <= NEGLIGIBLE * self.tolerance) {
            return Verdict::Converged;
        }
        let rate = self.last.map(|old| norm / old);
        self.last = Some(norm);
        let Some(rate) = rate else {
            return Verdict::Continue;
        };
        let left = self.max_iterations.saturating_sub(k) as i32;
        if rate >= 1.0 || rate.powi(left) / (1.0 - rate) * norm > self.tolerance {
            return Verdict::Diverging;
        }
        self.slowest = self.slowest.max(rate);
        if rate / (1.0 - rate) * norm < self.tolerance {
            Verdict::Converged
        } else {
            Verdict::Continue
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contracting_iterations_converge_and_growing_ones_diverge() {
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 1e-1), Verdict::Continue);
        assert_eq!(test.assess(1, 1e-3), Verdict::Converged, "rate 0.01: error left 1e-5");
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 1e-1), Verdict::Continue);
        assert_eq!(test.assess(1, 2e-1), Verdict::Diverging);
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 0.0), Verdict::Converged);
    }

    #[test]
    fn round_off_increments_converge_whatever_their_ratio() {
        // The fixed body at rest: 3.7e-11 then 4.6e-11 against a tolerance of 1e-3.
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 3.7e-11), Verdict::Continue, "one increment says nothing of the rate");
        assert_eq!(test.assess(1, 4.6e-11), Verdict::Converged);
        // Above 1e-4 of the tolerance a growing increment still diverges.
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 1e-7), Verdict::Continue);
        assert_eq!(test.assess(1, 2e-7), Verdict::Diverging);
    }
}
