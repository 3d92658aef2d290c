//! Convergence-rate monitoring of the simplified Newton iterations across steps, as DASSL and IDA keep
//! their rate estimate from step to step: the rate of the last converged iteration, extrapolated to the
//! next step, says before iterating whether the reused iteration matrix will still converge, so that it
//! is re-evaluated ahead of a failure instead of after one.
//!
//! Why the rate is extrapolated in time: a reused iteration matrix goes stale because its entries turn
//! with the bodies (a joint's constraint rows `B(q)`, the kinematic rows `ṗ = ½ Gᵀ(p) ω̄`, a spring's
//! `k u uᵀ`), so the contraction rate of the chord iteration grows about in proportion to the angle
//! turned since the matrix was evaluated, i.e. to the time elapsed. Measured with the BDF at
//! `rtol = 1e-6`, median rates at 1, 2, 3, 5 steps after the Jacobian: slider-crank 0.054, 0.12, 0.17,
//! 0.23; chain of four rods 0.047, 0.10, 0.14, 0.21; a Jacobian evaluated at the step's own predictor
//! contracts by 1e-7 to 1e-6. The iteration fails once `ρ` reaches about 0.15: the rate test
//! ([`ConvergenceTest`](super::newton::ConvergenceTest)) then finds that the iterations left cannot bring
//! the first increment, about one error tolerance, below the Newton tolerance.

/// The margin on the extrapolated rate: rates spread about it (the 90th percentile is 1.5 to 2 times
/// the median at the same age), and a re-evaluation a step early costs less than a failure, which costs
/// the same re-evaluation plus the iterations wasted.
/// 2 rather than 1.5: on the chain of 64 rods at rtol 3e-10, 630 Newton failures in 13067 steps against
/// 771 in 13141, for 9 % more residual evaluations (still 8 % fewer than before the monitoring).
const RATE_MARGIN: f64 = 2.0;
/// Most re-evaluations without a measurement of their own that a measurement outlives after failures.
const MOST_PATIENCE: u32 = 63;
/// The age limit ([`RateMonitor::age_limit`]) is this fraction of the age at which a reused matrix failed.
const AGE_MARGIN: f64 = 0.7;
/// Growth of the age limit with each matrix re-evaluated at it, so that it follows a motion that slows
/// and forgets a failure at a small age: a failure about every 5 re-evaluations where it holds.
const AGE_GROWTH: f64 = 1.1;
/// Steps after the evaluation from which a failed reuse teaches an age limit.
const AGE_STEPS: f64 = 5.0;
/// Steps after the evaluation up to which a failed reuse teaches an age limit: a matrix that served this
/// long fails rarely, and a limit would only re-evaluate it early (the flexible pendulum of
/// models/flexible_pendulum.toml, whose Jacobians serve about 130 steps, took 22 % more steps with one).
const MOST_AGE_STEPS: f64 = 50.0;

