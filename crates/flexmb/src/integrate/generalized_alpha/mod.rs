//! The generalized-α method for the constrained equations of motion: Chung and Hulbert's scheme (1993) in
//! the form Arnold and Brüls analysed for constrained mechanical systems (2007), on the Lie group of the
//! body positions (Brüls and Cardona 2010, here with Euler parameters), with the stabilized index-2
//! constraints of Arnold, Cardona and Brüls (2016), and a local error estimate for the step size.
//!
//! **Step.** From `t_n` to `t_{n+1} = t_n + h`, with the acceleration-like variables `ã`:
//!
//! ```text
//! (1 − α_m) ã_{n+1} + α_m ã_n = (1 − α_f) v̇_{n+1} + α_f v̇_n
//! v_{n+1} = v_n + h (1 − γ) ã_n + h γ ã_{n+1}
//! Δ_n     = v_n + h (½ − β) ã_n + h β ã_{n+1}
//! q_{n+1} = q_n ∘ exp(h Δ_n + (B(q_n) + B(q_{n+1}))ᵀ μ)     R += ·,  p ← p ⊗ exp(½ ·),  a += ·
//! M(q_{n+1}) v̇_{n+1} + h(q_{n+1}, v_{n+1}) − Q(q_{n+1}, v_{n+1}, t_{n+1}) + Bᵀ λ_{n+1} = 0
//! B(q_{n+1}) v_{n+1} + Φ_t = 0                                   (velocity constraints)
//! Φ(q_{n+1}, t_{n+1}) = 0                                          (position constraints)
//! ```
//! with Chung and Hulbert's parameters from the spectral radius at infinite frequency `ρ∞ ∈ [0, 1]`:
//! `α_m = (2ρ∞ − 1)/(ρ∞ + 1)`, `α_f = ρ∞/(ρ∞ + 1)`, `γ = ½ + α_f − α_m`, `β = ¼ (γ + ½)²` (second order,
//! unconditionally stable for linear problems, high-frequency amplitudes multiplied by `ρ∞` per step;
//! `ρ∞ = 1` is the trapezoidal rule without numerical damping).
//!
//! **Constraints.** Arnold and Brüls's index-3 form imposes only `Φ(q_{n+1}) = 0`: the velocities then
//! satisfy the velocity constraints only to the integration error, and velocities and multipliers
//! suffer an order reduction in the first steps unless the start is perturbed. Here
//! the stabilized index-2 form (Arnold, Cardona and Brüls) is used instead: `λ` enforces the velocity
//! constraints on `v_{n+1}`, and a second multiplier `μ` (a Gear–Gupta–Leimkuhler correction, zero in the
//! limit `h → 0`) moves the positions onto `Φ = 0` in velocity space. Both constraint levels then hold
//! to the Newton tolerance at every step; no projection is made after the step. The correction is made
//! along `(B(q_n) + B(q_{n+1}))ᵀ`, Hairer's symmetric projection, rather than along `B(q_{n+1})ᵀ` alone:
//! at `ρ∞ = 1` the step is then symmetric (time-reversible), and a conservative pendulum's energy stays
//! bounded; with the one-sided correction it drifted by `O(h³)` per period (2e-4 J per period at 80
//! steps per period). `B(q_{n+1})` in the correction is that of the previous Newton iterate (the
//! difference vanishes at convergence).
//!
//! **Newton iteration.** Unknowns `x = [v̇_{n+1}, λ_{n+1}, μ̃]`, predictor `[v̇_n, λ_n, 0]` extrapolated
//! linearly through the last step (`v̇_n + h (v̇_n − v̇_{n−1})/h_{n−1}`, the same for `λ`; at a fixed step,
//! which need not resolve the motion, the attempt is repeated from `[v̇_n, λ_n, 0]` held when the iteration
//! from the extrapolation fails, and the predictor holds them for the rest of the run: the peer's rigid
//! pendulum at the fixed step 7e-4 s took 4.2 (rtol 1e-8) and 3.4 (rtol 1e-5) solves per step from the
//! held predictor, 3.2 and 2.1 extrapolated). Held constant,
//! the multipliers' predictor was the largest part of the first increment (the rigid pendulum at rtol
//! 3e-6: 300 to 2,000 of the step's share, measured as impulses; extrapolated, 4 to 6), and the
//! iteration took 3.7 solves per step (43,881 for 11,841 steps; now 2.0, with `NEWTON_TOLERANCE`, a
//! floor of 0.03 of the share with error per unit step). The velocity
//! constraints are scaled by `1/(γ'h)` and the position constraints by `1/(β'h²)`, `μ = β'h² μ̃`, with
//! `β' = β (1 − α_f)/(1 − α_m)`, `γ' = γ (1 − α_f)/(1 − α_m)` (the derivatives of `h² β ã_{n+1}` and
//! `h γ ã_{n+1}` with respect to `v̇_{n+1}`), so that the iteration matrix tends to the index-1 matrix
//! `[M Bᵀ 0; B 0 0; B 0 BBᵀ]` as `h → 0` rather than becoming singular (see `iteration_matrix.rs`).
//! The iteration is a modified Newton method: `M` and `B` are exact and fresh at every factorization, with
//! the tangent `J_r` of the exponential map in the position derivatives and the coupling of `μ̃` to every
//! row; the stiffness and damping parts come from finite differences, kept until the iteration fails
//! with them (or converged with a rate above 0.1 with factors made at its own predictor, when they are
//! re-evaluated before the next step), or until a second [`RateMonitor`], which counts the time from
//! their evaluation and learns from the iterations with factors made at their own predictor of parts
//! from an earlier step, predicts that such an iteration would fail: they are then re-evaluated ahead of
//! the factorization (the IFToMM A05 flyball governor, whose stiff springs turn with the shaft: Newton
//! failures in 452 of 567 steps at tolerance 1e-3 without it, 23 with it). The factors are reused across steps, and across step sizes within
//! 5 % of theirs, while the convergence rate extrapolated in the time since they were made
//! ([`RateMonitor`]) predicts convergence; they are made again at the predictor when it does not, or when an
//! iteration with them fails. At a fixed step, reused factors carry their rate into the next iteration, as
//! IDA carries `ss = ρ/(1 − ρ)`: a first increment that the expected rate brings below the tolerance has
//! converged without a second solve. Before, every attempt refactored (slider-crank at tolerance 3e-11: 119,994
//! factorizations for 119,984 steps, now 4,111, the same steps and 1.8 times the Newton iterations, the run
//! 2.4 times faster, min of 3 interleaved runs). A
//! unit test checks the matrix against central differences of the step equations entry by entry.
//! Convergence is tested on the position, velocity and multiplier increments in the weighted norm of
//! the error test, with the BDF's rate-based criterion; an unconverged step is never accepted.
//!
//! **Step size.** The local error of the positions is estimated as
//! `e_q = h² (β − 1/6)(ã_{n+1} − ã_n)` (Géradin and Cardona 2001, after Zienkiewicz and Xie 1991), in
//! velocity space and mapped to `q` (rotations through `δp = ½ Gᵀ δθ̄`, as the BDF weighs the Euler
//! parameters). That of the velocities is the difference from a third-order velocity,
//! `e_v = v_{n+1} − (v_n + ∫ p)`, `p` the quadratic through the accelerations `v̇` at `t_{n−1}, t_n, t_{n+1}`
//! (a variable-step Adams–Moulton formula; `≈ −h³ v⃛/12` for `ρ∞ = 1`). The positions alone do not
//! suffice: on a fast top the body-frame angular velocity turns at the spin rate, and the velocities'
//! `h³ v⃛` error was 150 times the tolerance while the position estimate passed, which put the axis
//! 0.1 rad off the BDF's within one precession period. Both are measured in one weighted RMS norm with
//! `atol + rtol |y|`, as the BDF's error test; a step with `‖e‖ ≤ 1` is accepted and the next one is
//! `h · clamp(0.9 ‖e‖^(−1/3), 0.2, 5)` (at most `h` after a rejection), a step with `‖e‖ > 1` is retried
//! with that factor, and a step whose Newton iteration does not converge (with fresh finite-difference
//! parts) is retried with `h/2`. Away from singular positions the next step is chosen from the estimate
//! extrapolated two steps ahead along the trend of its error constant (`error_trend.rs`): steps that follow
//! the motion late pump energy into a conservative mechanism (the double four-bar at rtol 1e-3 was 10.1
//! tolerances off, now 6.6, in as many steps). On a change of step size `ã_n` is moved to the new size (see
//! `predict`); without that, 15 % of the steps of a slider-crank at tolerance 1e-8 were
//! rejected, with it 0.1 %. Near a singular position an estimate within the rounding that the
//! conditioning amplifies there (`SingularPassage::estimate_beyond_rounding`) passes, and the next step is
//! as long as this one, or as the last step whose estimate was measured, whichever is longer: it neither
//! shrinks onto the rounding nor grows on an estimate that no longer measures the truncation error (grown
//! by 1.64 a step, the steps across the double four-bar's first position reached 6.7e-4 s on estimates of
//! up to 3,000 shares, and the passage lost 1.9e-6 J; docs/accuracy.md, *Generalized-α's floor at the
//! passages*). The first step is `h_init` or is chosen from the initial velocities and
//! accelerations; `h_max` and `max_steps` of [`Tolerances`] hold. [`GeneralizedAlphaConfig::fixed_step`]
//! switches the error control off.
//!
//! **Start.** `ã_0 = v̇_0`, the consistent accelerations of the driver. (Arnold and Brüls's perturbed
//! start `ã_0 = v̇(t_0 + (α_m − α_f) h)` would remove an `O(h)` transient of `ã`; it does not change the
//! second order of `q` and `v`, and `α_m = α_f` at `ρ∞ = 1`.)
//!
//! **Dense output.** Cubic Hermite interpolation within the last step: the positions in velocity space
//! (`q(t) = q_n ∘ exp(u(s))`, `u` the cubic with `u(0) = 0`, `u(1)` the step's increment, `u'(0) = h v_n`,
//! `u'(1) = h J_r(u(1))⁻¹ v_{n+1}` for the rotations), the velocities from `v` and `v̇` at both ends.
//!
//! **Measured** (`tests/generalized_alpha.rs`): order 2.00 in positions, velocities and multipliers at
//! fixed step for `ρ∞ = 1, 0.9, 0.5` (pendulum against a BDF at 1e-12), 2.00 for the dense output; a
//! conservative pendulum at `ρ∞ = 1`, 80 steps per period, keeps its mean energy to 1e-7 of the swing over
//! 100 periods; at `ρ∞ = 0.5` a stiff spring–mass at `h ω = 10` loses its energy (5e-3 J to 1e-18 J within
//! 0.5 s) while the swing it rides on stays within 6e-4 rad of the BDF's; `ρ∞ = 1` keeps that energy.
//! With error control the method takes about as many steps as the BDF at tolerance 1e-4 and 2 to 10 times
//! as many at 1e-6 to 1e-8 (it is of order 2, the BDF of up to 5); on the shipped flexible pendulum
//! (rtol 1e-6) it takes 1223 steps to the BDF's 2070.

