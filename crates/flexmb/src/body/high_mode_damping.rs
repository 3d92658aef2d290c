//! Damping of a flexible body's high natural modes: a damping ratio `ζ` on every natural mode of the
//! reduced model whose frequency lies above a cutoff, and none on the modes below it.
//!
//! An undamped mode of a few hundred hertz that the time steps do not resolve sets the step of a
//! variable-order BDF by stability, not by accuracy: orders 3–5 amplify an undamped oscillation whose
//! `h ω` falls near the imaginary axis, so the step stays a fraction of that mode's period whatever the
//! tolerance (the steel beam pendulum of the peer comparison, modes up to 573 Hz: about 16,000 steps per
//! second at every rtol from 1e-3 to 1e-5). Damping those modes, and only those, lets the step follow
//! the modes that carry the motion. The damping is part of the equations of motion (`−D ȧ` in the
//! modal forces, its work in the energy balance), so every integrator integrates the same model and the
//! damped modes' physics changes where the modeller asked for it: `D = M X_h diag(2 ζ ωⱼ) X_hᵀ M` with
//! `X_h` the mass-normalized natural modes above the cutoff, so `D x = 0` for every natural mode `x`
//! below it, whose frequency is unchanged.

use nalgebra::DMatrix;

use super::modal::{ModalBody, ModalDamping, ModalError};

/// A damping ratio on the natural modes of a flexible body above a cutoff frequency.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HighModeDamping {
    /// The cutoff (Hz): natural modes of the reduced model with a higher frequency are damped, the others
    /// are not.
    pub above_hz: f64,
    /// The damping ratio `ζ` of each mode above the cutoff. Default [`DEFAULT_RATIO`](Self::DEFAULT_RATIO).
    pub ratio: f64,
}

impl HighModeDamping {
    /// The default damping ratio, 0.5: on the peer's beam pendulum (modes above 200 Hz damped, BDF at
    /// rtol 1e-6) it took 3011 steps against 3492 with 0.2 and 2445 with 1, with the tip 3.5e-6, 5.3e-6
    /// and 7.3e-6 (relative) from the undamped model's converged motion.
    pub const DEFAULT_RATIO: f64 = 0.5;

    /// Damping ratio [`DEFAULT_RATIO`](Self::DEFAULT_RATIO) on the modes above `above_hz`.
    pub fn above(above_hz: f64) -> Self {
        Self { above_hz, ratio: Self::DEFAULT_RATIO }
    }

    /// Checks that the cutoff is positive and finite and the ratio non-negative and finite.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.above_hz > 0.0 && self.above_hz.is_finite()) {
            return Err(format!("the cutoff frequency of the high-mode damping must be positive (Hz), got {}", self.above_hz));
        }
        if !(self.ratio >= 0.0 && self.ratio.is_finite()) {
            return Err(format!("the damping ratio of the high modes must not be negative, got {}", self.ratio));
        }
        Ok(())
    }

    /// The damping ratio of each natural mode whose `ω²` (rad²/s², ascending) is given: `ratio` above the
    /// cutoff, 0 at or below it.
    pub fn ratios(&self, omega_squared: &[f64]) -> Vec<f64> {
        let cutoff = 2.0 * std::f64::consts::PI * self.above_hz;
        omega_squared.iter().map(|w2| if w2.max(0.0).sqrt() > cutoff { self.ratio } else { 0.0 }).collect()
    }
}

impl ModalBody {
    /// The damping matrix of `damping` for this body's modal mass and stiffness,
    /// `M X diag(2 ζⱼ ωⱼ) Xᵀ M` with `ζⱼ` the ratio on the natural modes above the cutoff and 0 below;
    /// zero when no mode lies above it. An error if `damping` is not valid
    /// ([`HighModeDamping::validate`]), the modal mass is not positive definite or the stiffness not
    /// `m × m`.
    pub fn high_mode_damping_matrix(&self, damping: &HighModeDamping) -> Result<DMatrix<f64>, ModalError> {
        damping.validate().map_err(ModalError::HighModeDamping)?;
        let m = self.modes();
        if m == 0 {
            return Ok(DMatrix::zeros(0, 0));
        }
        let (omega_squared, _) = self.natural_modes()?;
        self.damping_matrix(&ModalDamping::Ratios(damping.ratios(&omega_squared)))
    }

    /// How many natural modes of this body lie above the cutoff of `damping` (0 if the modes cannot be
    /// computed).
    pub fn modes_above_cutoff(&self, damping: &HighModeDamping) -> usize {
        let probe = HighModeDamping { ratio: 1.0, ..*damping };
        self.natural_modes().map_or(0, |(omega_squared, _)| probe.ratios(&omega_squared).iter().filter(|&&z| z > 0.0).count())
    }
}