/// What the last converged iteration measured away from its matrix's state said of the convergence.
///
/// The growth of the rate in time is a property of the motion (how fast the bodies turn), not of one
/// matrix, so it is kept across a re-evaluation: the first step after one is predicted from the rate
/// measured with the matrix before (on a fast top, 0.07 to 0.13 one step after the Jacobian at
/// `rtol = 3e-8`). It is forgotten at the second re-evaluation without a measurement of its own, so that
/// a measurement from a transient long past (or at a tiny step) does not re-evaluate every step ever after:
/// the matrix after that is reused, and measured, whatever it predicts. An iteration that fails with a
/// reused matrix is a measurement too, and doubles (plus one) the re-evaluations its measurement outlives,
/// so that where reuse keeps failing (a driven mechanism whose matrix is stale after one step) it is tried
/// ever more rarely; a converged reuse halves that. Halves, not resets: where a stiff element turns with
/// the bodies (the springs of the IFToMM A05 flyball governor spin with its shaft) a matrix one step old
/// fails at most steps but converges now and then, slowly, and with a reset each such convergence began
/// the cycle of failures again (the BDF at rtol 1e-6: 63 Newton failures in 1,174 steps, 28 in 1,163
/// with the halving, for 8 % more residual evaluations).
/// It travels with a checkpoint, so that a resumed run re-evaluates where the uninterrupted one does.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RateMonitor {
    /// Time of the state the matrix's derivative parts were evaluated at (`None`: no matrix yet).
    pub evaluated_at: Option<f64>,
    /// The slowest contraction rate of the last converged iteration measured away from its matrix's state
    /// (0 when none was measured yet).
    pub rate: f64,
    /// Time from that matrix's evaluation to the step at which `rate` was measured.
    pub elapsed: f64,
    /// Time of the state that matrix was evaluated at.
    pub measured_with: Option<f64>,
    /// The weighted norm of the first increment of that iteration (the predictor's distance from the
    /// solution).
    pub first_increment: f64,
    /// Re-evaluations without a measurement of their own that the measurement outlives (0 until a
    /// reuse fails).
    #[serde(default)]
    pub patience: u32,
    /// Re-evaluations without a measurement of their own since the measurement.
    #[serde(default)]
    pub unmeasured: u32,
    /// The age (time since the evaluation) beyond which a matrix is expected to fail whatever its rate
    /// says: 0.7 of the age at which a reused matrix last failed 5 to 50 steps after its evaluation, grown
    /// by 10 % with each re-evaluation at it (0: none learnt; learnt by the BDF only).
    #[serde(default)]
    pub age_limit: f64,
}

impl RateMonitor {
    /// The matrix's derivative parts were evaluated at the state of time `t`.
    pub(crate) fn evaluated(&mut self, t: f64) {
        if let Some(t0) = self.evaluated_at {
            if self.age_limit > 0.0 && (t - t0).abs() >= self.age_limit {
                self.age_limit *= AGE_GROWTH;
            }
        }
        if self.measured_with != self.evaluated_at {
            self.unmeasured += 1;
            if self.unmeasured > self.patience {
                self.rate = 0.0;
                self.elapsed = 0.0;
            }
        }
        self.evaluated_at = Some(t);
    }

    /// An iteration with the matrix at the step to `t` failed, its slowest rate `rate` (at least 1 when it
    /// diverged) from a first increment of weighted norm `first_increment`.
    pub(crate) fn failed(&mut self, t: f64, rate: f64, first_increment: f64) {
        let Some(t0) = self.evaluated_at else { return };
        let elapsed = (t - t0).abs();
        if elapsed > 0.0 {
            self.record(t0, rate, elapsed, first_increment);
            self.patience = (2 * self.patience + 1).min(MOST_PATIENCE);
        }
    }

    fn record(&mut self, t0: f64, rate: f64, elapsed: f64, first_increment: f64) {
        self.rate = rate;
        self.elapsed = elapsed;
        self.first_increment = first_increment;
        self.measured_with = Some(t0);
        self.unmeasured = 0;
    }

    /// An iteration with the matrix at the step to `t` failed, the matrix evaluated at another state: the
    /// age limit is learnt from it. The rate of a converged iteration is that of its first two or three
    /// increments, which the well-resolved motions dominate; a slow motion the stale matrix resolves
    /// badly shows only in later ones (the spinning top at rtol 1e-7: converged rates of 0.05 to 0.14, then
    /// failures about 11 steps after the Jacobian, rates climbing from 0.1 to 0.5–0.9 over iterations 3
    /// to 5, while the extrapolated rate predicted 0.09 to 0.28).
    /// Only a failure [`AGE_STEPS`] to [`MOST_AGE_STEPS`] steps of size `h` after the evaluation teaches a
    /// limit: one
    /// sooner is a transient's (a stale matrix fails within a few steps where the motion changes fast),
    /// and a limit of a few steps would re-evaluate at nearly every step after it (the 3-D slider-crank
    /// at rtol 1e-6: 21 % more residual evaluations for 12 Newton failures instead of 10).
    pub(crate) fn reuse_failed(&mut self, t: f64, h: f64) {
        if let Some(t0) = self.evaluated_at {
            let age = (t - t0).abs();
            if (AGE_STEPS * h..=MOST_AGE_STEPS * h).contains(&age) {
                self.age_limit = AGE_MARGIN * age;
            }
        }
    }

