//! Full-state integration with projection: the ODE of `y = [q, v]`,
//!
//! ```text
//! q̇ = T(q) v                      T(q) v = [Ṙ; ½ Gᵀ(p) ω̄; ȧ] per body
//! v̇ from [M Bᵀ; B 0] [v̇; λ] = [Q − h; γ]      (the index-1 system, Haug 1989 eq. 11.1.19)
//! ```
//!
//! with the constraints enforced by projection after every accepted step (the [`OdeSystem::accept`]
//! hook), before the final evaluation of the PECE step:
//!
//! 1. **Euler parameters** rescaled to unit norm.
//! 2. **Positions**: Newton on `Φ(q, t) = 0` with the minimum-norm correction in the metric of the
//!    mass matrix, `δv = argmin δvᵀ M δv` subject to `B δv = −Φ`, i.e. `[M Bᵀ; B 0] [δv; z] = [0; −Φ]`,
//!    mapped onto the positions by `q ← q ⊕ T(q) δv` (`Φ_q T = B`, so this is a Newton step) and the
//!    Euler parameters rescaled again. The first iterations reuse the factors of the predicted state's
//!    evaluation (a chord iteration; the two states differ by about the local error), refactoring at
//!    the current positions only if the convergence is slow. Converged when the largest `|Φ|` is below
//!    1 % of `atol` or the last correction below 10⁻³ of the error tolerance; near a singular position on
//!    to the rounding ([`super::rounding_projection`]).
//! 3. **Velocities**: the same metric, `[M Bᵀ; B 0] [δv; z] = [0; −(B v + Φ_t)]`, exact in one solve;
//!    the matrix is factored at the projected positions, and the same factors then give the
//!    accelerations at the projected state, which enter the difference table. So the projection costs
//!    no factorization beyond the two evaluations of the PECE step.
//!
//! Why the mass metric: the corrections are the ones an impulse through the joints would make (the
//! kinetic-energy-closest consistent velocity), they are independent of the units of the coordinates
//! (metres against radians against modal amplitudes), and the matrix is the one the accelerations need
//! anyway. Why project after the step and keep the difference table: the Adams formulas integrate the
//! derivative history forward from whatever `y_n` is, so replacing `y_n` by its projection is
//! consistent; the derivatives in the table were evaluated at points that missed the constraints by
//! about the local error (the predictor's) or at the projected points (the corrector's final
//! evaluation), a perturbation of the order of the local error that the projection keeps from
//! accumulating. [`ProjectionDrift`] measures it: on the slider-crank the projection moves the state by
//! about a tenth of the tolerance per step (RMS), at most about one tolerance.

use crate::data::Data;
use std::sync::Arc;

use crate::model::Model;
use crate::stage::{run_kinematic_stages, update_angle_references};

use super::kkt::{constraint_rate, position_residual, Kkt};
use crate::integrate::error_norm::{error_weight, position_sum_of_squares, root_mean_square, weighted_rms_norm};
use crate::math::{Vec3, Vec4};
use crate::stage::{euler_parameter_rates, normalize_euler_parameters, position_rates};
use super::method::{EvaluationFailure, OdeSystem};
use super::rounding_projection::ROUNDING_RESIDUAL;

/// Position Newton iterations of one projection, at most.
const PROJECTION_ITERATIONS: usize = 6;
/// Converged when the last correction is this small in the error-tolerance units of the step.
const CORRECTION_TOLERANCE: f64 = 1e-3;
/// Or when the largest position residual is below this fraction of `atol`.
const RESIDUAL_TOLERANCE: f64 = 1e-2;
/// Iterations beyond [`PROJECTION_ITERATIONS`] on the way to [`ROUNDING_RESIDUAL`] near a singular position.
const ROUNDING_ITERATIONS: usize = 4;

const NO_CONVERGENCE: EvaluationFailure =
    EvaluationFailure("the projection onto the position constraints does not converge");

/// How far the solution strayed from the constraints before each projection, and how much the
/// projection moved it: the cost of keeping the difference table while the state is projected.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ProjectionDrift {
    /// Projections made (one per accepted step).
    pub projections: usize,
    /// Largest `|Φ|` of an active constraint row at a corrected solution, before projection.
    pub max_position_residual: f64,
    /// Largest `|B v + Φ_t|` before the velocity projection.
    pub max_velocity_residual: f64,
    /// Largest `|pᵀp − 1|` before the rescaling.
    pub max_normalization_error: f64,
    /// Largest change of `(q, v)` by a projection, RMS-weighted by `atol + rtol |y|` like the local
    /// error test: values well below 1 mean that the projection moves the state by much less than the
    /// error each step is allowed.
    pub max_weighted_correction: f64,
    /// Sum of the squares of those changes (for their RMS over the steps).
    pub sum_squared_weighted_correction: f64,
    /// Position Newton iterations over all projections.
    pub newton_iterations: usize,
    /// Factorizations made because a chord iteration with the predictor's factors converged slowly.
    pub refactorizations: usize,
}

