//! Solver statistics, the same record for every method.

/// Counters of one integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Steps rejected by the local error test.
    pub error_test_failures: usize,
    /// Step attempts abandoned because the Newton iteration did not converge.
    pub newton_failures: usize,
    /// Newton iterations (projection iterations for the Adams method).
    pub newton_iterations: usize,
    /// Evaluations of the equations of motion.
    pub residual_evaluations: usize,
    /// Evaluations of the iteration matrix's Jacobian.
    pub jacobian_evaluations: usize,
    /// LU factorizations.
    pub factorizations: usize,
    /// Accepted steps taken at each order (index = order): 1–5 for the BDF, 1–12 for the Adams method.
    pub order_counts: [usize; 13],
    /// Sum of squared accepted step sizes (for the RMS step).
    pub sum_h_squared: f64,
    /// Accepted steps whose Newton iteration ended at the rounding floor: increments that shrank neither
    /// with the iterations nor with the step, the residual's rounding amplified by the iteration matrix (a
    /// near-singular constraint Jacobian, large forces), above the Newton tolerance.
    #[serde(default)]
    pub rounding_floor_steps: usize,
    /// The largest rounding floor of those steps relative to the solution (`rtol` times the floor's level
    /// in tolerances): about the finest tolerance the step equations could be resolved to there.
    #[serde(default)]
    pub rounding_floor: f64,
    /// Accepted steps taken while a singular position was predicted ahead (the constraint Jacobian's
    /// condition number rising past 100 toward a zero of its smallest singular value), their Newton and error
    /// tests allowing the rounding amplified by it (`integrate/singular_position.rs`); those at which the
    /// condition number was measured, which is at every step where its rounding could matter.
    #[serde(default)]
    pub singular_position_steps: usize,
    /// The largest condition number of the constraint Jacobian at the end of such a step: the steps there
    /// are resolved to about `10 ε` times it, relative to the solution.
    #[serde(default)]
    pub singular_position_condition: f64,
    /// Singular positions passed (windows around a predicted one that the steps ended past).
    #[serde(default)]
    pub singular_positions: usize,
    /// The finest fraction of the solution that a step near a singular position was held to while its tests
    /// allowed the amplified rounding (`rtol` times the step's share of the tolerance: `rtol` with error per
    /// step, far less with error per unit step); 0 when no step was.
    #[serde(default)]
    pub singular_position_tolerance: f64,
    /// Accepted steps whose share of the tolerance was the fixed floor, what one step resolves
    /// ([`share_floor`](Self::share_floor) of the solution), rather than their share of the span: their
    /// local errors are each about that floor and add up over the run, to about their number times it
    /// (the BDF; `integrate/share_floor.rs`).
    #[serde(default)]
    pub share_floor_steps: usize,
    /// That floor relative to the solution, the mean over those steps (the BDF's, between 1.5e-14 and
    /// 1e-13, follows the estimate's measured noise: `integrate/noise_floor.rs`); 0 when no
    /// step was held to it.
    #[serde(default)]
    pub share_floor: f64,
    /// What the accepted steps let pass as rounding, relative to the solution, added up over the run: the
    /// parts of their local error estimates above their share of the tolerance that passed because they
    /// were at the rounding level (near a singular position, at the Newton increments' rounding floor, or
    /// noise that no shorter step resolves; the BDF, `integrate/passed_rounding.rs`). A bound on what the
    /// global error may exceed the tolerance by; 0 when nothing passed.
    #[serde(default)]
    pub rounding_passed: f64,
}

impl Stats {
    /// Rejected steps of any cause.
    pub fn rejected_steps(&self) -> usize {
        self.error_test_failures + self.newton_failures
    }

    /// What the steps held to the fixed floor under a step's share may add up to, relative to the
    /// solution: their number times their mean floor.
    pub fn share_floor_spent(&self) -> f64 {
        self.share_floor_steps as f64 * self.share_floor
    }

    /// The counters of two integrations one after the other (a run whose integrator was restarted).
    pub fn followed_by(&self, later: &Stats) -> Stats {
        let mut order_counts = self.order_counts;
        order_counts.iter_mut().zip(&later.order_counts).for_each(|(a, b)| *a += b);
        Stats {
            steps: self.steps + later.steps,
            error_test_failures: self.error_test_failures + later.error_test_failures,
            newton_failures: self.newton_failures + later.newton_failures,
            newton_iterations: self.newton_iterations + later.newton_iterations,
            residual_evaluations: self.residual_evaluations + later.residual_evaluations,
            jacobian_evaluations: self.jacobian_evaluations + later.jacobian_evaluations,
            factorizations: self.factorizations + later.factorizations,
            order_counts,
            sum_h_squared: self.sum_h_squared + later.sum_h_squared,
            rounding_floor_steps: self.rounding_floor_steps + later.rounding_floor_steps,
            rounding_floor: self.rounding_floor.max(later.rounding_floor),
            singular_position_steps: self.singular_position_steps + later.singular_position_steps,
            singular_position_condition: self.singular_position_condition.max(later.singular_position_condition),
            singular_positions: self.singular_positions + later.singular_positions,
            singular_position_tolerance: finest_nonzero(self.singular_position_tolerance, later.singular_position_tolerance),
            share_floor_steps: self.share_floor_steps + later.share_floor_steps,
            // The mean floor over both parts' held steps.
            share_floor: if self.share_floor_steps + later.share_floor_steps > 0 {
                (self.share_floor_steps as f64 * self.share_floor + later.share_floor_steps as f64 * later.share_floor)
                    / (self.share_floor_steps + later.share_floor_steps) as f64
            } else {
                0.0
            },
            rounding_passed: self.rounding_passed + later.rounding_passed,
        }
    }

    /// A step near a singular position, its tests allowing the amplified rounding, was accepted, held to
    /// `fraction` of the solution ([`singular_position_tolerance`](Self::singular_position_tolerance)).
    pub(crate) fn held_near_singular_position(&mut self, fraction: f64) {
        self.singular_position_tolerance = finest_nonzero(self.singular_position_tolerance, fraction);
    }

    /// Root-mean-square accepted step size (s), the seed's "RMS integration stepsize".
    pub fn rms_step(&self) -> f64 {
        if self.steps == 0 {
            0.0
        } else {
            (self.sum_h_squared / self.steps as f64).sqrt()
        }
    }
}

/// The smaller of two levels, 0 standing for none.
fn finest_nonzero(a: f64, b: f64) -> f64 {
    match (a > 0.0, b > 0.0) {
        (true, true) => a.min(b),
        (true, false) => a,
        _ => b,
    }
}