    /// An iteration at the step to `t` converged with slowest rate `rate` from a first increment of
    /// weighted norm `first_increment`.
    pub(crate) fn converged(&mut self, t: f64, rate: f64, first_increment: f64) {
        let Some(t0) = self.evaluated_at else { return };
        let elapsed = (t - t0).abs();
        if elapsed > 0.0 {
            self.record(t0, rate, elapsed, first_increment);
            self.patience /= 2;
        }
    }

    /// The rate expected at the step to `t`: the last measured one grown in proportion to the time
    /// elapsed since the evaluation, times [`RATE_MARGIN`]; 0 when nothing was measured.
    pub(crate) fn expected_rate(&self, t: f64) -> f64 {
        match self.evaluated_at {
            Some(t0) if self.elapsed > 0.0 => RATE_MARGIN * self.rate * (t - t0).abs() / self.elapsed,
            _ => 0.0,
        }
    }

    /// Whether an iteration at the step to `t`, tested for `tolerance` in at most `max_iterations`
    /// iterations, is expected to fail with this matrix: with rate `ρ` the increment of iteration `k` is
    /// `ρᵏ δ₀`, and the rate test gives up at the first `k ≥ 1` where even the iterations left cannot
    /// bring the error `ρ/(1 − ρ) ρ^(m−1) δ₀` below the tolerance, i.e. when `ρᵐ δ₀ / (1 − ρ) > tolerance`.
    /// A matrix older than the age limit is expected to fail whatever the rate says.
    pub(crate) fn expects_failure(&self, t: f64, tolerance: f64, max_iterations: usize) -> bool {
        if let Some(t0) = self.evaluated_at {
            if self.age_limit > 0.0 && (t - t0).abs() > self.age_limit {
                return true;
            }
        }
        let rho = self.expected_rate(t);
        if rho == 0.0 {
            return false;
        }
        rho >= 1.0 || rho.powi(max_iterations as i32) * self.first_increment / (1.0 - rho) > tolerance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::newton::{ConvergenceTest, Verdict};

    /// The prediction agrees with the rate test it anticipates: an iteration contracting exactly at the
    /// expected rate (without the margin) fails the test where the monitor said it would, and converges
    /// where it said it would not fail.
    #[test]
    fn expected_failures_are_those_of_the_rate_test() {
        let (tolerance, max_iterations, first) = (1e-3, 4, 1.0);
        for rate in [0.05, 0.1, 0.14, 0.16, 0.2, 0.3] {
            let mut monitor = RateMonitor::default();
            monitor.evaluated(0.0);
            monitor.converged(1.0, rate / RATE_MARGIN, first);
            let predicted = monitor.expects_failure(1.0, tolerance, max_iterations);
            let mut test = ConvergenceTest::new(tolerance, max_iterations);
            let mut verdict = Verdict::Continue;
            for k in 0..max_iterations {
                verdict = test.assess(k, first * rate.powi(k as i32));
                if verdict != Verdict::Continue {
                    break;
                }
            }
            assert_eq!(predicted, verdict != Verdict::Converged, "rate {rate}: {verdict:?}");
        }
    }

    /// The rate grows in proportion to the time since the evaluation: twice the time, twice the rate (with
    /// the margin), also for the next matrix; a rate measured at the evaluation's own state predicts
    /// nothing, and before any measurement nothing is expected to fail.
    #[test]
    fn the_rate_is_extrapolated_in_the_time_since_the_evaluation() {
        let mut monitor = RateMonitor::default();
        monitor.evaluated(2.0);
        monitor.converged(2.0, 1e-7, 1.0);
        assert_eq!(monitor.expected_rate(2.5), 0.0);
        assert!(!monitor.expects_failure(3.0, 1e-3, 4));
        monitor.converged(2.1, 0.05, 1.0);
        assert!((monitor.expected_rate(2.2) - RATE_MARGIN * 0.1).abs() < 1e-12);
        monitor.evaluated(2.2);
        monitor.converged(2.2, 1e-7, 1.0);
        assert!((monitor.expected_rate(2.25) - RATE_MARGIN * 0.025).abs() < 1e-12);
        assert!(monitor.expects_failure(2.6, 1e-3, 4));
        // A second evaluation without a measurement in between forgets it.
        monitor.evaluated(2.3);
        assert_eq!(monitor.expected_rate(2.35), 0.0);
        // A failed reuse is a measurement, which then outlives one re-evaluation more; a converged one
        // halves that.
        monitor.evaluated(2.4);
        monitor.failed(2.5, 1.0, 1.0);
        assert_eq!(monitor.patience, 1);
        monitor.evaluated(2.5);
        monitor.evaluated(2.6);
        assert!(monitor.expects_failure(2.65, 1e-3, 4));
        monitor.evaluated(2.7);
        assert_eq!(monitor.expected_rate(2.9), 0.0);
        monitor.converged(2.95, 0.01, 1.0);
        assert_eq!(monitor.patience, 0);
        // Three failed reuses in a row outlive 7 re-evaluations; a converged reuse then leaves 3.
        for t in [3.0, 3.1, 3.2] {
            monitor.evaluated(t);
            monitor.failed(t + 0.05, 1.0, 1.0);
        }
        assert_eq!(monitor.patience, 7);
        monitor.converged(3.26, 0.3, 1.0);
        assert_eq!(monitor.patience, 3);
    }

    /// A reuse that failed at an age teaches that matrices fail from about that age on, whatever their
    /// measured rate: the limit is `AGE_MARGIN` of it, and grows by `AGE_GROWTH` with each re-evaluation
    /// it causes.
    #[test]
    fn a_failed_reuse_limits_the_age_of_the_next_matrices() {
        let mut monitor = RateMonitor::default();
        monitor.evaluated(1.0);
        monitor.converged(1.001, 1e-3, 1.0);
        assert!(!monitor.expects_failure(1.011, 1e-3, 7), "the rate alone predicts convergence");
        monitor.reuse_failed(1.011, 1e-3);
        assert!((monitor.age_limit - AGE_MARGIN * 0.011).abs() < 1e-15);
        monitor.evaluated(1.011);
        let limit = monitor.age_limit;
        assert!((limit - AGE_GROWTH * AGE_MARGIN * 0.011).abs() < 1e-15, "re-evaluated beyond it: grown");
        monitor.converged(1.012, 1e-3, 1.0);
        assert!(!monitor.expects_failure(1.011 + 0.99 * limit, 1e-3, 7));
        assert!(monitor.expects_failure(1.011 + 1.01 * limit, 1e-3, 7));
        monitor.evaluated(1.011 + 1.01 * limit);
        assert!((monitor.age_limit - AGE_GROWTH * limit).abs() < 1e-15);
        assert_eq!(RateMonitor::default().age_limit, 0.0, "nothing learnt, no limit");
        // A failure within a few steps of the evaluation is a transient's: nothing learnt.
        let mut monitor = RateMonitor::default();
        monitor.evaluated(1.0);
        monitor.reuse_failed(1.004, 1e-3);
        assert_eq!(monitor.age_limit, 0.0);
        monitor.reuse_failed(1.06, 1e-3);
        assert_eq!(monitor.age_limit, 0.0, "nor from one after many steps");
    }
}
