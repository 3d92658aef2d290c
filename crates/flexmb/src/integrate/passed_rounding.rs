//! What the BDF let pass as rounding, added up over the run: a bound on the global error its error control
//! did not hold, and the warning when it exceeds the tolerance.
//!
//! Three tests of the BDF pass a local error estimate above the step's share of the tolerance, because no
//! shorter step resolves it more finely: an estimate that does not fall with the step
//! ([`ShareFloor::is_noise`](super::share_floor::ShareFloor::is_noise)), one within the Newton
//! increments' rounding floor ([`RoundingFloor`](super::newton_rounding::RoundingFloor)), and, near a
//! singular position, one within the rounding of the constrained solution that the constraint
//! Jacobian's condition number amplifies ([`SingularPassage::estimate_beyond_rounding`](super::singular_position::SingularPassage::estimate_beyond_rounding)).
//! Each is right about the step it passes: the estimate is at the level of the rounding. But what passes
//! is also the truncation error up to that level: the step grew until its truncation error reached the
//! allowance. With error per unit step over a run of thousands of steps those local errors add up. (Near
//! a singular position the step after such an estimate now aims at the rounding itself,
//! [`SingularPassage::estimate_for_selection`](super::singular_position::SingularPassage::estimate_for_selection),
//! so that what passes there is mostly rounding, which does not add up as truncation does: the sum is
//! then an upper measure of the error, not an estimate of it.)
//!
//! Andrews' squeezer (`models/benchmarks/andrews_squeezer.toml`, 0.03 s) is the case: every step is near a
//! singular position (κ 147 to 204), where an estimate within `50 · gain · 10 ε κ` of the solution (2.3e-10
//! at order 5) passes. At rtol 1e-9 over the run, 1,985 of its 2,695 steps passed estimates above their
//! share (1e-13 to 3.5e-13 of the solution) that added up to 4.0e-8 of the solution, and its global error
//! `E` was 2.5e-8, 25 tolerances (docs/accuracy.md, *Andrews' squeezer at 1e-9 is not the floor but the
//! singular-position guard*); with the selection aimed at the rounding, 4,801 steps passed 1.9e-8 and `E`
//! is 7.7e-10, 0.77 tolerances. Each step here adds what its estimate exceeded its share by
//! ([`beyond_share`]) to [`Stats::rounding_passed`]; the run warns at its end when that sum exceeds the
//! tolerance ([`passed_warning`]).

use crate::integrate::Stats;

/// What an accepted step let pass as rounding, relative to the solution: the part of its local error
/// estimate `error` (in shares of the tolerance, before any test passed it) above its share `share` of the
/// tolerance `rtol`; 0 for an estimate within its share, which the error control holds.
pub(crate) fn beyond_share(error: f64, share: f64, rtol: f64) -> f64 {
    (error - 1.0).max(0.0) * share * rtol
}

/// The warning at the end of a run of `t_end` seconds whose tolerance is `rtol` over each `span` seconds
/// ([`Tolerances::span`](super::Tolerances::span)) when what its steps let pass as rounding,
/// [`Stats::rounding_passed`], exceeds the run's tolerance, `rtol` times its number of spans; `None`
/// otherwise. Those local errors are each bounded by the rounding level, not by the tolerance, and add up
/// over the run: the global error can be that large beyond the tolerance. The message says how much, why
/// (where [`Stats::singular_position_condition`] amplifies the rounding, near singular positions if the
/// run passed one; or below what f64 resolves) and what to do. With error per step (`span` infinite) the tolerance is a
/// promise about each step, not the run, and a step that passed its rounding is reported by the warnings
/// of the rounding floor and of the singular positions: no warning here.
pub(crate) fn passed_warning(stats: &Stats, rtol: f64, span: f64, t_end: f64) -> Option<String> {
    let passed = stats.rounding_passed;
    let allowed = rtol * (t_end / span).max(1.0);
    (span.is_finite() && passed > allowed).then(|| {
        let why = if stats.singular_position_steps > 0 {
            // Near a singular position only where the run passed one: elsewhere the condition number merely
            // dipped (the 3-D slider-crank's 25).
            let near = if stats.singular_positions > 0 { " near singular positions" } else { "" };
            format!(
                "the rounding of the constrained solution{near}, where the constraint Jacobian's condition number \
                 (up to {:.0}) amplifies it",
                stats.singular_position_condition
            )
        } else {
            "the rounding of f64 arithmetic, which no shorter step resolves".to_string()
        };
        format!(
            "tolerance finer than the BDF keeps over this run: its steps let local error estimates above their share of \
             the tolerance pass as {why}; their excess adds up to {passed:.1e} of the solution, {ratio:.1} times rtol \
             {allowed:e}, and the global error can be that much larger than the tolerance asks; for a finer tolerance \
             use the Adams method (integrator = \"adams\"), which keeps rtol 1e-10 on the benchmarks of docs/accuracy.md but \
             the double four-bar through its singular positions (there to 1e-9); \
             the statistic rounding_passed gives the sum",
            ratio = passed / allowed,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An estimate within its share passes nothing; one of 3 shares passes the 2 above it.
    #[test]
    fn a_step_passes_what_its_estimate_exceeds_its_share_by() {
        assert_eq!(beyond_share(0.9, 1e-3, 1e-9), 0.0);
        assert!((beyond_share(3.0, 1e-3, 1e-9) - 2e-12).abs() < 1e-24);
    }

    /// The warning comes where the sum exceeds the run's tolerance (rtol times the spans in the run), says
    /// how much and why.
    #[test]
    fn the_run_warns_when_what_passed_exceeds_its_tolerance() {
        let passed = |sum| Stats { rounding_passed: sum, singular_position_steps: 10, singular_position_condition: 204.0, ..Stats::default() };
        assert_eq!(passed_warning(&passed(1e-9), 1e-9, 0.03, 0.03), None, "exactly rtol");
        let message = passed_warning(&passed(4e-8), 1e-9, 0.03, 0.03).expect("40 tolerances");
        assert!(message.contains("4.0e-8 of the solution, 40.0 times rtol") && message.contains("204"), "{message}");
        assert!(!message.contains("near singular positions"), "no position passed: {message}");
        let near = passed_warning(&Stats { singular_positions: 2, ..passed(4e-8) }, 1e-9, 0.03, 0.03).unwrap();
        assert!(near.contains("solution near singular positions, where"), "{near}");
        // Over a span of 1 s, a run of 5 s may pass five tolerances.
        assert_eq!(passed_warning(&passed(4e-9), 1e-9, 1.0, 5.0), None);
        let floor = Stats { rounding_passed: 6e-9, ..Stats::default() };
        assert!(passed_warning(&floor, 1e-9, 1.0, 5.0).unwrap().contains("f64"));
        assert_eq!(passed_warning(&floor, 1e-9, f64::INFINITY, 5.0), None, "error per step");
    }
}
