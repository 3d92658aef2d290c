//! The simplified Newton iteration of the implicit methods (the BDF and the generalized-α method):
//! [`iterate`] drives it (evaluate the residual, check it is finite, solve with the factored iteration
//! matrix, test the increment, apply it), each method supplying its equations as a [`NewtonSystem`];
//! the convergence test is the rate-based test of Shampine (Hairer and Wanner, *Solving Ordinary
//! Differential Equations II*, section IV.8), with an absolute test for increments lost in round-off and
//! a floor for increments that are the rounding of the residual amplified by the iteration matrix
//! ([`RoundingFloor`](super::newton_rounding::RoundingFloor)).

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
    /// The increment of a few units of rounding of the solution, in the test's norm: below it an
    /// increment has converged whatever its rate ([`with_round_off`](Self::with_round_off)).
    round_off: f64,
    max_iterations: usize,
    last: Option<f64>,
    /// The slowest contraction rate `‖Δₖ‖ / ‖Δₖ₋₁‖` seen so far.
    pub slowest: f64,
    /// The weighted norm of the first increment (the predictor's distance from the solution).
    pub first_increment: f64,
    /// The last contraction rate measured, also of an iteration that diverged.
    pub last_rate: f64,
    /// Increments after the first at or below this have converged whatever their rate: the rounding floor
    /// (0: none).
    rounding_floor: f64,
    /// The smallest weighted norm of an increment after the first (infinite before the second).
    pub smallest_after_first: f64,
    /// The iteration converged by the rounding floor, not by its rate.
    pub at_floor: bool,
    /// The contraction rate carried from earlier iterations with the same factors, which lets the first
    /// increment converge on its own (0: none; see [`with_carried_rate`](Self::with_carried_rate)).
    carried_rate: f64,
    /// Increments after the first at or below this have converged whatever their rate: the rounding of
    /// the residual amplified by the iteration matrix, estimated a priori
    /// ([`rounding_level`](super::rounding_level)); `None` before it is estimated (once per iteration,
    /// when first needed).
    rounding_level: Option<f64>,
    /// The iteration converged by the rounding level, not by its rate.
    pub at_level: bool,
}

impl ConvergenceTest {
    pub fn new(tolerance: f64, max_iterations: usize) -> Self {
        Self {
            tolerance,
            max_iterations,
            round_off: 0.0,
            last: None,
            slowest: 0.0,
            first_increment: 0.0,
            last_rate: 0.0,
            rounding_floor: 0.0,
            smallest_after_first: f64::INFINITY,
            at_floor: false,
            carried_rate: 0.0,
            rounding_level: None,
            at_level: false,
        }
    }

    /// Whether the increment of iteration `k` of weighted norm `norm` needs the rounding level to be
    /// judged: one after the first that converges neither outright nor by its rate, while no level is held.
    pub fn needs_rounding_level(&self, k: usize, norm: f64) -> bool {
        if k == 0 || self.rounding_level.is_some() || norm == 0.0 || norm <= (NEGLIGIBLE * self.tolerance).max(self.round_off) {
            return false;
        }
        let rate = self.last.map_or(0.0, |old| norm / old);
        !(rate < 1.0 && rate / (1.0 - rate) * norm < self.tolerance)
    }

    /// This test with the rounding level `level` known from the start (estimated for an earlier
    /// iteration with the same factors; see [`set_rounding_level`](Self::set_rounding_level)).
    pub fn with_rounding_level(mut self, level: Option<f64>) -> Self {
        self.rounding_level = level;
        self
    }

    /// Increments after the first at or below `level` (in the test's norm) have converged whatever their
    /// rate: the rounding of the residual amplified by the iteration matrix. The rate of such an
    /// increment is measured only against a predecessor above the level, one that was a correction.
    pub fn set_rounding_level(&mut self, level: f64) {
        self.rounding_level = Some(level);
    }

    /// This test with the contraction rate `rate` expected of this iteration, measured by earlier ones with
    /// the same factors: the first increment then converges when `ρ/(1 − ρ) ‖Δ₀‖ < tol`, the error the
    /// rate leaves after it, without a second iteration to measure the rate (IDA carries its `ss = ρ/(1 − ρ)`
    /// from step to step the same way, CVODE its `crate`). 0 (or a rate of 1 and more): the first
    /// increment never converges on its own.
    pub fn with_carried_rate(self, rate: f64) -> Self {
        Self { carried_rate: rate, ..self }
    }

