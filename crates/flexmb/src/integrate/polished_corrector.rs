//! The BDF's corrector polished where its Newton tolerance is at the rounding floor, and the lower floor
//! under a step's share of the tolerance that this resolves.
//!
//! The BDF's local error estimate is the corrector's correction `d = y_{n+1} − y⁽⁰⁾` over `k + 1`,
//! accumulated from the Newton increments themselves (not a difference of two states). It is not limited
//! by the rounding of the residual but by what the iteration leaves unresolved in the state it accepts:
//! where the Newton tolerance is held by its floor ([`BDF_NEWTON_FLOOR`], 20 units of rounding of the
//! solution; below rtol of about 1e-7 with error per unit step), an accepted `y_n` carries up to that
//! much of the iteration's rest, and every later estimate sees it through the history: the estimate is
//! `∇^{k+1} y` in effect, and at order 5 the differences of six states weigh independent errors by
//! `√(Σ (b_j − p_j)²)/(k + 1)` ≈ 4.6 (`b_j`, `p_j` the BDF's and the predictor's coefficients), so
//! 20 units become about 2e-14 of noise in the estimate. Traced on the 3-D slider-crank at rtol 1e-10
//! (each accepted step's estimate relative to the solution; 23,211 of 23,416 steps at order 5, all held
//! to the share's floor of 1e-13): estimates 2.2e-14 to 3.4e-14 (10th to 90th percentile) jumping by
//! ±1.5e-14 between steps of equal size, the jitter `|e_n − (e_{n−1} + e_{n+1})/2|` 1.5e-15 at the median
//! and 1.2e-14 at the 90th percentile. One more Newton iteration after convergence
//! ([`POLISH_ITERATIONS`]) cut the 90th percentile to 3.7e-15 (two: 2.6e-15; a Newton floor of 2 units
//! instead: 4.3e-15, with more iterations on every step), the estimates themselves unchanged (median
//! 2.8e-14): the noise was the iteration's rest, not the predictor's extrapolation nor the residual's
//! rounding.
//!
//! With the estimate resolved to about 4e-15, the floor under a step's share can be
//! [`POLISHED_STEP_FLOOR`], 1.5e-14 of the solution, instead of
//! [`FINE_STEP_FLOOR`] (1e-13), where the corrector is polished. Near a singular position (the guard's
//! amplification above 1, or an approach watched: [`away_from_singular_positions`]) the estimate is the
//! amplified rounding: neither the polish nor the lower floor applies there (Andrews' squeezer, κ ≈ 191
//! at every step, went from 12.8 to 356 tolerances at rtol 1e-10 with the lower floor applied there too).
//! Measured over the run (`docs/accuracy/work_precision.py --integrators bdf --tolerance-span run`,
//! reference Adams at 1e-12; docs/accuracy.md, *The BDF's floor over a long run*): the slider-crank at
//! 1e-10 from 61 to 21.9 tolerances in 30,049 steps (23,416), at 1e-9 from 6.2 to 4.9, Andrews' squeezer
//! 21 and 9.7 at 1e-9 and 1e-10 (25 and 12.8); with the floor lowered wherever the guard does not amplify
//! the rounding (also on the slider-crank's dips to κ ≈ 25) 10.7 at 1e-10, but the double four-bar stopped
//! (below). Floors of 1.2e-14 and 1e-14 gave the slider-crank 8.4 and 6.8 at 1e-10 but Andrews' squeezer
//! 60 at 1e-9 and 44 at 1e-10.

use crate::integrate::share_floor::FINE_STEP_FLOOR;
#[cfg(doc)]
use crate::integrate::share_floor::BDF_NEWTON_FLOOR;

/// The floor under a BDF step's local error, relative to the solution, where its corrector is polished:
/// 1.5e-14, about four times the estimate's noise then (see the module documentation).
pub(crate) const POLISHED_STEP_FLOOR: f64 = 1.5e-14;

/// Newton iterations made after the iteration has converged, where it is polished: each removes all but
/// the contraction rate's fraction of the iteration's rest (one: the estimate's noise from 1.2e-14 to
/// 3.7e-15 on the slider-crank at rtol 1e-10; a second only to 2.6e-15).
pub(crate) const POLISH_ITERATIONS: usize = 1;

/// Whether a step is away from singular positions: the guard neither amplifies the rounding
/// (`amplification` 1) nor watches an approach or a passage (`near`, `SingularPassage::near`: `κ` above
/// 20 and falling towards a predicted position, or not yet back below 20 after one). The guard's
/// amplification is 1 until the rounding `10 ε κ` matters against a share of the Adams method's floor
/// (1e-12), but it exceeds 1.5e-14 from `κ` = 7 on: with the amplification alone the double four-bar over
/// its run at rtol 1e-10 stopped at t = 6.513 s (step 2.1e-14 s, the Newton iteration not converging) on
/// its approach to the seventh position.
pub(crate) fn away_from_singular_positions(amplification: f64, near: bool) -> bool {
    amplification <= 1.0 && !near
}

/// Whether a converged corrector is polished: away from singular positions
/// ([`away_from_singular_positions`]) and where the attempt's Newton tolerance is held by its rounding
/// floor (`newton_floor_holds`), the only place its rest is as large as the local errors the steps are
/// held to. Elsewhere the Newton tolerance is a small fraction of the share, and the cost (one residual
/// and one solve per step) buys nothing.
pub(crate) fn polishes(away: bool, newton_floor_holds: bool) -> bool {
    away && newton_floor_holds
}

/// The floor under a BDF step's local error, relative to the solution: [`POLISHED_STEP_FLOOR`] away from
/// singular positions (`away`, [`away_from_singular_positions`]), [`FINE_STEP_FLOOR`] near one (the
/// estimate is not resolved below it there).
pub(crate) fn step_floor(away: bool) -> f64 {
    if away {
        POLISHED_STEP_FLOOR
    } else {
        FINE_STEP_FLOOR
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lower floor only where the guard does not amplify the rounding, and the polish only there and
    /// where the Newton floor holds.
    #[test]
    fn the_corrector_is_polished_and_the_floor_lowered_only_away_from_singular_positions() {
        assert!(away_from_singular_positions(1.0, false));
        assert!(!away_from_singular_positions(1.0, true), "an approach watched");
        assert!(!away_from_singular_positions(191.0, false), "the rounding amplified");
        assert_eq!(step_floor(true), POLISHED_STEP_FLOOR);
        assert_eq!(step_floor(false), FINE_STEP_FLOOR);
        const { assert!(POLISHED_STEP_FLOOR < FINE_STEP_FLOOR / 5.0) };
        assert!(polishes(true, true));
        assert!(!polishes(true, false), "a Newton tolerance above its floor leaves a rest far below the share");
        assert!(!polishes(false, true), "near a singular position the estimate is the amplified rounding");
    }
}