mod error_trend;
mod finest_tolerance;
mod iteration_matrix;

use error_trend::ErrorTrend;

pub(crate) use iteration_matrix::IterationMatrix;
use crate::stage::{retract, right_jacobian_inverse};

use crate::analysis::{Accelerations, OperatingPoint, State};
use crate::data::Data;
use crate::integrate::diagnosis::{self, EquationRow};
use crate::integrate::error_norm::{error_weight, position_sum_of_squares, root_mean_square};
use crate::integrate::newton::{self, ConvergenceTest, NewtonSystem};
use crate::integrate::newton_rounding::RoundingFloor;
use crate::integrate::share_floor::ShareFloor;
use crate::integrate::singular_position::SingularPassage;
use crate::integrate::RateMonitor;
use std::sync::Arc;

use crate::integrate::{
    check_len, AttemptFailure, CheckpointError, GeneralizedAlphaCheckpoint, GeneralizedAlphaConfig, IntegrationError,
    Integrator, IntegratorCheckpoint, Stats, Tolerances,
};
use crate::math::Vec3;
use crate::model::Model;
use crate::stage::{add_jacobian_transpose, equations_of_motion, run_kinematic_stages, update_angle_references};

const NEWTON_MAXITER: usize = 6;
/// Range of `h/h_f` in which the factors made for the step size `h_f` are reused (while the convergence
/// rate predicts convergence): the constraint rows are scaled so that the matrix tends to an
/// `h`-independent one as `h → 0`, so only the damping and stiffness parts `γ'h C + β'h² K` change with `h`.
/// Within 0.8–1.25 the flexible pendulum (modes to 573 Hz, where `β'h² K` dominates) took 19 % more steps
/// (the chord iteration's leftovers in its stiff modes move the error estimate); within 1/1.05–1.05 as
/// many as with a factorization at every attempt (10534 against 10497 at tolerance 1e-4).
const REUSE_MIN: f64 = 1.0 / 1.05;
const REUSE_MAX: f64 = 1.05;
/// A converged Newton iteration slower than this (with finite-difference parts from an earlier step)
/// has the parts re-evaluated before the next step.
const SLOW_RATE: f64 = 0.1;
/// The Newton tolerance, in the step's share of the tolerance, is at least this (the common one,
/// `√rtol` at most 0.03, is 1.7e-3 at rtol 3e-6). The increments are measured against the step's share,
/// so a fixed fraction of it keeps the unresolved part a fixed fraction of the local error at every
/// tolerance. Only with error per unit step (a share below 1): with error per step the common one is
/// kept (a pendulum with redundant rows moved 1.5e-7 m off the one without them at rtol 1e-7 with 0.03,
/// the two iterations stopping at different iterates). Rigid pendulum of models/peer at 3e-6: 24,080 Newton iterations for 11,866 steps (34 error
/// test failures) against 32,647 for 11,854 (17) with `√rtol`; 0.01 gave 25,654.
const NEWTON_TOLERANCE: f64 = 0.03;
/// The floor of a step's share of the tolerance, relative to the solution: `SHARE_FLOOR / rtol`, the BDF's
/// ([`FINE_STEP_FLOOR`](crate::integrate::share_floor::FINE_STEP_FLOOR), 1e-13), not the Adams method's
/// 1e-12. Over the run the steps of this second-order method reach the floor from about rtol 1e-7 on, and
/// the error is then about the floor times the number of steps: with 1e-12, 1e-7 to 1.2e-6 relative at
/// every rtol from 1e-8 to 1e-10 on six cases (the same steps at each; docs/accuracy.md, *Generalized-α
/// over the run's span*), 12 tolerances on the double four-bar at 1e-7; with 1e-13 within 5.4 tolerances
/// at 1e-7 on each, at up to 1.9 times the steps (the slider-crank, 694,281 against 372,786).
/// [`GeneralizedAlpha::FINEST_OVER_RUN`] follows from it.
const SHARE_FLOOR: f64 = crate::integrate::share_floor::FINE_STEP_FLOOR;
const SAFETY: f64 = 0.9;
const MIN_FACTOR: f64 = 0.2;
const MAX_FACTOR: f64 = 5.0;

