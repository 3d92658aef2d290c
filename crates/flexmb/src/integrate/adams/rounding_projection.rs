//! The Adams method's position projection near a singular position: on to the rounding, not to the
//! tolerance.
//!
//! After every accepted step the positions are projected onto the constraints by Newton's method
//! ([`super::projection`]), which stops where the largest residual `|Φ|` is below 1 % of `atol` or the
//! last correction below 10⁻³ of the step's tolerance. Away from singular positions what that leaves is
//! far below the step's error. Near one it is not: the constraint Jacobian's smallest singular value `σ`
//! is `σ_rms / κ`, and a residual `r` left in the direction the constraints lose is a position error of
//! about `κ r / σ_rms` along it, which the next steps' accelerations (ill-conditioned there by the same
//! `κ`) carry on. On the double four-bar over its run (`models/benchmarks/double_four_bar.toml`, 10 s, error
//! per unit step) at rtol = atol = 1e-3 to 1e-8 the runs left the parallelogram branch at the first or
//! second singular position (B0 2 m off at 10 s), stalled or stopped there.
//!
//! Near a singular position ([`SingularPassage::near`](crate::integrate::singular_position::SingularPassage::near): one is predicted ahead, or one was passed and `κ`
//! has not yet fallen back to the watch) the projection therefore goes on to [`ROUNDING_RESIDUAL`], as long
//! as each iteration still halves the residual; where it stops falling (the rounding of `Φ` and of the
//! corrections, amplified by `κ`) the state is taken as projected once the ordinary test is met. Away
//! from singular positions nothing changes. Measured on the double four-bar over the run (B0 against the
//! exact path, `docs/accuracy/double_four_bar_exact.py`): 1e-3 to 1e-10 within 10 tolerances (5.2, 3.6,
//! 4.4, 4.7, 2.8, 5.5, 9.0, 6.8; 277 to 1,124 steps), 1e-12 bit-identical; measured again over rtol × 0.97
//! to 1.03, 1e-9 1.1 to 9.4 tolerances, 1e-10 12 to 32 (the 6.8 a lucky sample). Applied only from a larger `κ`
//! (30 to 300) or only where the guard's amplified rounding does not matter to the step, one tolerance or
//! another missed the 10 (docs/accuracy.md, *The position projection on to the rounding near a
//! position*). The 3-D slider-crank's dip to κ ≈ 25 counts as near: over the run its error rose from
//! 0.13 to 1.15 tolerances at 1e-6, within the promise.

/// The largest position residual `|Φ|` the projection iterates to near a singular position: a hundred
/// units of rounding of constraints whose lengths are about 1 (the four-bar's links are 1 m).
pub(super) const ROUNDING_RESIDUAL: f64 = 100.0 * f64::EPSILON;
