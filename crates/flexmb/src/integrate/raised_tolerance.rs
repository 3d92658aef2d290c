//! The tolerance raised to what the step equations resolve, the last resort of the implicit methods (the
//! BDF and the generalized-α method) before a step-size underflow.
//!
//! Near a singular position the equations of a step can be resolved no finer than the rounding of the
//! constraints amplified by the near-singular constraint Jacobian: the IFToMM double four-bar
//! (`models/benchmarks/double_four_bar.toml`), whose links come into line at t ≈ 0.7141 s, has Newton
//! increments of 5e-10 of the solution 20 µs before, and above it at every step size down to 1e-12 s
//! (the BDF at rtol = atol = 1e-12). The [rounding floor](super::newton_rounding) accepts such increments
//! only while they are a small part of the step's change of the solution, which a step shortened toward
//! the singular position no longer makes; and the closer the steps land to it, the larger the rounding.
//! The steps then shrank to the smallest step and the run stopped, there (BDF at 1e-12, 1e-11;
//! generalized-α at 1e-12 to 1e-9).
//!
//! So when a step's size falls below the smallest step, the tolerances asked for, if finer than
//! [`CEILING`], are raised tenfold and the step is attempted again from its start: the steps are then
//! longer, land farther from the singular position, where the rounding is smaller. The raise is repeated
//! up to [`CEILING`] and relaxes by [`DECAY`] per accepted step back to the tolerances asked for; the
//! steps taken with a raised tolerance are counted and reported as those at the rounding floor are
//! ([`Stats::rounding_floor_steps`](super::Stats::rounding_floor_steps), with the warning of the
//! simulation), the raised `rtol` as the level they were resolved to. A run that needs no raise is not
//! changed at all.

use crate::integrate::newton_rounding::RoundingFloor;
use crate::integrate::share_floor::ShareFloor;
use crate::integrate::Tolerances;

/// Factor of each raise of the tolerances.
const RAISE: f64 = 10.0;
/// The coarsest relative tolerance a raise reaches: the generalized-α method passes the double
/// four-bar's ten singular positions at rtol = atol = 1e-8 (and stops at the first at 1e-9).
const CEILING: f64 = 1e-8;
/// Factor of the raise per accepted step: from 1e4 back to 1 in 180 steps.
const DECAY: f64 = 0.95;
/// Factor per accepted step of the recent step size from which a step is attempted again after a raise.
const REACH_DECAY: f64 = 0.98;
/// A rounding floor above this many tolerances raises the tolerances: the steps are resolved no finer.
const RAISE_AT: f64 = 10.0;

/// The raise of the tolerances of one integrator (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RaisedTolerance {
    /// The relative and absolute tolerances asked for.
    asked: (f64, f64),
    /// The factor of the tolerances in force (1: as asked).
    factor: f64,
    /// The longest recent step (s): the longest accepted step, its length falling by [`REACH_DECAY`] per
    /// accepted step since.
    reach: f64,
}

impl RaisedTolerance {
    /// No raise of `tolerances`, those asked for.
    pub fn new(tolerances: &Tolerances) -> Self {
        Self { asked: (tolerances.rtol, tolerances.atol), factor: 1.0, reach: 0.0 }
    }

    /// Raises `tolerances` tenfold; false (and `tolerances` unchanged) when that would pass [`CEILING`].
    pub fn raise(&mut self, tolerances: &mut Tolerances) -> bool {
        let factor = self.factor * RAISE;
        if !(self.asked.0 * factor <= CEILING * (1.0 + 1e-9)) {
            return false;
        }
        self.factor = factor;
        self.apply(tolerances);
        true
    }

    /// Raises `tolerances` tenfold, up to [`CEILING`], while the rounding floor is above [`RAISE_AT`] of
    /// them, the floors (in tolerances) rescaled to the raised ones.
    pub fn follow_floor(&mut self, rounding: &mut RoundingFloor, share: &mut ShareFloor, tolerances: &mut Tolerances) {
        while rounding.floor > RAISE_AT && self.raise(tolerances) {
            rounding.rescale(1.0 / RAISE);
            share.rescale(1.0 / RAISE);
        }
    }

    /// Whether the tolerances in force are above those asked for.
    pub fn is_raised(&self) -> bool {
        self.factor > 1.0
    }

    /// The step size from which a step is attempted again after a raise at the smallest step: the longest
    /// recent one, at least `h`. The steps had shrunk toward the singular position, where the rounding
    /// grows; a step as long as those before lands as far from it.
    pub fn restart_step(&self, h: f64) -> f64 {
        self.reach.max(h)
    }

    /// A step of size `h` was accepted: the raise relaxes by [`DECAY`].
    pub fn accepted(&mut self, h: f64, tolerances: &mut Tolerances) {
        self.reach = h.max(REACH_DECAY * self.reach);
        if self.is_raised() {
            self.factor = (self.factor * DECAY).max(1.0);
            self.apply(tolerances);
        }
    }

    /// The state to store in a checkpoint: the factor of the tolerances.
    pub fn stored(&self) -> f64 {
        self.factor
    }

    /// The raise stored in a checkpoint by [`stored`](Self::stored) (0, of a checkpoint written before the
    /// raise, is none), applied to `tolerances`.
    pub fn restore(&mut self, stored: f64, tolerances: &mut Tolerances) {
        self.factor = stored.max(1.0);
        self.apply(tolerances);
    }

    fn apply(&self, tolerances: &mut Tolerances) {
        tolerances.rtol = self.asked.0 * self.factor;
        tolerances.atol = self.asked.1 * self.factor;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tolerances finer than the ceiling are raised tenfold at a time up to it, and relax back to those
    /// asked for, never below; coarser ones are never raised.
    #[test]
    fn tight_tolerances_are_raised_to_the_ceiling_and_relax_back() {
        let mut tolerances = Tolerances::new(1e-12, 1e-12);
        let mut raise = RaisedTolerance::new(&tolerances);
        assert!(!raise.is_raised());
        for k in 1..=4 {
            assert!(raise.raise(&mut tolerances), "raise {k}");
            assert!((tolerances.rtol / (1e-12 * 10f64.powi(k)) - 1.0).abs() < 1e-12, "{tolerances:?}");
            assert_eq!(tolerances.atol, tolerances.rtol);
        }
        assert!(!raise.raise(&mut tolerances), "1e-7 is past the ceiling");
        assert!((tolerances.rtol - 1e-8).abs() < 1e-20);
        let steps = (1e-4f64.ln() / DECAY.ln()).ceil() as usize;
        for _ in 0..steps {
            raise.accepted(1e-3, &mut tolerances);
        }
        assert!(!raise.is_raised());
        assert_eq!((tolerances.rtol, tolerances.atol), (1e-12, 1e-12));

        let mut restored = RaisedTolerance::new(&tolerances);
        restored.restore(100.0, &mut tolerances);
        assert!((tolerances.rtol - 1e-10).abs() < 1e-22 && restored.is_raised());
        restored.restore(0.0, &mut tolerances);
        assert_eq!(tolerances.rtol, 1e-12);

        let mut tolerances = Tolerances::new(1e-6, 1e-9);
        let mut raise = RaisedTolerance::new(&tolerances);
        assert!(!raise.raise(&mut tolerances), "rtol 1e-6 is resolved");
        assert_eq!((tolerances.rtol, tolerances.atol), (1e-6, 1e-9));
    }
}