/// The parameters `α_m, α_f, γ, β` of the method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coefficients {
    pub alpha_m: f64,
    pub alpha_f: f64,
    pub gamma: f64,
    pub beta: f64,
}

impl Coefficients {
    /// Chung and Hulbert's second-order parameters with high-frequency spectral radius `rho`.
    pub fn from_spectral_radius(rho: f64) -> Self {
        let alpha_m = (2.0 * rho - 1.0) / (rho + 1.0);
        let alpha_f = rho / (rho + 1.0);
        let gamma = 0.5 + alpha_f - alpha_m;
        let beta = 0.25 * (gamma + 0.5).powi(2);
        Self { alpha_m, alpha_f, gamma, beta }
    }
    /// `∂ã_{n+1}/∂v̇_{n+1} = (1 − α_f)/(1 − α_m)`.
    fn a_rate(&self) -> f64 {
        (1.0 - self.alpha_f) / (1.0 - self.alpha_m)
    }
    /// `β' = β (1 − α_f)/(1 − α_m)`: `∂(h Δ_n)/∂v̇_{n+1} = β' h²`.
    pub fn beta_prime(&self) -> f64 {
        self.beta * self.a_rate()
    }
    /// `γ' = γ (1 − α_f)/(1 − α_m)`: `∂v_{n+1}/∂v̇_{n+1} = γ' h`.
    pub fn gamma_prime(&self) -> f64 {
        self.gamma * self.a_rate()
    }
}

/// The generalized-α integrator with its workspaces; one [`step`](Self::step) is one accepted step.
pub struct GeneralizedAlpha {
    model: Arc<Model>,
    data: Data,
    active: Vec<bool>,
    tolerances: Tolerances,
    fixed_step: Option<f64>,
    coefficients: Coefficients,
    nv: usize,
    nc: usize,
    /// The floor under a step's share of the tolerance (error per unit step).
    share_floor: ShareFloor,
    /// The trend of the local error estimates, extrapolated to choose the next step (`error_trend.rs`).
    error_trend: ErrorTrend,
    /// The level below which the Newton increments are the residual's rounding.
    rounding: RoundingFloor,
    /// Of the last Newton iteration: its smallest increment after the first (in the step's share), and
    /// whether it converged by the rounding floor.
    newton_stalled: f64,
    newton_at_floor: bool,
    /// The approach to a singular position: its predicted window, which the step ends avoid.
    singular: SingularPassage,
    /// The last accepted step whose error estimate was measured, not passed as the rounding amplified near
    /// a singular position: the longest step taken while estimates are passed so (module documentation,
    /// *Step size*). Not in a checkpoint (0 after a restore: the steps then only stay), as the guard's state.
    resolved_step: f64,
    /// The factor by which the conditioning at the attempt's end amplifies the rounding (1 away from a
    /// singular position).
    amplification: f64,
    matrix: IterationMatrix,
    /// The finite-difference parts were evaluated during the current step.
    derivatives_current: bool,
    /// Re-evaluate them at the next step's predictor (the last iteration converged slowly).
    refresh_next: bool,
    /// The predictor holds `v̇_n` and `λ_n` instead of extrapolating them: at a fixed step, for the rest of
    /// the run after an iteration from the extrapolation failed (see [`predict`](Self::predict)).
    hold_predictor: bool,
    /// The step size the current factors were made for; `None` when they must be made again.
    factored_h: Option<f64>,
    /// The convergence rate of the iterations with the current factors, which predicts the next one's.
    rate: RateMonitor,
    /// The convergence rate of the iterations with factors made at their own predictor of finite-difference
    /// parts evaluated at an earlier step, which predicts whether those parts must be evaluated again
    /// before the next factorization.
    derivative_rate: RateMonitor,
    t: f64,
    /// Step size planned for the next step.
    h: f64,
    /// The accepted state at `t`: positions, velocities, accelerations, `ã`, multipliers.
    q: Vec<f64>,
    v: Vec<f64>,
    vdot: Vec<f64>,
    a_tilde: Vec<f64>,
    /// `ã_n` shifted to the step size of the current attempt (see [`predict`](Self::predict)).
    a_start: Vec<f64>,
    lambda: Vec<f64>,
    /// The last step, for dense output: its start and size, the state at its start, and its position
    /// increment in velocity space.
    t_old: f64,
    h_last: f64,
    q_old: Vec<f64>,
    v_old: Vec<f64>,
    vdot_old: Vec<f64>,
    /// The size of the step before the last and the velocities at its start (0 and unused until two steps
    /// were taken): with the last step's and the attempt's, three velocity differences, of which the error
    /// estimate takes the curvature of the accelerations (see [`error_norm`](Self::error_norm)).
    h_before_last: f64,
    v_before_last: Vec<f64>,
    /// The multipliers at the last step's start, from which the predictor extrapolates them.
    lambda_old: Vec<f64>,
    d_last: Vec<f64>,
    /// Newton unknowns `[v̇, λ, μ̃]`, increment and residual.
    x: Vec<f64>,
    dx: Vec<f64>,
    res: Vec<f64>,
    /// The state of the current iterate: `q_{n+1}`, `v_{n+1}`, `ã_{n+1}`, `h Δ_n + Bᵀμ`.
    q_new: Vec<f64>,
    v_new: Vec<f64>,
    a_new: Vec<f64>,
    d_step: Vec<f64>,
    /// `Bᵀμ` of the current iterate, of the next one, and `μ` itself.
    delta: Vec<f64>,
    delta_new: Vec<f64>,
    mu: Vec<f64>,
    /// Scratch of length `nv` (error estimate, increments, interpolation).
    work: Vec<f64>,
    /// The counters so far.
    pub stats: Stats,
}