    /// This test with increments up to `round_off` (in the test's norm) converged whatever their rate,
    /// as those below `1e-4 tol` are. Where the norm is a small share of the tolerance (error per unit
    /// step), `1e-4 tol` is below one unit of rounding of the solution: a body at rest on a fixed joint,
    /// whose increments were half a unit of rounding, 1.9e-6 of a share of 2e-5, failed every step.
    pub fn with_round_off(mut self, round_off: f64) -> Self {
        self.round_off = round_off;
        self
    }

    /// This test with increments after the first at or below `floor` converged whatever their rate (the
    /// level of the residual's rounding, in the measure of the increments).
    pub fn with_rounding_floor(self, floor: f64) -> Self {
        Self { rounding_floor: floor, ..self }
    }

    /// The rate an iteration that did not converge measured before it gave up: its slowest or its last,
    /// 1 when it measured none (a residual that was not finite: as diverged).
    pub fn failed_rate(&self) -> f64 {
        if self.last_rate > 0.0 {
            self.slowest.max(self.last_rate)
        } else {
            1.0
        }
    }

    /// The verdict on the weighted norm of the increment of iteration `k` (from 0). With the rate
    /// `ρ = ‖Δₖ‖ / ‖Δₖ₋₁‖` it converges when `ρ/(1 − ρ) ‖Δₖ‖ < tol` (the error left) and diverges when
    /// `ρ ≥ 1` or when the iterations left cannot bring the error below the tolerance. A second
    /// increment as small as `1e-4 tol` has converged whatever the rate: at that level the increments
    /// are round-off that does not shrink, and their ratio, about 1, says nothing (a body at rest on a
    /// fixed joint failed every step, down to h = 1e-307, with increments of 4e-8 of the tolerance).
    pub fn assess(&mut self, k: usize, norm: f64) -> Verdict {
        if k == 0 {
            self.first_increment = norm;
            let rate = self.carried_rate;
            if rate > 0.0 && rate < 1.0 && rate / (1.0 - rate) * norm < self.tolerance {
                return Verdict::Converged;
            }
        }
        if norm == 0.0 || (k > 0 && norm <= (NEGLIGIBLE * self.tolerance).max(self.round_off)) {
            return Verdict::Converged;
        }
        if let Some(level) = self.rounding_level.filter(|&level| k > 0 && norm <= level) {
            // Rounding: converged whatever its rate. The rate from a correction above the level is still
            // one of the matrix, which the rate monitor needs; one from an increment that was rounding
            // itself says nothing.
            if let Some(old) = self.last.filter(|&old| old > level) {
                self.last_rate = norm / old;
                self.slowest = self.slowest.max(self.last_rate);
            }
            self.at_level = true;
            return Verdict::Converged;
        }
        if k > 0 {
            self.smallest_after_first = self.smallest_after_first.min(norm);
            if norm <= self.rounding_floor && norm > self.tolerance {
                self.at_floor = true;
                return Verdict::Converged;
            }
        }
        let rate = self.last.map(|old| norm / old);
        self.last = Some(norm);
        let Some(rate) = rate else {
            return Verdict::Continue;
        };
        self.last_rate = rate;
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

/// The equations of one simplified Newton iteration, as an implicit method gives them to [`iterate`].
pub(crate) trait NewtonSystem {
    /// Evaluates the residual at the current iterate (iteration `k`, from 0) and returns it.
    fn residual(&mut self, k: usize) -> &[f64];
    /// Solves the factored iteration matrix for the increment from the residual; `false` when it cannot.
    fn solve(&mut self) -> bool;
    /// The weighted norm of the increment, the convergence test's measure.
    fn increment_norm(&mut self) -> f64;
    /// Adds the increment to the iterate.
    fn apply(&mut self);
    /// The weighted norm (the test's measure) of the increment that the rounding of the residual at the
    /// current iterate produces: increments at or below it have converged whatever their rate. 0 (the
    /// default) for a system that does not estimate it.
    fn rounding_level(&mut self) -> f64 {
        0.0
    }
}

/// How a Newton iteration ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NewtonOutcome {
    /// The iteration converged (its last increment applied).
    pub converged: bool,
    /// Iterations begun (residuals evaluated).
    pub iterations: usize,
    /// Linear solves made, the Newton iterations of the statistics.
    pub solves: usize,
}

/// At most `max_iterations` simplified Newton iterations on `system`, tested by `test` (made for the same
/// `max_iterations`): a residual that is not finite, a failed solve or a diverging increment ends it
/// unconverged, the increment of a diverging iteration not applied.
pub(crate) fn iterate(system: &mut impl NewtonSystem, test: &mut ConvergenceTest, max_iterations: usize) -> NewtonOutcome {
    let mut solves = 0;
    let end = |converged: bool, iterations: usize, solves: usize| NewtonOutcome { converged, iterations, solves };
    for k in 0..max_iterations {
        if !system.residual(k).iter().all(|x| x.is_finite()) {
            return end(false, k + 1, solves);
        }
        if !system.solve() {
            return end(false, k + 1, solves);
        }
        solves += 1;
        let norm = system.increment_norm();
        if test.needs_rounding_level(k, norm) {
            test.set_rounding_level(system.rounding_level());
        }
        let verdict = test.assess(k, norm);
        if verdict == Verdict::Diverging {
            return end(false, k + 1, solves);
        }
        system.apply();
        if verdict == Verdict::Converged {
            return end(true, k + 1, solves);
        }
    }
    end(false, max_iterations, solves)
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

    /// With a rounding floor, an increment after the first at or below it converges at any rate, and says
    /// so; the first increment never does, and without the floor the same increments diverge.
    #[test]
    fn increments_at_the_rounding_floor_converge_whatever_their_rate() {
        let mut test = ConvergenceTest::new(2.2e-3, 7).with_rounding_floor(0.25);
        assert_eq!(test.assess(0, 0.17), Verdict::Continue, "the first increment is a correction");
        assert_eq!(test.assess(1, 0.21), Verdict::Converged, "a rate of 1.2 at the floor");
        assert!(test.at_floor);
        assert_eq!(test.smallest_after_first, 0.21);
        let mut test = ConvergenceTest::new(2.2e-3, 7);
        assert_eq!(test.assess(0, 0.17), Verdict::Continue);
        assert_eq!(test.assess(1, 0.21), Verdict::Diverging);
        assert!(!test.at_floor);
        assert_eq!(test.smallest_after_first, 0.21);
    }

    /// With a rate carried from earlier iterations, a first increment whose error left at that rate is
    /// below the tolerance converges on its own; a larger one, or one without a carried rate, does not.
    #[test]
    fn a_carried_rate_lets_the_first_increment_converge() {
        let mut test = ConvergenceTest::new(1e-3, 4).with_carried_rate(0.1);
        assert_eq!(test.assess(0, 5e-3), Verdict::Converged, "error left 0.1/0.9 × 5e-3 = 5.6e-4");
        let mut test = ConvergenceTest::new(1e-3, 4).with_carried_rate(0.1);
        assert_eq!(test.assess(0, 1e-2), Verdict::Continue, "error left 1.1e-3");
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 5e-3), Verdict::Continue, "no carried rate");
        let mut test = ConvergenceTest::new(1e-3, 4).with_carried_rate(1.5);
        assert_eq!(test.assess(0, 1e-9), Verdict::Continue, "a carried rate of 1.5 says nothing");
    }

    #[test]
    fn round_off_increments_converge_whatever_their_ratio() {
        // The fixed body at rest: 3.7e-11 then 4.6e-11 against a tolerance of 1e-3.
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 3.7e-11), Verdict::Continue, "one increment says nothing of the rate");
        assert_eq!(test.assess(1, 4.6e-11), Verdict::Converged);
        // A small share of the tolerance: half a unit of rounding is round-off whatever the tolerance.
        let mut test = ConvergenceTest::new(1.1e-3, 4).with_round_off(1.1e-5);
        assert_eq!(test.assess(0, 1.5e-6), Verdict::Continue);
        assert_eq!(test.assess(1, 1.9e-6), Verdict::Converged);
        // Above 1e-4 of the tolerance a growing increment still diverges.
        let mut test = ConvergenceTest::new(1e-3, 4);
        assert_eq!(test.assess(0, 1e-7), Verdict::Continue);
        assert_eq!(test.assess(1, 2e-7), Verdict::Diverging);
    }

    /// An increment after the first at or below the rounding level converges at any rate; the level is
    /// asked for by the first increment after the first that converges neither outright nor by its rate,
    /// or given from the start. The increments of a failed iteration of the chain of 512 rods (rtol 3e-10,
    /// the chain benchmark's: they stalled at 9e-4 tolerances at a rate of 0.999 against a Newton tolerance
    /// of 7.4e-5) converge against its level of 7.25e-3.
    #[test]
    fn increments_at_the_rounding_level_converge_whatever_their_rate() {
        let increments = [6.773, 7.229e-2, 2.380e-3, 9.185e-4, 9.172e-4];
        let mut test = ConvergenceTest::new(7.4e-5, 7);
        let verdicts: Vec<Verdict> = increments.iter().enumerate().map(|(k, &norm)| test.assess(k, norm)).collect();
        assert_eq!(verdicts.last(), Some(&Verdict::Diverging), "stalled without the level: {verdicts:?}");

        let mut test = ConvergenceTest::new(7.4e-5, 7);
        assert!(!test.needs_rounding_level(0, 6.773), "the first increment is a correction");
        assert_eq!(test.assess(0, 6.773), Verdict::Continue);
        assert!(!test.needs_rounding_level(1, 1e-7), "converges by its rate");
        assert!(test.needs_rounding_level(1, 7.229e-2));
        test.set_rounding_level(7.25e-3);
        assert!(!test.needs_rounding_level(1, 7.229e-2), "asked for once");
        assert_eq!(test.assess(1, 7.229e-2), Verdict::Continue, "above the level: a correction");
        assert_eq!(test.assess(2, 2.380e-3), Verdict::Converged);
        assert!(test.at_level);
        assert!((test.slowest - 2.380e-3 / 7.229e-2).abs() < 1e-12, "the rate from a correction above the level counts");

        // Known from the start (the same factors): the second increment converges at it, its rate measured.
        let mut test = ConvergenceTest::new(7.4e-5, 7).with_rounding_level(Some(7.25e-3));
        assert!(!test.needs_rounding_level(1, 7.229e-2));
        assert_eq!(test.assess(0, 5.0e-3), Verdict::Continue, "never the first increment");
        assert_eq!(test.assess(1, 4.0e-3), Verdict::Converged);
        assert_eq!(test.slowest, 0.0, "a rate from an increment at the level says nothing");
        let mut test = ConvergenceTest::new(7.4e-5, 7).with_rounding_level(Some(7.25e-3));
        assert_eq!(test.assess(0, 1e-2), Verdict::Continue);
        assert_eq!(test.assess(1, 2e-2), Verdict::Diverging, "above the level a growing increment diverges");
        assert!(!test.at_level);
    }

    /// Newton's method on the scalar `x² − 2 = 0` with the derivative frozen at the start (a chord
    /// iteration, as the integrators' reused iteration matrix): it converges linearly to √2, at the
    /// rate `|1 − f'(√2)/f'(x₀)|`.
    struct Chord {
        x: f64,
        slope: f64,
        residual: [f64; 1],
        dx: f64,
    }

    impl NewtonSystem for Chord {
        fn residual(&mut self, _k: usize) -> &[f64] {
            self.residual[0] = self.x * self.x - 2.0;
            &self.residual
        }
        fn solve(&mut self) -> bool {
            self.dx = -self.residual[0] / self.slope;
            true
        }
        fn increment_norm(&mut self) -> f64 {
            self.dx.abs()
        }
        fn apply(&mut self) {
            self.x += self.dx;
        }
    }

    #[test]
    fn a_chord_iteration_converges_to_the_root_within_the_tolerance() {
        let mut chord = Chord { x: 1.5, slope: 3.0, residual: [0.0], dx: 0.0 };
        let mut test = ConvergenceTest::new(1e-10, 8);
        let outcome = iterate(&mut chord, &mut test, 8);
        assert!(outcome.converged, "{outcome:?}");
        assert_eq!(outcome.iterations, outcome.solves);
        assert!((chord.x - 2f64.sqrt()).abs() < 1e-10, "{}", chord.x);
        let rate = (1.0 - 2.0 * 2f64.sqrt() / 3.0).abs();
        assert!((test.slowest - rate).abs() < 0.02, "contraction {} against {rate}", test.slowest);
    }

    #[test]
    fn a_diverging_or_not_finite_iteration_stops_unconverged() {
        // A slope of the wrong sign: the iterates run away from the root.
        let mut chord = Chord { x: 1.5, slope: -3.0, residual: [0.0], dx: 0.0 };
        let outcome = iterate(&mut chord, &mut ConvergenceTest::new(1e-10, 8), 8);
        assert!(!outcome.converged && outcome.iterations < 8, "{outcome:?}");
        let mut chord = Chord { x: f64::INFINITY, slope: 3.0, residual: [0.0], dx: 0.0 };
        let outcome = iterate(&mut chord, &mut ConvergenceTest::new(1e-10, 8), 8);
        assert_eq!(outcome, NewtonOutcome { converged: false, iterations: 1, solves: 0 });
    }
}