impl ProjectionDrift {
    /// RMS over the steps of the weighted change a projection makes.
    pub fn rms_weighted_correction(&self) -> f64 {
        if self.projections == 0 {
            0.0
        } else {
            (self.sum_squared_weighted_correction / self.projections as f64).sqrt()
        }
    }
}

/// The mechanism on `y = [q, v]` with projection after each step: evaluations and projections with
/// their workspaces.
pub(super) struct ProjectedMechanism {
    pub model: Arc<Model>,
    pub data: Data,
    pub kkt: Kkt,
    /// The state before the projection, for the weighted size of its change.
    y_before: Vec<f64>,
    pub nq: usize,
    nv: usize,
    rtol: f64,
    atol: f64,
    pub evaluations: usize,
    pub drift: ProjectionDrift,
    /// The step ends are near a singular position: the positions are projected on to the rounding
    /// ([`super::rounding_projection`]); set by the guard before each step's acceptance.
    pub near_singular_position: bool,
}

impl ProjectedMechanism {
    pub fn new(model: Arc<Model>, active: Vec<bool>, rtol: f64, atol: f64) -> Self {
        let (nq, nv) = (model.layout.nq, model.layout.nv);
        Self {
            data: Data::new(&model),
            kkt: Kkt::new(&model, active),
            model,
            y_before: vec![0.0; nq + nv],
            nq,
            nv,
            rtol,
            atol,
            evaluations: 0,
            drift: ProjectionDrift::default(),
            near_singular_position: false,
        }
    }

    /// `dy = [T(q) v, v̇]` with the factored KKT system, after the kinematics and constraint stages.
    fn derivatives(&mut self, t: f64, q: &[f64], v: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        self.evaluations += 1;
        let nq = self.nq;
        self.kkt.accelerations(&self.model, &mut self.data, t, &mut dy[nq..])?;
        position_rates(&self.model, q, v, &mut dy[..nq]);
        Ok(())
    }

    /// Newton on `Φ(q, t) = 0` by minimum-norm (mass metric) corrections; `v` only feeds the kinematics.
    /// Near a singular position ([`near_singular_position`](Self::near_singular_position)) on to
    /// [`ROUNDING_RESIDUAL`] while the residual still falls ([`super::rounding_projection`]).
    fn project_positions(&mut self, t: f64, q: &mut [f64], v: &[f64]) -> Result<(), EvaluationFailure> {
        let model = &*self.model;
        let to_rounding = self.near_singular_position;
        let iterations = if to_rounding { PROJECTION_ITERATIONS + ROUNDING_ITERATIONS } else { PROJECTION_ITERATIONS };
        let mut previous = f64::INFINITY;
        let mut fresh = false;
        // The ordinary test is met: the residual within 1 % of `atol` or the last correction small.
        let mut converged = false;
        for it in 0..=iterations {
            if it == iterations && !to_rounding {
                break;
            }
            run_kinematic_stages(model, &mut self.data, t, q, v);
            let residual = position_residual(&self.data, &self.kkt.active);
            if it == 0 {
                self.drift.max_position_residual = self.drift.max_position_residual.max(residual);
            }
            converged |= residual <= RESIDUAL_TOLERANCE * self.atol;
            if converged && (!to_rounding || residual <= ROUNDING_RESIDUAL || residual > 0.5 * previous || it == iterations) {
                return Ok(());
            }
            if it == iterations || !residual.is_finite() || (fresh && residual > 0.5 * previous) {
                return Err(NO_CONVERGENCE);
            }
            // The predictor's factors serve while the iteration contracts fast; else refactor here.
            if !self.kkt.factored || (it > 0 && residual > 0.1 * previous) {
                self.kkt.factor(model, &self.data)?;
                self.drift.refactorizations += 1;
                fresh = true;
            }
            previous = residual;
            self.kkt.min_norm_correction(&self.data, |data, r| -data.equations[r].phi)?;
            self.drift.newton_iterations += 1;
            let size = apply_correction(model, q, &self.kkt.rhs[..self.nv], self.rtol, self.atol);
            if size <= CORRECTION_TOLERANCE {
                if !to_rounding {
                    return Ok(());
                }
                converged = true;
            }
        }
        Err(NO_CONVERGENCE)
    }