impl GeneralizedAlpha {
    /// Starts from a consistent state (assembled, velocity-analysed) and its accelerations, with the
    /// error tolerances and step limits of `tolerances` and the spectral radius (and fixed step, if any)
    /// of `alpha`.
    pub fn new(
        model: Arc<Model>,
        state: &State,
        accelerations: &Accelerations,
        tolerances: Tolerances,
        alpha: GeneralizedAlphaConfig,
    ) -> Result<Self, IntegrationError> {
        crate::integrate::check_start(&model, state, accelerations)?;
        let t = state.t;
        if let Err(reason) = alpha.validate() {
            return Err(IntegrationError::InitialConditions {
                t,
                reason: format!("invalid method settings: {reason}"),
            });
        }
        let finite = |x: &[f64]| x.iter().all(|x| x.is_finite());
        if !(finite(&state.q) && finite(&state.v) && finite(&accelerations.vdot) && finite(&accelerations.lambda)) {
            return Err(IntegrationError::InitialConditions {
                t,
                reason: "initial positions, velocities, accelerations or multipliers are not finite".into(),
            });
        }
        let tolerances = tolerances.attainable().0;
        let l = &model.layout;
        let (nq, nv, nc) = (l.nq, l.nv, l.nc);
        let h0 = alpha
            .fixed_step
            .or(tolerances.h_init)
            .unwrap_or_else(|| initial_step(&model, &tolerances, &state.q, &state.v, &accelerations.vdot))
            .min(tolerances.h_max);
        let mut data = Data::new(&model);
        run_kinematic_stages(&model, &mut data, t, &state.q, &state.v);
        data.angle_reference.fill(0.0);
        update_angle_references(&model, &mut data);
        let mut integrator = Self {
            active: state.active.clone(),
            tolerances,
            fixed_step: alpha.fixed_step,
            coefficients: Coefficients::from_spectral_radius(alpha.spectral_radius),
            nv,
            nc,
            share_floor: ShareFloor::default(),
            error_trend: ErrorTrend::default(),
            rounding: RoundingFloor::default(),
            newton_stalled: f64::INFINITY,
            newton_at_floor: false,
            singular: SingularPassage::new(&model, &state.active, tolerances.rtol),
            resolved_step: 0.0,
            amplification: 1.0,
            matrix: IterationMatrix::new(&model),
            data,
            derivatives_current: false,
            refresh_next: false,
            hold_predictor: false,
            factored_h: None,
            rate: RateMonitor::default(),
            derivative_rate: RateMonitor::default(),
            t,
            h: h0,
            q: state.q.clone(),
            v: state.v.clone(),
            vdot: accelerations.vdot.clone(),
            a_tilde: accelerations.vdot.clone(),
            a_start: accelerations.vdot.clone(),
            lambda: accelerations.lambda.clone(),
            t_old: t,
            h_last: 0.0,
            q_old: state.q.clone(),
            v_old: state.v.clone(),
            h_before_last: 0.0,
            v_before_last: state.v.clone(),
            vdot_old: accelerations.vdot.clone(),
            lambda_old: accelerations.lambda.clone(),
            d_last: vec![0.0; nv],
            x: vec![0.0; nv + 2 * nc],
            dx: vec![0.0; nv + 2 * nc],
            res: vec![0.0; nv + 2 * nc],
            q_new: vec![0.0; nq],
            v_new: vec![0.0; nv],
            a_new: vec![0.0; nv],
            d_step: vec![0.0; nv],
            delta: vec![0.0; nv],
            delta_new: vec![0.0; nv],
            mu: vec![0.0; nc],
            work: vec![0.0; nv],
            stats: Stats::default(),
            model,
        };
        integrator.matrix.set_start_jacobian(&integrator.model, &integrator.data, &integrator.active);
        let at = OperatingPoint::new(state, accelerations);
        let evaluations =
            integrator.matrix.derivatives.evaluate_at(&integrator.model, &mut integrator.data, &integrator.active, &at);
        integrator.stats.jacobian_evaluations += 1;
        integrator.stats.residual_evaluations += evaluations;
        integrator.derivative_rate.evaluated(t);
        Ok(integrator)
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }
    /// Step size planned for the next step.
    pub fn step_size(&self) -> f64 {
        self.h
    }
    /// Positions at the current time.
    pub fn q(&self) -> &[f64] {
        &self.q
    }
    /// Velocities at the current time.
    pub fn v(&self) -> &[f64] {
        &self.v
    }
    /// Accelerations `v̇` at the current time (those of the equations of motion, not `ã`).
    pub fn accelerations(&self) -> &[f64] {
        &self.vdot
    }
    /// Multipliers `λ` at the current time.
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }
    /// The complete state between two steps.
    pub fn checkpoint(&self) -> GeneralizedAlphaCheckpoint {
        let (stiffness, damping, start_jacobian) = self.matrix.stored_parts();
        GeneralizedAlphaCheckpoint {
            t: self.t,
            h: self.h,
            q: self.q.clone(),
            v: self.v.clone(),
            vdot: self.vdot.clone(),
            a_tilde: self.a_tilde.clone(),
            lambda: self.lambda.clone(),
            t_old: self.t_old,
            h_last: self.h_last,
            q_old: self.q_old.clone(),
            v_old: self.v_old.clone(),
            vdot_old: self.vdot_old.clone(),
            h_before_last: self.h_before_last,
            v_before_last: self.v_before_last.clone(),
            lambda_old: self.lambda_old.clone(),
            d_last: self.d_last.clone(),
            derivatives_current: self.derivatives_current,
            share_floor: self.share_floor.stored(),
            error_trend: self.error_trend.stored(),
            newton_rounding: self.rounding.stored(),
            refresh_next: self.refresh_next,
            predictor_held: self.hold_predictor,
            factored_h: self.factored_h,
            kept_pivots: self.matrix.kept_pivots().map(<[usize]>::to_vec),
            factored_matrix: if self.factored_h.is_some() { self.matrix.factored_values().to_vec() } else { Vec::new() },
            newton_rate: self.rate,
            derivative_rate: self.derivative_rate,
            stiffness: stiffness.to_vec(),
            damping: damping.to_vec(),
            start_jacobian: start_jacobian.to_vec(),
            active: self.active.clone(),
            angle_reference: self.data.angle_reference.clone(),
            stats: self.stats,
        }
    }

    /// Continues from `c`, taken of a generalized-α integrator on the same model with the same settings.
    pub fn restore(&mut self, c: &GeneralizedAlphaCheckpoint) -> Result<(), CheckpointError> {
        let (nq, nv, nc) = (self.q.len(), self.nv, self.nc);
        let (stiffness, damping, start_jacobian) = self.matrix.stored_parts();
        for (what, expected, found) in [
            ("the positions", nq, c.q.len()),
            ("the positions at the last step's start", nq, c.q_old.len()),
            ("the velocities", nv, c.v.len()),
            ("the velocities at the last step's start", nv, c.v_old.len()),
            ("the accelerations", nv, c.vdot.len()),
            ("the accelerations at the last step's start", nv, c.vdot_old.len()),
            ("ã", nv, c.a_tilde.len()),
            ("the last step's increment", nv, c.d_last.len()),
            ("the multipliers", nc, c.lambda.len()),
            ("the stiffness part", stiffness.len(), c.stiffness.len()),
            ("the damping part", damping.len(), c.damping.len()),
            ("the constraint Jacobian", start_jacobian.len(), c.start_jacobian.len()),
            ("the constraint rows in force", nc, c.active.len()),
            ("the joint angles", self.data.angle_reference.len(), c.angle_reference.len()),
        ] {
            check_len(what, expected, found)?;
        }
        self.t = c.t;
        self.h = c.h;
        self.q.copy_from_slice(&c.q);
        self.v.copy_from_slice(&c.v);
        self.vdot.copy_from_slice(&c.vdot);
        self.a_tilde.copy_from_slice(&c.a_tilde);
        self.lambda.copy_from_slice(&c.lambda);
        self.t_old = c.t_old;
        self.h_last = c.h_last;
        self.q_old.copy_from_slice(&c.q_old);
        self.v_old.copy_from_slice(&c.v_old);
        self.vdot_old.copy_from_slice(&c.vdot_old);
        // A checkpoint without them (written before they were kept): the next estimate takes the
        // curvature from the accelerations, as the first steps of a run do.
        if c.v_before_last.len() == nv {
            self.h_before_last = c.h_before_last;
            self.v_before_last.copy_from_slice(&c.v_before_last);
        } else {
            self.h_before_last = 0.0;
        }
        self.d_last.copy_from_slice(&c.d_last);
        // A checkpoint without them (written before they were kept): the predictor holds the multipliers.
        if c.lambda_old.is_empty() {
            self.lambda_old.copy_from_slice(&c.lambda);
        } else {
            check_len("the multipliers at the last step's start", nc, c.lambda_old.len())?;
            self.lambda_old.copy_from_slice(&c.lambda_old);
        }
        self.derivatives_current = c.derivatives_current;
        self.share_floor = ShareFloor::restored(c.share_floor);
        self.error_trend = ErrorTrend::restored(c.error_trend);
        self.rounding = RoundingFloor::restored(c.newton_rounding);
        self.refresh_next = c.refresh_next;
        self.hold_predictor = c.predictor_held;
        self.matrix.set_stored_parts(&c.stiffness, &c.damping, &c.start_jacobian);
        self.matrix.keep_pivots(c.kept_pivots.as_deref())?;
        self.factored_h = None;
        if c.factored_h.is_some() {
            check_len("the factored matrix", self.matrix.factored_values().len(), c.factored_matrix.len())?;
            if self.matrix.factor_values(&c.factored_matrix).is_ok() {
                self.factored_h = c.factored_h;
            }
        }
        self.rate = c.newton_rate;
        self.derivative_rate = c.derivative_rate;
        self.active.copy_from_slice(&c.active);
        self.data.angle_reference.copy_from_slice(&c.angle_reference);
        self.stats = c.stats;
        Ok(())
    }

    /// Evaluations of the equations one iteration-matrix evaluation costs.
    pub fn evaluations_per_jacobian(&self) -> usize {
        self.matrix.evaluations_per_jacobian()
    }

    /// Takes one accepted step, not passing `t_stop`.
    pub fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError> {
        if self.stats.steps >= self.tolerances.max_steps {
            return Err(IntegrationError::TooManySteps { t: self.t, max_steps: self.tolerances.max_steps });
        }
        let t = self.t;
        if t_stop <= t {
            return Ok(());
        }
        let min_step = crate::integrate::smallest_step(t, t_stop);
        let mut h = self.h.min(self.tolerances.h_max);
        // Why the last attempt failed; described (which allocates) only if the step size underflows.
        let mut failure = AttemptFailure::None;
        let mut rejected = false;
        loop {
            if h < min_step {
                let reason = self.describe_failure(failure);
                return Err(IntegrationError::StepSizeTooSmall { t, h, reason });
            }
            // The last step ends on t_stop, stretched by up to 1e-4 h rather than leaving a sliver.
            let reach = t + h * (1.0 + 1e-4) >= t_stop - 4.0 * f64::EPSILON * t_stop.abs();
            let (mut t_new, mut h_step) = if reach { (t_stop, t_stop - t) } else { (t + h, h) };
            // Not at a step end where a singular position leaves the constraints ill-conditioned.
            match self.singular.placed_end(t, t_new, self.share_floor.share_above(&self.tolerances, h_step, SHARE_FLOOR)) {
                Some(end) if end < t_stop && self.fixed_step.is_none() => (t_new, h_step) = (end, end - t),
                _ => self.singular.asked = None,
            }
            // Whether the rounding there matters is judged against the share the step's length gives, not
            // the floors under it: a noise floor raised near the position would switch the guard off, and the
            // Newton iteration, no longer allowed the amplified rounding, then failed at every step size (the
            // four-bar at 1e-8 over the run, 12 µs after its seventh position, steps collapsing to 1e-13 s).
            let base_share = self.tolerances.step_share(t_new - t);
            self.amplification = SingularPassage::quadratic_beyond(self.singular.amplification(t, t_new, base_share));
            let newton_tolerance = self.newton_tolerance(h_step);
            if self.refresh_next
                || !self.derivatives_current
                    && self.derivative_rate.expects_failure(t_new, newton_tolerance, NEWTON_MAXITER)
            {
                // Slow last time, or the rate measured with parts from an earlier step, grown with the time
                // since they were evaluated, says that factors made of them here would fail.
                self.refresh_next = false;
                self.refresh_derivatives(t_new, h_step);
            }
            self.predict(h_step);
            self.evaluate_residual(t_new, h_step);
            // The factors of a nearby step size are reused while the convergence rate, grown with the time
            // since they were made, predicts convergence.
            let reused = self.factored_h.is_some_and(|h_f| (REUSE_MIN..=REUSE_MAX).contains(&(h_step / h_f)))
                && !self.rate.expects_failure(t_new, newton_tolerance, NEWTON_MAXITER);
            let factored = reused || self.factor_at(t_new, h_step);
            let mut converged = factored && self.newton(t_new, h_step, reused);
            if !converged && factored && !reused && self.amplification > 1.0 {
                // Near a singular position the matrix of the predictor is that of a Jacobian whose smallest
                // singular value changes fast against itself, and the chord iteration from it converges too
                // slowly: the iteration continues from its last iterate with the matrix made there, rather
                // than halving the step, which brings the step end nearer the position (module documentation, *Singular positions*).
                self.state_from_unknowns(h_step);
                self.evaluate_residual(t_new, h_step);
                converged = self.factor_at(t_new, h_step) && self.newton(t_new, h_step, false);
            }
            if !converged {
                if factored {
                    self.stats.newton_failures += 1;
                }
                if reused {
                    // Made for another state or step size: made again here before anything else.
                    self.factored_h = None;
                    continue;
                }
                if self.fixed_step.is_some() && !self.hold_predictor && self.h_last > 0.0 {
                    // A fixed step need not resolve the motion (an unresolved stiff mode, damped or not, makes
                    // `v̇` alternate from step to step): from the held predictor before anything else, and
                    // for the rest of the run.
                    self.hold_predictor = true;
                    continue;
                }
                if !self.derivatives_current {
                    self.refresh_derivatives(t_new, h_step);
                    continue;
                }
                // Increments that shrank neither with the iterations nor with the step are the residual's
                // rounding: the attempt is repeated with them as its floor.
                let share = self.share_floor.share_above(&self.tolerances, h_step, SHARE_FLOOR);
                if factored && self.rounding.failed_with_fresh_matrix(self.newton_stalled * share, f64::INFINITY, self.tolerances.rtol) {
                    continue;
                }
                failure = if factored {
                    AttemptFailure::Newton { t_new, step: h_step }
                } else {
                    AttemptFailure::Singular { t_new, step: h_step }
                };
                h = 0.5 * h_step;
                rejected = true;
                continue;
            }
            let mut error_norm = self.error_norm(h_step);
            let share = self.share_floor.share_above(&self.tolerances, h_step, SHARE_FLOOR);
            if self.fixed_step.is_none() && error_norm > 1.0 && self.share_floor.is_noise(h_step, error_norm * share, self.tolerances.rtol) {
                // Noise, not error: the floor is now twice it.
                error_norm = self.error_norm(h_step);
            }
            if error_norm > 1.0 && self.rounding.covers(error_norm * self.share_floor.share_above(&self.tolerances, h_step, SHARE_FLOOR)) {
                // Within the Newton increments' rounding floor: no shorter step resolves it.
                error_norm = 1.0;
            }
            // Within the rounding of the constrained solution near a singular position: passes, and says
            // nothing of the next step.
            let measured = error_norm;
            error_norm = SingularPassage::estimate_beyond_rounding(error_norm, share, self.tolerances.rtol, self.amplification, 2);
            let within_rounding = error_norm != measured;
            if self.fixed_step.is_none() && error_norm > 1.0 {
                self.stats.error_test_failures += 1;
                failure = AttemptFailure::ErrorTest { error_norm, t_new, step: h_step };
                h = h_step * (SAFETY * error_norm.powf(-1.0 / self.tolerances.error_power_above(h_step, 3, SHARE_FLOOR))).max(MIN_FACTOR);
                if self.singular.asked.is_some() {
                    // A step moved across a singular position ends as far past it as it starts before it,
                    // whatever the step asked for within `[4/3, 2]` times that distance: retried at a factor
                    // above 2/3 it would be the same step with the same error, for ever (the four-bar at 1e-9,
                    // at its sixth position). At most half of it ends before the position instead.
                    h = h.min(0.5 * h_step);
                }
                rejected = true;
                continue;
            }
            self.accept(t_new, h_step);
            if let Some(condition) = self.singular.accepted(&self.model, &self.data, t_new) {
                self.stats.singular_position_steps += 1;
                self.stats.singular_position_condition = self.stats.singular_position_condition.max(condition);
            }
            self.stats.singular_positions = self.singular.passages;
            if self.amplification > 1.0 {
                self.stats.held_near_singular_position(self.tolerances.rtol * share);
            }
            self.rounding.accepted(self.newton_at_floor);
            if self.newton_at_floor {
                self.stats.rounding_floor_steps += 1;
                self.stats.rounding_floor = self.stats.rounding_floor.max(self.rounding.floor * self.tolerances.rtol);
            }
            self.share_floor.accepted(h_step, self.share_floor.share_above(&self.tolerances, h_step, SHARE_FLOOR));
            self.h = match self.fixed_step {
                Some(fixed) => fixed,
                None => {
                    let h_next = if within_rounding {
                        self.error_trend.forget();
                        // An estimate within the amplified rounding says nothing of the truncation error: the
                        // step neither grows nor shrinks on it, and returns to the last step whose estimate
                        // was measured (see `resolved_step`).
                        if rejected {
                            h_step
                        } else {
                            h_step.max(self.resolved_step)
                        }
                    } else {
                        self.resolved_step = h_step;
                        let power = self.tolerances.error_power_above(h_step, 3, SHARE_FLOOR);
                        // For where the motion will be (`error_trend.rs`); not near a singular position, where the
                        // steps follow the passage's conditioning rather than the motion.
                        let error_norm = if self.singular.near() {
                            self.error_trend.forget();
                            error_norm
                        } else {
                            self.error_trend.predicted(error_norm, h_step, power)
                        };
                        let factor = if error_norm > 0.0 {
                            (SAFETY * error_norm.powf(-1.0 / power)).clamp(MIN_FACTOR, MAX_FACTOR)
                        } else {
                            MAX_FACTOR
                        };
                        h_step * if rejected { factor.min(1.0) } else { factor }
                    };
                    // A step shortened to end on t_stop does not shrink the next one.
                    if h_step < h && !rejected {
                        h_next.max(h)
                    } else {
                        h_next
                    }
                }
            }
            .min(self.tolerances.h_max);
            return Ok(());
        }
    }

    /// The predictor `x = [v̇_n, λ_n, 0]` and its state. `ã_n` approximates `v̇(t_n + (α_m − α_f) h)` for the
    /// step size `h` it was computed with (Arnold and Brüls); for a new step size it is moved along
    /// `v̈ ≈ (v̇_n − v̇_{n−1})/h_{n−1}` by `(α_m − α_f)(h − h_{n−1})`, without which every change of step size
    /// costs a first-order error in the velocities.
    fn predict(&mut self, h: f64) {
        let (nv, nc) = (self.nv, self.nc);
        let c = self.coefficients;
        let shift = if self.h_last > 0.0 { (c.alpha_m - c.alpha_f) * (h - self.h_last) / self.h_last } else { 0.0 };
        // Under error control the steps resolve the motion; a fixed step need not (`h ω = 10` on a stiff
        // spring), and there the extrapolation can overshoot so that the iteration fails: the attempt is then
        // repeated from the held predictor, which is kept for the rest of the run (`hold_predictor`).
        let ratio = if self.h_last > 0.0 && !self.hold_predictor { h / self.h_last } else { 0.0 };
        for k in 0..nv {
            let change = self.vdot[k] - self.vdot_old[k];
            self.a_start[k] = self.a_tilde[k] + shift * change;
            self.x[k] = self.vdot[k] + ratio * change;
        }
        for r in 0..nc {
            self.x[nv + r] = self.lambda[r] + ratio * (self.lambda[r] - self.lambda_old[r]);
        }
        self.x[nv + nc..].fill(0.0);
        self.delta.fill(0.0);
        self.state_from_unknowns(h);
    }

    /// `ã_{n+1}`, `v_{n+1}`, `h Δ_n + Bᵀμ` and `q_{n+1}` of the current unknowns.
    fn state_from_unknowns(&mut self, h: f64) {
        let Coefficients { alpha_m, alpha_f, gamma, beta } = self.coefficients;
        for k in 0..self.nv {
            let a_new =
                ((1.0 - alpha_f) * self.x[k] + alpha_f * self.vdot[k] - alpha_m * self.a_start[k]) / (1.0 - alpha_m);
            self.a_new[k] = a_new;
            self.v_new[k] = self.v[k] + h * ((1.0 - gamma) * self.a_start[k] + gamma * a_new);
            self.d_step[k] = h * self.v[k] + h * h * ((0.5 - beta) * self.a_start[k] + beta * a_new) + self.delta[k];
        }
        retract(&self.model.layout, &self.q, &self.d_step, &mut self.q_new);
    }

    /// The scaled residual `[g_dyn; (B v + Φ_t)/(γ'h); Φ/(β'h²)]` at the current iterate (switched-off rows:
    /// `λ_k`, `μ̃_k`), leaving the stages evaluated there in `data`.
    fn evaluate_residual(&mut self, t_new: f64, h: f64) {
        let (nv, nc) = (self.nv, self.nc);
        let (cb, cg) = (self.coefficients.beta_prime() * h * h, self.coefficients.gamma_prime() * h);
        let (vdot, rest) = self.x.split_at(nv);
        equations_of_motion(
            &self.model,
            &mut self.data,
            &self.active,
            t_new,
            &self.q_new,
            &self.v_new,
            vdot,
            &rest[..nc],
            &mut self.res[..nv + nc],
        );
        for r in 0..nc {
            if self.active[r] {
                self.res[nv + r] /= cg;
                self.res[nv + nc + r] = self.data.equations[r].phi / cb;
            } else {
                self.res[nv + r] = self.x[nv + r];
                self.res[nv + nc + r] = self.x[nv + nc + r];
            }
        }
        self.stats.residual_evaluations += 1;
    }

    /// Forms and factors the iteration matrix at the predictor of the step to `t_new` (its residual
    /// evaluated, so `data` holds `M` and `B` there); whether it could.
    fn factor_at(&mut self, t_new: f64, h: f64) -> bool {
        let factored =
            self.matrix.factor(&self.model, &self.data, &self.active, h, &self.coefficients, &self.d_step).is_ok();
        self.stats.factorizations += 1;
        self.factored_h = factored.then_some(h);
        self.rate.evaluated(t_new);
        factored
    }

    /// Re-evaluates the finite-difference parts of the iteration matrix at the predictor.
    fn refresh_derivatives(&mut self, t_new: f64, h: f64) {
        self.predict(h);
        let (nv, nc) = (self.nv, self.nc);
        let at = OperatingPoint { t: t_new, q: &self.q_new, v: &self.v_new, vdot: &self.x[..nv], lambda: &self.x[nv..nv + nc] };
        let evaluations = self.matrix.derivatives.evaluate_at(&self.model, &mut self.data, &self.active, &at);
        self.stats.jacobian_evaluations += 1;
        self.stats.residual_evaluations += evaluations;
        self.derivatives_current = true;
        self.derivative_rate.evaluated(t_new);
        self.factored_h = None;
    }

    /// The Newton tolerance of a step of size `h`, measured against the step's share of the tolerance as
    /// the local error is (see `increment_norm`): the one its iteration is tested against and the rate
    /// monitor predicts for.
    fn newton_tolerance(&self, h: f64) -> f64 {
        let share = self.share_floor.share_above(&self.tolerances, h, SHARE_FLOOR);
        let tolerance = self.tolerances.newton_tolerance_at(share);
        if share < 1.0 {
            tolerance.max(NEWTON_TOLERANCE)
        } else {
            tolerance
        }
    }

    /// Modified Newton iteration from the predictor, whose residual is in `res` and whose matrix is
    /// factored (at this attempt's predictor, or `reused` from an earlier one). Returns whether it
    /// converged; the state of the converged unknowns is then in `q_new`, `v_new`, `a_new`, `d_step`.
    fn newton(&mut self, t_new: f64, h: f64, reused: bool) -> bool {
        // Measured against the step's share of the tolerance, as the local error is (see `increment_norm`).
        let share = self.share_floor.share_above(&self.tolerances, h, SHARE_FLOOR);
        // At a fixed step, reused factors carry the rate measured with them (grown with their age, with its
        // margin): a first increment that rate brings below the tolerance has converged on its own. Not under
        // error control, whose estimate `ã_{n+1} − ã_n` sees what one solve leaves: the peer's rigid pendulum
        // at rtol 3e-6 then failed 240 error tests in 11,901 steps (36 in 11,867 without), for 4 % fewer solves.
        let carried_rate = if reused && self.fixed_step.is_some() { self.rate.expected_rate(t_new) } else { 0.0 };
        let mut test =
            ConvergenceTest::new(self.newton_tolerance(h), NEWTON_MAXITER)
                .with_round_off(self.tolerances.round_off_at(share) * SingularPassage::round_off_factor(self.amplification))
                .with_rounding_floor(self.rounding.in_share(share))
                .with_carried_rate(carried_rate);
        let outcome = newton::iterate(&mut StepEquations { integrator: self, t_new, h }, &mut test, NEWTON_MAXITER);
        self.stats.newton_iterations += outcome.solves;
        self.newton_stalled = test.smallest_after_first;
        self.newton_at_floor = outcome.converged && test.at_floor;
        // Factors made here of parts from an earlier step measure how fast those parts go stale.
        let stale_parts = !reused && !self.derivatives_current;
        if outcome.converged {
            self.state_from_unknowns(h);
            // One solve measures no rate: the carried one stays.
            if outcome.solves > 1 {
                self.rate.converged(t_new, test.slowest, test.first_increment);
            }
            if stale_parts {
                self.derivative_rate.converged(t_new, test.slowest, test.first_increment);
            }
            // Slow with factors made here: the finite-difference parts are what is stale.
            self.refresh_next = stale_parts && test.slowest > SLOW_RATE;
        } else {
            self.rate.failed(t_new, test.failed_rate(), test.first_increment);
            if stale_parts {
                self.derivative_rate.failed(t_new, test.failed_rate(), test.first_increment);
            }
        }
        outcome.converged
    }

    /// Weighted RMS norm of a Newton increment: the position increment `β'h² Δv̇ + Δ(Bᵀμ)` and the
    /// velocity increment `γ'h Δv̇` in the weights of the error test, and the multipliers' increments as
    /// impulses `γ'h Δλ` over `atol + rtol |λ|` (as the BDF weighs its multipliers), so that they converge
    /// too. As a fraction of the step's share of the tolerance ([`Tolerances::step_share`], with its floor), as the local
    /// error is: the unresolved part of the step then stays small against the error the step is held to.
    fn increment_norm(&mut self, h: f64) -> f64 {
        let (nv, nc) = (self.nv, self.nc);
        let (cb, cg) = (self.coefficients.beta_prime() * h * h, self.coefficients.gamma_prime() * h);
        let (atol, rtol) = (self.tolerances.atol, self.tolerances.rtol);
        for k in 0..nv {
            self.work[k] = cb * self.dx[k] + self.delta_new[k] - self.delta[k];
        }
        let mut sum = position_sum_of_squares(&self.model.layout, &self.q_new, &self.work, atol, rtol);
        for k in 0..nv {
            sum += (cg * self.dx[k] / error_weight(atol, rtol, self.v_new[k])).powi(2);
        }
        // Near a singular position the multipliers' rounding is amplified once more than the positions'
        // and velocities' (κ² against κ), along a direction in which they hardly act on the motion.
        let cl = cg / self.amplification;
        for r in 0..nc {
            sum += (cl * self.dx[nv + r] / error_weight(atol, rtol, self.x[nv + r])).powi(2);
        }
        root_mean_square(sum, self.model.layout.nq + nv + nc) / self.share_floor.share_above(&self.tolerances, h, SHARE_FLOOR)
    }

    /// Weighted RMS norm of the local error estimates of the positions and the velocities (see the
    /// module documentation), over `nq + nv` components, as a fraction of the step's share of the
    /// tolerance ([`Tolerances::step_share`]: error per unit step).
    fn error_norm(&mut self, h: f64) -> f64 {
        let (atol, rtol) = (self.tolerances.atol, self.tolerances.rtol);
        let c = h * h * (self.coefficients.beta - 1.0 / 6.0);
        for k in 0..self.nv {
            self.work[k] = c * (self.a_new[k] - self.a_start[k]);
        }
        let mut sum = position_sum_of_squares(&self.model.layout, &self.q_new, &self.work, atol, rtol);
        let (h_p, h_pp) = (self.h_last, self.h_before_last);
        // The curvature `c` of the accelerations (`v̇ ≈ … + c t²`) from the mean accelerations of the attempt
        // and the two steps before it, their velocity differences over their sizes, where those are known
        // and the step ends are away from singular positions (where the velocities are held to the
        // amplified rounding). Not from the accelerations at the three step ends: the constraint forces
        // oscillate from step to step about their smooth values, decaying by about ρ∞ a step, which the
        // velocities do not feel (their update averages consecutive accelerations) but the second
        // difference of the accelerations does, as an estimate that does not shrink with the step. With
        // it the steps collapsed at ρ∞ = 1 (the peer's 3-D pendulum at rtol 1e-5: t = 0.011 s of 5 s in
        // 5.2 million steps) and took several times the steps near it (0.999: 10,271 against 2,104 at 0.9,
        // rtol 1e-4); with the velocities', 1,998 steps at ρ∞ = 1, and at 0.8 the same steps within 1 %
        // and the same errors on the benchmarks (docs/accuracy.md, *Generalized-α's default spectral
        // radius*). Near a singular position the accelerations' curvature: the velocities' failed the
        // double four-bar at rtol 1e-6 at its ninth position (t = 8.485 s, the step down to 1.8e-14 s).
        let from_velocities = h_p > 0.0 && h_pp > 0.0 && !self.singular.near();
        for k in 0..self.nv {
            let (a0, a1) = (self.vdot[k], self.x[k]);
            // Third-order velocity from the accelerations at t_n, t_{n+1} and their curvature (quadratic, integrated).
            let curvature = if from_velocities {
                let mean = [(self.v_new[k] - self.v[k]) / h, (self.v[k] - self.v_old[k]) / h_p, (self.v_old[k] - self.v_before_last[k]) / h_pp];
                let slopes = [(mean[0] - mean[1]) / (0.5 * (h + h_p)), (mean[1] - mean[2]) / (0.5 * (h_p + h_pp))];
                (slopes[0] - slopes[1]) / (0.5 * (h + 2.0 * h_p + h_pp))
            } else if h_p > 0.0 {
                ((a1 - a0) / h - (a0 - self.vdot_old[k]) / h_p) / (h + h_p)
            } else {
                0.0
            };
            let v3 = self.v[k] + 0.5 * h * (a0 + a1) - h * h * h / 6.0 * curvature;
            sum += ((self.v_new[k] - v3) / error_weight(atol, rtol, self.v_new[k])).powi(2);
        }
        root_mean_square(sum, self.model.layout.nq + self.nv) / self.share_floor.share_above(&self.tolerances, h, SHARE_FLOOR)
    }

    /// Accepts the converged step to `t_new`.
    fn accept(&mut self, t_new: f64, h: f64) {
        let nv = self.nv;
        self.t_old = self.t;
        self.h_before_last = self.h_last;
        // v_before_last ← v_old ← v (v is overwritten below).
        std::mem::swap(&mut self.v_before_last, &mut self.v_old);
        self.h_last = h;
        self.t = t_new;
        std::mem::swap(&mut self.q_old, &mut self.q);
        self.q.copy_from_slice(&self.q_new);
        std::mem::swap(&mut self.v_old, &mut self.v);
        self.v.copy_from_slice(&self.v_new);
        std::mem::swap(&mut self.vdot_old, &mut self.vdot);
        self.vdot.copy_from_slice(&self.x[..nv]);
        self.a_tilde.copy_from_slice(&self.a_new);
        std::mem::swap(&mut self.lambda_old, &mut self.lambda);
        self.lambda.copy_from_slice(&self.x[nv..nv + self.nc]);
        self.d_last.copy_from_slice(&self.d_step);
        self.stats.steps += 1;
        self.stats.sum_h_squared += h * h;
        self.stats.order_counts[2] += 1;
        self.derivatives_current = false;
        run_kinematic_stages(&self.model, &mut self.data, t_new, &self.q, &self.v);
        update_angle_references(&self.model, &mut self.data);
        self.matrix.set_start_jacobian(&self.model, &self.data, &self.active);
    }

    /// Positions and velocities at `t` within the last step (cubic Hermite, positions in velocity space).
    pub fn interpolate(&mut self, t: f64, q: &mut [f64], v: &mut [f64]) {
        if self.h_last == 0.0 {
            q.copy_from_slice(&self.q);
            v.copy_from_slice(&self.v);
            return;
        }
        let h = self.h_last;
        let s = (t - self.t_old) / h;
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2);
        let l = &self.model.layout;
        for b in 0..l.n_bodies() {
            let vo = l.v_offset[b];
            let u = Vec3::new(self.d_last[vo + 3], self.d_last[vo + 4], self.d_last[vo + 5]);
            let w = Vec3::new(self.v[vo + 3], self.v[vo + 4], self.v[vo + 5]);
            let end_rate = right_jacobian_inverse(&u) * w;
            for k in l.v_span(b) {
                let end = if (vo + 3..vo + 6).contains(&k) { end_rate[k - vo - 3] } else { self.v[k] };
                self.work[k] = h10 * h * self.v_old[k] + h01 * self.d_last[k] + h11 * h * end;
            }
        }
        retract(l, &self.q_old, &self.work, q);
        for k in 0..self.nv {
            v[k] = h00 * self.v_old[k] + h10 * h * self.vdot_old[k] + h01 * self.v[k] + h11 * h * self.vdot[k];
        }
    }

    /// The message of a step-size underflow after `failure` (allocates; only called then).
    fn describe_failure(&mut self, failure: AttemptFailure) -> String {
        failure.describe(|t_new, step| self.worst_equation(t_new, step))
    }

    /// The largest residuals of the equations of motion and of the constraints at the predictor of the
    /// failed step, and any constraints that have become dependent there.
    fn worst_equation(&mut self, t_new: f64, h: f64) -> String {
        let (nv, nc) = (self.nv, self.nc);
        self.predict(h);
        self.evaluate_residual(t_new, h);
        let (cb, cg) = (self.coefficients.beta_prime() * h * h, self.coefficients.gamma_prime() * h);
        let (model, res) = (&self.model, &self.res);
        // The constraint rows unscaled: `B v + Φ_t` and `Φ` themselves.
        let unscaled = |i: usize| {
            if i < nv {
                res[i]
            } else if i < nv + nc {
                cg * res[i]
            } else {
                cb * res[i]
            }
        };
        let name = |row: usize| {
            if row < nv {
                EquationRow::Motion(row)
            } else if row < nv + nc {
                EquationRow::VelocityConstraint(row - nv)
            } else {
                EquationRow::PositionConstraint(row - nv - nc)
            }
        };
        let rows = (0..nv, nv..nv + 2 * nc);
        diagnosis::worst_equations(model, &mut self.data, t_new, &self.q_new, &self.active, rows, unscaled, name)
    }
}

/// The step equations of one attempt in the unknowns `[v̇, λ, μ̃]`, for the Newton driver; the first
/// iteration starts from the predictor's residual, already in `res`.
struct StepEquations<'a> {
    integrator: &'a mut GeneralizedAlpha,
    t_new: f64,
    h: f64,
}

impl NewtonSystem for StepEquations<'_> {
    fn residual(&mut self, k: usize) -> &[f64] {
        let g = &mut *self.integrator;
        if k > 0 {
            g.state_from_unknowns(self.h);
            g.evaluate_residual(self.t_new, self.h);
        }
        &g.res
    }

    fn solve(&mut self) -> bool {
        let g = &mut *self.integrator;
        for (d, r) in g.dx.iter_mut().zip(&g.res) {
            *d = -r;
        }
        g.matrix.solve_in_place(&mut g.dx).is_ok()
    }

    /// Also makes the position correction `Bᵀμ` of the new multipliers, with `B` of this iterate (in
    /// `data`), which the norm measures.
    fn increment_norm(&mut self) -> f64 {
        let g = &mut *self.integrator;
        let (nv, nc) = (g.nv, g.nc);
        let cb = g.coefficients.beta_prime() * self.h * self.h;
        for r in 0..nc {
            g.mu[r] = if g.active[r] { cb * (g.x[nv + nc + r] + g.dx[nv + nc + r]) } else { 0.0 };
        }
        g.delta_new.fill(0.0);
        g.matrix.add_start_jacobian_transpose(&g.mu, &mut g.delta_new);
        add_jacobian_transpose(&g.model, &g.data, &g.mu, &mut g.delta_new);
        g.increment_norm(self.h)
    }

    fn apply(&mut self) {
        let g = &mut *self.integrator;
        for (x, d) in g.x.iter_mut().zip(&g.dx) {
            *x += d;
        }
        g.delta.copy_from_slice(&g.delta_new);
    }
}