    /// Corrects `v` at the (projected) positions `q` by the minimum-norm change that satisfies the
    /// velocity constraints, with the KKT factors made there; returns the residual before.
    fn project_velocities(&mut self, t: f64, q: &[f64], v: &mut [f64]) -> Result<f64, EvaluationFailure> {
        let model = &*self.model;
        run_kinematic_stages(model, &mut self.data, t, q, v);
        self.kkt.factor(model, &self.data)?;
        let active = &self.kkt.active;
        let residual =
            (0..active.len()).filter(|r| active[*r]).map(|r| constraint_rate(model, &self.data, r).abs()).fold(0.0, f64::max);
        self.kkt.min_norm_correction(&self.data, |data, r| -constraint_rate(model, data, r))?;
        for k in 0..self.nv {
            v[k] += self.kkt.rhs[k];
        }
        Ok(residual)
    }

    /// Projects an interpolated state at `t` onto the constraints as an accepted step is (Euler
    /// parameters normalized, positions by minimum-norm Newton, velocities by a minimum-norm
    /// correction), so that dense output keeps the constraints to the projection's tolerance and not
    /// only to the local error. The drift statistics, which describe the accepted steps, are left as
    /// they were.
    pub fn project_output(&mut self, t: f64, q: &mut [f64], v: &mut [f64]) -> Result<(), EvaluationFailure> {
        let model = &*self.model;
        let drift = self.drift;
        normalize_euler_parameters(model, q, |_, _| {});
        let projected = self.project_positions(t, q, v);
        self.drift = drift;
        projected?;
        self.project_velocities(t, q, v).map(|_| ())
    }
}

impl ProjectedMechanism {
    /// A predicted state `y` at `t` onto the constraints (as [`project_output`](Self::project_output)),
    /// then `dy = f(t, y)` there; the drift statistics are left as they were.
    pub fn predicted(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let (q, v) = y.split_at_mut(self.nq);
        self.project_output(t, q, v)?;
        run_kinematic_stages(&self.model, &mut self.data, t, q, v);
        self.derivatives(t, q, v, dy)
    }
}

impl OdeSystem for ProjectedMechanism {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let (q, v) = y.split_at(self.nq);
        run_kinematic_stages(&self.model, &mut self.data, t, q, v);
        self.kkt.factor(&self.model, &self.data)?;
        self.derivatives(t, q, v, dy)
    }

    fn accept(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let model = Arc::clone(&self.model);
        let model = &*model;
        self.y_before.copy_from_slice(y);
        let (q, v) = y.split_at_mut(self.nq);
        let normalization = normalize_euler_parameters(model, q, |_, _| {});
        self.drift.max_normalization_error = self.drift.max_normalization_error.max(normalization);
        self.project_positions(t, q, v)?;
        // Velocities at the projected positions, with factors made there (used for v̇ too).
        let velocity_residual = self.project_velocities(t, q, v)?;
        self.drift.max_velocity_residual = self.drift.max_velocity_residual.max(velocity_residual);
        run_kinematic_stages(model, &mut self.data, t, q, v);
        self.derivatives(t, q, v, dy)?;
        update_angle_references(model, &mut self.data);
        // The size of the projection's change in the units of the error test.
        let (rtol, atol) = (self.rtol, self.atol);
        let weighted =
            weighted_rms_norm(self.y_before.iter().zip(y.iter()).map(|(&b, &a)| (a - b, error_weight(atol, rtol, b))));
        let d = &mut self.drift;
        d.projections += 1;
        d.max_weighted_correction = d.max_weighted_correction.max(weighted);
        d.sum_squared_weighted_correction += weighted * weighted;
        Ok(())
    }
}

/// `q ← q ⊕ T(q) δv` with the Euler parameters rescaled; returns the RMS of the change weighted by
/// `atol + rtol |q|`.
fn apply_correction(model: &Model, q: &mut [f64], dv: &[f64], rtol: f64, atol: f64) -> f64 {
    let l = &model.layout;
    let sum = position_sum_of_squares(l, q, dv, atol, rtol);
    for b in 0..model.bodies.len() {
        let (qo, vo, m) = (l.q_offset[b], l.v_offset[b], l.modes[b]);
        // T(q) δv: δR, ½ Gᵀ δω̄, δa.
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        let dp = euler_parameter_rates(&p, &Vec3::new(dv[vo + 3], dv[vo + 4], dv[vo + 5]));
        for k in 0..3 {
            q[qo + k] += dv[vo + k];
        }
        for k in 0..4 {
            q[qo + 3 + k] += dp[k];
        }
        for k in 0..m {
            q[qo + 7 + k] += dv[vo + 6 + k];
        }
    }
    normalize_euler_parameters(model, q, |_, _| {});
    root_mean_square(sum, l.nq)
}