/// First step: about `0.5 ‖·‖^(−1/3)` of the weighted initial velocities and accelerations (the local
/// error grows as `h³`), at most 10 ms.
fn initial_step(model: &Model, tolerances: &Tolerances, q: &[f64], v: &[f64], vdot: &[f64]) -> f64 {
    let l = &model.layout;
    let norm = |x: &[f64]| root_mean_square(position_sum_of_squares(l, q, x, tolerances.atol, tolerances.rtol), l.nq);
    let d = norm(v).max(norm(vdot));
    if d > 1e-10 {
        (0.5 * d.powf(-1.0 / 3.0)).min(1e-2)
    } else {
        1e-2
    }
}

impl Integrator for GeneralizedAlpha {
    fn checkpoint(&self) -> Result<IntegratorCheckpoint, CheckpointError> {
        Ok(IntegratorCheckpoint::GeneralizedAlpha(GeneralizedAlpha::checkpoint(self)))
    }
    fn restore(&mut self, checkpoint: &IntegratorCheckpoint) -> Result<(), CheckpointError> {
        match checkpoint {
            IntegratorCheckpoint::GeneralizedAlpha(c) => GeneralizedAlpha::restore(self, c),
            other => Err(CheckpointError::Method { expected: "gen-alpha", found: other.method() }),
        }
    }
    fn t(&self) -> f64 {
        self.t
    }
    fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError> {
        GeneralizedAlpha::step(self, t_stop)
    }
    fn state(&self) -> (&[f64], &[f64]) {
        (&self.q, &self.v)
    }
    fn interpolate(&mut self, t: f64, q: &mut [f64], v: &mut [f64]) {
        GeneralizedAlpha::interpolate(self, t, q, v)
    }
    fn stats(&self) -> &Stats {
        &self.stats
    }
    fn data_mut(&mut self) -> &mut Data {
        &mut self.data
    }
    fn active(&self) -> &[bool] {
        &self.active
    }
    fn name(&self) -> &'static str {
        "gen-alpha"
    }
}

#[cfg(test)]
mod tests;
