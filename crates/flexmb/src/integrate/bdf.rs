//! Variable-order, variable-step BDF for the stabilized index-2 equations of motion.
//!
//! Quasi-constant step size in backward-difference form (Shampine and Reichelt, *The MATLAB ODE Suite*,
//! 1997; Byrne and Hindmarsh 1975): the predictor is `y⁽⁰⁾ = Σ_{j≤k} ∇ʲyₙ`, the corrector solves
//! `F(t, y⁽⁰⁾ + d, (ψ + d)/c) = 0` for the correction `d` by a simplified Newton iteration with a
//! reused iteration matrix, `c = h/γ_k`, `ψ = Σ_{1≤j≤k} γ_j ∇ʲyₙ / γ_k`, `γ_k = Σ_{j≤k} 1/j`. The local
//! error estimate is `d/(k+1)`, tested on positions and velocities only (not on the multipliers), in the
//! RMS norm weighted by `atol + rtol |y|`. When it fails the test, the estimate is also filtered through
//! the iteration matrix (Shampine's device, restricted to the free motions: see
//! [`filtered_norm`](Bdf::filtered_norm)); if stiff components inflated it (the filtered one is below half
//! of it), the filtered estimates decide the error test and the order and step size while that lasts. A
//! step that fails the error test or whose Newton iteration does not converge is rejected and retried with
//! a smaller step; nothing unconverged is ever accepted. A Newton failure with a Jacobian evaluated
//! elsewhere than at the current predictor first re-evaluates it there. Step size changes re-interpolate
//! the difference array; the order moves by at most one after `k + 1` steps of equal size, to the order
//! whose error estimate allows the largest next step. With [`BdfConfig::stability_limits`] each order
//! above 2 also has a step bound learned from error-test failures that betray an instability (the
//! estimate grew fast at an unchanged step), and an order held back by its bound drops straight to 2
//! when order 2 allows a longer step.

use crate::analysis::{Accelerations, State};
use crate::data::Data;
use crate::integrate::convergence_rate::RateMonitor;
use crate::integrate::diagnosis::{self, EquationRow};
use crate::integrate::error_norm::{error_weight, weighted_rms_norm};
use crate::integrate::floor_step_cap::FloorStepCap;
use crate::integrate::iteration_matrix::IterationMatrix;
use crate::integrate::newton::{self, ConvergenceTest, NewtonSystem};
use crate::integrate::newton_rounding::{RoundingFloor, CHANGE_RATIO, NOISE_CEILING};
use crate::integrate::noise_floor::NoiseFloor;
use crate::integrate::passed_rounding;
use crate::integrate::rounding_level::rounding_residual;
use crate::integrate::share_floor::{ShareFloor, BDF_NEWTON_FLOOR, FINE_STEP_FLOOR};
use crate::integrate::singular_position::SingularPassage;
use crate::integrate::{
    check_len, AttemptFailure, BdfCheckpoint, BdfConfig, CheckpointError, IntegrationError, Integrator, IntegratorCheckpoint, Stats,
    Tolerances,
};
use std::sync::Arc;

use crate::model::Model;
use crate::stage::{normalize_euler_parameters, position_rates, residual, update_angle_references, YLayout};

const MAX_ORDER: usize = 5;
/// Most attempts at one step. Each failure shortens the step: a Newton failure halves it, an error-test
/// failure multiplies it by at most 0.9 (the safety factor times the estimate's root, below 1), so from any
/// step to the smallest the time resolves (1e-14 of it) takes at most about 310 failures, each with at most
/// three attempts (one with a fresh Jacobian, one at the Newton increments' rounding floor). More means that
/// something lengthens the attempts again after each failure, as the singular-position guard's crossing
/// once did without end (`singular_position::FAILED_CROSSINGS`): the run then stops with the reason rather
/// than looping where no interruption is checked.
const MAX_ATTEMPTS: usize = 2000;
/// Most Newton iterations of one attempt (Radau5's 7; DASSL and IDA allow 4). A reused Jacobian contracts
/// ever more slowly as the bodies turn away from where it was evaluated, and an iteration costs one residual
/// where a new Jacobian costs one per colour of its columns (20 to 45 on the peer cases) and a
/// factorization, so a slow iteration is let run rather than failed: with 4 the rate test gave up at
/// rates of about 0.15 (heavy top at rtol 3e-8: 1410 Newton failures in 3927 steps).
const NEWTON_MAXITER: usize = 7;
/// The iterations in the step-size safety factor `0.9 (2m + 1)/(2m + iterations)` of the last Newton
/// iteration (that of `ode15s`), with the `m = 4` it had before the iterations were raised to
/// [`NEWTON_MAXITER`]: slow iterations shorten the next step as they did.
const SAFETY_ITERATIONS: usize = 4;
const MIN_FACTOR: f64 = 0.2;
const MAX_FACTOR: f64 = 10.0;
/// Near a singular position, the factor by which the step may grow at an order selection whose estimate
/// passed as the amplified rounding, up to the last step taken away from the position
/// ([`Bdf::smooth_step`]). Such an estimate says nothing of the truncation error; taken as the stand-in
/// 0.3 it kept the step where it was (a factor of about 0.99 after the safety factor), so that a step cut
/// short on the approach was never long again. The double four-bar over its run at rtol 1.03e-10: at
/// κ ≈ 36 to 45, 22 ms before its first position, where the guard does not yet act, estimates of the
/// rounding failed the error test until the step had fallen from 7.1e-4 s to 7.3e-5 s; from there to the
/// position every estimate passed as rounding, the steps stayed near 1e-4 s, the crossing of the
/// position came from within three such steps (κ 4,200 at its start) and failed, and the ends crept onto
/// the position until the run stopped, step too small (3 or 4 of 21 runs at rtol × 0.90 … 1.10 at 1e-9 and
/// 1e-10). Growing back by 1.2 per selection (every six steps at order 5) brings the step to the smooth
/// motion's again before the position, where the crossing passes (none of 21 stopped).
const REGROWTH_NEAR_POSITION: f64 = 1.2;
/// Error-test failures of one step after which it is retried at order 1.
const ORDER_ONE_AFTER: usize = 3;
/// Range of `c/c_f` in which the factors made for `c_f` are reused.
const REUSE_MIN: f64 = 0.6;
const REUSE_MAX: f64 = 1.0 / 0.6;
/// The filtered error estimate counts as evidence of stiff components when it is below this fraction of
/// the classical one; it is then used for [`FILTER_HOLD`] accepted steps (renewed while the evidence lasts).
const FILTER_RATIO: f64 = 0.5;
const FILTER_HOLD: usize = 20;
/// Stability limits of orders 3–5 ([`BdfConfig::stability_limits`]): an error-test failure at the step size of
/// the step before whose estimate grew by more than `STABILITY_GROWTH` marks that step size as unstable for
/// the order; the order's steps are then kept below `STABILITY_MARGIN` times it, a bound that relaxes by
/// `STABILITY_RELAX` per accepted step (doubling in about 700 steps) so that the order is retried.
const STABILITY_GROWTH: f64 = 1.5;
const STABILITY_MARGIN: f64 = 0.7;
const STABILITY_RELAX: f64 = 1.001;

/// `γ_k = Σ_{j=1..k} 1/j` for `k = 0..=MAX_ORDER`.
const GAMMA: [f64; MAX_ORDER + 1] =
    [0.0, 1.0, 1.5, 1.5 + 1.0 / 3.0, 1.5 + 1.0 / 3.0 + 0.25, 1.5 + 1.0 / 3.0 + 0.25 + 0.2];

/// Error constant of BDF order `k`: `1/(k + 1)`.
fn error_const(k: usize) -> f64 {
    1.0 / (k + 1) as f64
}

/// The BDF integrator with all its workspaces; one [`step`](Self::step) is one accepted step.
pub struct Bdf {
    model: Arc<Model>,
    data: Data,
    /// Scratch for [`Integrator::interpolate`].
    y_interp: Vec<f64>,
    yl: YLayout,
    active: Vec<bool>,
    tolerances: Tolerances,
    config: BdfConfig,
    n: usize,
    n_diff: usize,
    t: f64,
    t_old: f64,
    h: f64,
    order: usize,
    n_equal_steps: usize,
    /// Backward differences `∇ʲy`, rows `j = 0..MAX_ORDER+2`, each of length `n`.
    d: Vec<f64>,
    jac: IterationMatrix,
    /// When the iteration matrix was evaluated and factored, and when it is evaluated again.
    reuse: MatrixReuse,
    /// Accepted steps left during which the error estimates are filtered.
    filter_steps: usize,
    filtered: Vec<f64>,
    stability: StabilityLimits,
    /// The attempt's share of the tolerance ([`step_share`](Self::step_share)); the Newton increments are
    /// measured against it, as the local error is.
    share: f64,
    /// The floor under a step's share of the tolerance.
    share_floor: ShareFloor,
    /// The last step accepted away from singular positions (the guard not [`near`](SingularPassage::near)
    /// one), which the error control chose on truncation estimates: near a position a step may grow back
    /// to it where the estimates pass as rounding ([`REGROWTH_NEAR_POSITION`]); 0 before the first.
    smooth_step: f64,
    /// The bound on the steps the floor under the share holds (`integrate/floor_step_cap.rs`).
    floor_cap: FloorStepCap,
    /// The fixed floor under it, made of the estimate's noise measured by the polishing iteration.
    noise_floor: NoiseFloor,
    /// The level below which the Newton increments are the residual's rounding.
    rounding: RoundingFloor,
    /// The approach to a singular position: its predicted window, which the step ends avoid.
    singular: SingularPassage,
    /// The factor by which the conditioning at the attempt's end amplifies the rounding (1 away from a
    /// singular position).
    amplification: f64,
    /// The rounding level of the Newton increments estimated with the current factors, in tolerances (the
    /// error weights, not a step's share); `None` until an iteration with them needs it
    /// ([`rounding_level`](super::rounding_level)).
    rounding_level: Option<f64>,
    y_pred: Vec<f64>,
    psi: Vec<f64>,
    y_new: Vec<f64>,
    corr: Vec<f64>,
    rhs: Vec<f64>,
    res: Vec<f64>,
    yp: Vec<f64>,
    scale: Vec<f64>,
    change_tmp: Vec<f64>,
    /// The counters so far.
    pub stats: Stats,
}

/// The reuse of the iteration matrix across steps (DASSL's policy): the factors of a nearby `c = h/α`
/// serve, the finite-difference part is re-evaluated when a Newton iteration fails with one evaluated
/// elsewhere, and ahead of the iteration when the convergence rate monitored across steps
/// ([`RateMonitor`]) predicts that it would fail.
#[derive(Clone, Copy, Debug, Default)]
struct MatrixReuse {
    /// The `c` of the current factors; `None` when they must be made again.
    factored_c: Option<f64>,
    /// The Jacobian was evaluated at the predictor of the current attempt.
    at_attempt: bool,
    /// The convergence rate of the iterations with the current Jacobian, which predicts the next one's.
    rate: RateMonitor,
}

impl Bdf {
    /// Starts from a consistent state (assembled, velocity-analysed) and its accelerations, with the
    /// error tolerances and step limits of `tolerances` and the order limit of `config`.
    pub fn new(
        model: Arc<Model>,
        state: &State,
        accelerations: &Accelerations,
        tolerances: Tolerances,
        config: BdfConfig,
    ) -> Result<Self, IntegrationError> {
        super::check_start(&model, state, accelerations)?;
        let yl = YLayout::new(&model);
        let n = yl.len();
        let n_diff = yl.n_differential();
        let mut y0 = vec![0.0; n];
        let mut yp0 = vec![0.0; n];
        y0[yl.q.clone()].copy_from_slice(&state.q);
        y0[yl.v.clone()].copy_from_slice(&state.v);
        y0[yl.lambda.clone()].copy_from_slice(&accelerations.lambda);
        yp0[yl.v.clone()].copy_from_slice(&accelerations.vdot);
        position_rates(&model, &state.q, &state.v, &mut yp0[yl.q.clone()]);
        if !y0.iter().chain(&yp0).all(|x| x.is_finite()) {
            return Err(IntegrationError::InitialConditions {
                t: state.t,
                reason: "initial positions, velocities or accelerations are not finite".into(),
            });
        }
        let tolerances = tolerances.attainable().0;
        let max_order = config.max_order.clamp(1, MAX_ORDER);
        let config = BdfConfig { max_order, ..config };
        let h0 = tolerances
            .h_init
            .unwrap_or_else(|| initial_step(&tolerances, &y0[..n_diff], &yp0[..n_diff]))
            .min(tolerances.h_max);
        let mut d = vec![0.0; (MAX_ORDER + 3) * n];
        d[..n].copy_from_slice(&y0);
        for k in 0..n {
            d[n + k] = h0 * yp0[k];
        }
        let mut data = Data::new(&model);
        let references = state_angle_references(&model, &mut data, state);
        data.angle_reference.copy_from_slice(&references);
        let jac = IterationMatrix::new(&model, &yl);
        let singular = SingularPassage::new(&model, &state.active, tolerances.rtol).crossing_where_conditioned_badly();
        let mut bdf = Self {
            model,
            yl,
            active: state.active.clone(),
            tolerances,
            config,
            n,
            n_diff,
            t: state.t,
            t_old: state.t,
            h: h0,
            order: 1,
            n_equal_steps: 0,
            d,
            jac,
            reuse: MatrixReuse::default(),
            filter_steps: 0,
            filtered: vec![0.0; n],
            stability: StabilityLimits::new(),
            share: 1.0,
            share_floor: ShareFloor::default(),
            smooth_step: 0.0,
            floor_cap: FloorStepCap::default(),
            noise_floor: NoiseFloor::default(),
            rounding: RoundingFloor::default(),
            singular,
            amplification: 1.0,
            rounding_level: None,
            y_pred: vec![0.0; n],
            psi: vec![0.0; n],
            y_new: vec![0.0; n],
            corr: vec![0.0; n],
            rhs: vec![0.0; n],
            res: vec![0.0; n],
            yp: yp0,
            scale: vec![0.0; n],
            change_tmp: vec![0.0; (MAX_ORDER + 1) * n],
            stats: Stats::default(),
            data,
            y_interp: vec![0.0; n],
        };
        let yp0 = bdf.yp.clone();
        bdf.evaluate_jacobian_at(state.t, &y0, &yp0);
        Ok(bdf)
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }
    /// Time at the start of the last accepted step.
    pub fn t_old(&self) -> f64 {
        self.t_old
    }
    /// Current `y = [q, v, λ, μ]`.
    pub fn y(&self) -> &[f64] {
        &self.d[..self.n]
    }
    /// Current order.
    pub fn order(&self) -> usize {
        self.order
    }
    /// Step size planned for the next step.
    pub fn step_size(&self) -> f64 {
        self.h
    }
    /// The constraint rows in force.
    pub fn active(&self) -> &[bool] {
        &self.active
    }
    /// Scratch data (for evaluating outputs between steps).
    pub fn data_mut(&mut self) -> &mut Data {
        &mut self.data
    }
    /// The complete state between two steps.
    pub fn checkpoint(&self) -> BdfCheckpoint {
        let (f_y, f_yp) = self.jac.stored_parts();
        BdfCheckpoint {
            t: self.t,
            t_old: self.t_old,
            h: self.h,
            order: self.order,
            n_equal_steps: self.n_equal_steps,
            differences: self.d.clone(),
            jacobian: f_y.to_vec(),
            jacobian_derivative: f_yp.to_vec(),
            factored_c: self.reuse.factored_c,
            kept_pivots: self.jac.kept_pivots().map(<[usize]>::to_vec),
            jacobian_at_attempt: self.reuse.at_attempt,
            newton_rate: self.reuse.rate,
            filter_steps: self.filter_steps,
            step_limits: self.stability.h_limit.to_vec(),
            last_h: self.stability.last_h,
            last_error: self.stability.last_error,
            share_floor: self.share_floor.stored(),
            newton_rounding: self.rounding.stored(),
            newton_rounding_level: self.rounding_level,
            smooth_step: self.smooth_step,
            floor_step_cap: self.floor_cap.stored(),
            noise_level: self.noise_floor.level,
            active: self.active.clone(),
            angle_reference: self.data.angle_reference.clone(),
            stats: self.stats,
        }
    }

    /// Continues from `c`, taken of a BDF on the same model with the same settings; the factors in use
    /// are made again from the stored Jacobian.
    pub fn restore(&mut self, c: &BdfCheckpoint) -> Result<(), CheckpointError> {
        let (f_y, f_yp) = self.jac.stored_parts();
        check_len("the backward differences", self.d.len(), c.differences.len())?;
        check_len("the Jacobian", f_y.len(), c.jacobian.len())?;
        check_len("the Jacobian's derivative part", f_yp.len(), c.jacobian_derivative.len())?;
        check_len("the stability limits", self.stability.h_limit.len(), c.step_limits.len())?;
        check_len("the constraint rows in force", self.active.len(), c.active.len())?;
        check_len("the joint angles", self.data.angle_reference.len(), c.angle_reference.len())?;
        if !(1..=self.config.max_order).contains(&c.order) {
            return Err(CheckpointError::Unsupported(format!(
                "the checkpoint's BDF order {} exceeds max_order {}",
                c.order, self.config.max_order
            )));
        }
        self.t = c.t;
        self.t_old = c.t_old;
        self.h = c.h;
        self.order = c.order;
        self.n_equal_steps = c.n_equal_steps;
        self.d.copy_from_slice(&c.differences);
        self.jac.set_stored_parts(&c.jacobian, &c.jacobian_derivative);
        self.jac.keep_pivots(c.kept_pivots.as_deref())?;
        self.reuse.factored_c = c.factored_c.filter(|&cf| self.jac.factor(cf).is_ok());
        self.rounding_level = c.newton_rounding_level.filter(|_| self.reuse.factored_c.is_some());
        self.smooth_step = c.smooth_step;
        self.floor_cap = FloorStepCap::restored(c.floor_step_cap);
        self.reuse.at_attempt = c.jacobian_at_attempt;
        self.reuse.rate = c.newton_rate;
        self.filter_steps = c.filter_steps;
        self.stability.h_limit.copy_from_slice(&c.step_limits);
        self.stability.last_h = c.last_h;
        self.stability.last_error = c.last_error;
        self.share_floor = ShareFloor::restored(c.share_floor);
        self.rounding = RoundingFloor::restored(c.newton_rounding);
        self.noise_floor = NoiseFloor { level: c.noise_level };
        self.active.copy_from_slice(&c.active);
        self.data.angle_reference.copy_from_slice(&c.angle_reference);
        self.stats = c.stats;
        Ok(())
    }

    /// Residual evaluations one Jacobian costs.
    pub fn evaluations_per_jacobian(&self) -> usize {
        self.jac.evaluations_per_jacobian()
    }

    /// `y(t)` for `t` in `[t_old, t]` from the interpolating polynomial of the last step.
    pub fn interpolate(&self, t_eval: f64, out: &mut [f64]) {
        let n = self.n;
        out.copy_from_slice(&self.d[..n]);
        let mut p = 1.0;
        for j in 0..self.order {
            let x = (t_eval - (self.t - j as f64 * self.h)) / (self.h * (j + 1) as f64);
            p *= x;
            let row = &self.d[(j + 1) * n..(j + 2) * n];
            for k in 0..n {
                out[k] += row[k] * p;
            }
        }
    }

    fn evaluate_jacobian_at(&mut self, t: f64, y: &[f64], yp: &[f64]) {
        let evals = self.jac.evaluate(&self.model, &mut self.data, &self.yl, &self.active, t, y, yp);
        self.stats.jacobian_evaluations += 1;
        self.stats.residual_evaluations += evals;
        self.reuse.factored_c = None;
        self.reuse.rate.evaluated(t);
    }

    /// Rescales the differences for a step size change by `factor` at the current order.
    fn change_differences(&mut self, order: usize, factor: f64) {
        let r = compute_r(order, factor);
        let u = compute_r(order, 1.0);
        let mut ru = [[0.0; MAX_ORDER + 1]; MAX_ORDER + 1];
        for i in 0..=order {
            for j in 0..=order {
                ru[i][j] = (0..=order).map(|k| r[i][k] * u[k][j]).sum();
            }
        }
        let n = self.n;
        // new D[j] = Σ_i RU[i][j] · D[i]
        self.change_tmp[..(order + 1) * n].fill(0.0);
        for j in 0..=order {
            for i in 0..=order {
                let w = ru[i][j];
                if w == 0.0 {
                    continue;
                }
                for k in 0..n {
                    self.change_tmp[j * n + k] += w * self.d[i * n + k];
                }
            }
        }
        self.d[..(order + 1) * n].copy_from_slice(&self.change_tmp[..(order + 1) * n]);
    }

    /// Takes one accepted step, not passing `t_stop`.
    pub fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError> {
        if self.stats.steps >= self.tolerances.max_steps {
            return Err(IntegrationError::TooManySteps { t: self.t, max_steps: self.tolerances.max_steps });
        }
        let t = self.t;
        let min_step = super::smallest_step(t, t_stop);
        if self.h > self.tolerances.h_max {
            self.change_differences(self.order, self.tolerances.h_max / self.h);
            self.h = self.tolerances.h_max;
            self.reuse.factored_c = None;
        } else if self.h < min_step {
            self.change_differences(self.order, min_step / self.h);
            self.h = min_step;
            self.reuse.factored_c = None;
        }
        // Why the last attempt failed; described (which allocates) only if the step size underflows.
        let mut failure = AttemptFailure::None;
        let mut error_test_failures = 0;
        let mut attempts = 0;
        let (t_new, safety) = loop {
            let mut h = self.h;
            if h < min_step {
                let reason = self.describe_failure(failure);
                return Err(IntegrationError::StepSizeTooSmall { t, h, reason });
            }
            attempts += 1;
            if attempts > MAX_ATTEMPTS {
                let reason = self.describe_failure(failure);
                return Err(IntegrationError::AttemptsWithoutProgress { t, h, attempts: MAX_ATTEMPTS, reason });
            }
            let mut t_new = t + h;
            // Not at a step end where a singular position leaves the constraints ill-conditioned.
            // The guard measures the rounding against the share of the other methods' floor (1e-12 of the
            // solution): against the BDF's lower one it acted on the 3-D slider-crank's ordinary dip of
            // the conditioning to κ = 25 and passed estimates within 50 times its rounding (E 2.0e-7 at
            // rtol 1e-9 and 1e-10, against 4.1e-8 with the 1e-12 floor).
            match self.singular.placed_end(t, t_new, self.share_floor.share(&self.tolerances, h)) {
                Some(end) if end < t_stop => {
                    self.change_differences(self.order, (end - t) / h);
                    h = end - t;
                    self.h = h;
                    self.reuse.factored_c = None;
                    t_new = end;
                }
                _ => self.singular.asked = None,
            }
            self.amplification = self.singular.amplification(t, t_new, self.share_floor.share(&self.tolerances, t_new - t));
            if t_new >= t_stop - 4.0 * f64::EPSILON * t_stop.abs() {
                t_new = t_stop;
                self.change_differences(self.order, (t_new - t) / h);
                h = t_new - t;
                self.h = h;
                self.reuse.factored_c = None;
            }
            let order = self.order;
            self.predict();
            self.share = self.step_share();
            let c = h / GAMMA[order];
            if !self.reuse.at_attempt && self.reuse.rate.expects_failure(t_new, self.newton_tolerance(), NEWTON_MAXITER) {
                // The rate of the last iterations, grown with the time since the Jacobian, says this
                // iteration would fail: the Jacobian is re-evaluated here rather than after the failure.
                self.refresh_jacobian(t_new, c);
            }
            // Reuse the factors of a nearby c (DASSL): the increments are then scaled by 2/(1 + c_f/c).
            let reusable = self.reuse.factored_c.is_some_and(|cf| (REUSE_MIN..=REUSE_MAX).contains(&(c / cf)));
            if !reusable {
                self.rounding_level = None;
                if self.jac.factor(c).is_err() {
                    self.stats.factorizations += 1;
                    if !self.reuse.at_attempt {
                        self.refresh_jacobian(t_new, c);
                        continue;
                    }
                    failure = AttemptFailure::Singular { t_new, step: c };
                    self.reduce_step(0.5);
                    continue;
                }
                self.stats.factorizations += 1;
                self.reuse.factored_c = Some(c);
            }
            let c_factored = self.reuse.factored_c.unwrap_or(c);
            let (converged, iterations, test) = self.newton(t_new, c, c_factored);
            if !converged {
                self.stats.newton_failures += 1;
                // A Jacobian evaluated elsewhere (an earlier step, or this step's predictor for another
                // step size) is re-evaluated here before the step is reduced: F_y of a stiff spring or of
                // the constraints turns with the bodies, and a chord iteration with a turned one diverges.
                if !self.reuse.at_attempt {
                    // A measurement as a converged reuse is: where a stiff element turns with the bodies
                    // (the flyball governor's springs spin with the shaft), a matrix one step old fails
                    // at every step, and the monitor must learn it to re-evaluate ahead of the step.
                    self.reuse.rate.failed(t_new, test.failed_rate(), test.first_increment);
                    self.reuse.rate.reuse_failed(t_new, h);
                    self.refresh_jacobian(t_new, c);
                    continue;
                }
                // Increments that shrank neither with the iterations nor with the step are the residual's
                // rounding: the attempt is repeated with them as its floor.
                let (stalled, change) = (test.smallest_after_first * self.share, self.predicted_change());
                if self.rounding.failed_with_fresh_matrix(stalled, change, self.tolerances.rtol) {
                    continue;
                }
                failure = AttemptFailure::Newton { t_new, step: c };
                self.reduce_step(0.5);
                continue;
            }
            self.reuse.rate.converged(t_new, test.slowest, test.first_increment);
            let polished = if self.polishes() { self.polish(t_new, c, c_factored) } else { None };
            let safety = 0.9 * (2 * SAFETY_ITERATIONS + 1) as f64 / (2 * SAFETY_ITERATIONS + iterations) as f64;
            let mut error_norm = self.local_error();
            // What passes beyond the share if a test below lets the estimate pass as rounding.
            let beyond_share = passed_rounding::beyond_share(error_norm, self.share, self.tolerances.rtol);
            if error_norm > 1.0 && self.share_floor.is_noise(h, error_norm * self.share, self.tolerances.rtol) {
                // Noise, not error: the floor is now twice it.
                self.share = self.step_share();
                error_norm = self.local_error();
            }
            if error_norm > 1.0 && self.rounding.covers(error_norm * self.share) {
                // Within the Newton increments' rounding floor: no shorter step resolves it.
                error_norm = 1.0;
            }
            // Within the rounding of the constrained solution near a singular position: passes.
            error_norm = SingularPassage::estimate_beyond_rounding(error_norm, self.share, self.tolerances.rtol, self.amplification, order);
            if error_norm > 1.0 {
                if self.config.stability_limits {
                    self.stability.error_test_failed(order, h, error_norm);
                }
                self.stats.error_test_failures += 1;
                error_test_failures += 1;
                let power = error_power(&self.tolerances, h, order + 1, self.config.max_order == 1, self.noise_floor.floor());
                let factor = MIN_FACTOR.max(safety * error_norm.powf(-1.0 / power));
                failure = AttemptFailure::ErrorTest { error_norm, t_new, step: c };
                self.reduce_step(factor);
                // From the third failure of one step on, order 1 (as DASSL and IDA): the polynomial of
                // the history does not describe a fast transient, and its extrapolation then errs by
                // O(h) however short the step, which error per unit step never accepts; order 1
                // extrapolates the last derivative only, whose error falls as h².
                //
                // Not near a singular position: there the estimate that does not fall with the step is the
                // rounding of the ill-conditioned state the last step ended in, which order 1 extrapolates
                // as well, and its own truncation error is then far larger (the double four-bar at rtol 1e-6
                // over its 10 s, just past the fifth position, κ = 5,815: order 5 failed with 1.6, 1.5 and
                // 1.4 shares of the tolerance at steps of 4.4, 3.2 and 2.4 ms, order 1 then with 3e5 shares,
                // and was trapped there for 10,800 steps whose truncation errors passed as rounding).
                // Nor where the estimate is within the rounding that the conditioning measured at the last
                // step end amplifies, even where that rounding does not yet matter to the share: the step is
                // shortened at its order until it does, and the estimate then passes as rounding.
                let rounding = self.singular.within_measured_rounding(error_norm * self.share, order);
                if error_test_failures >= ORDER_ONE_AFTER && self.order > 1 && !rounding && !self.singular.near() {
                    self.order = 1;
                    self.n_equal_steps = 0;
                }
                continue;
            }
            self.stability.accepted(h, error_norm);
            self.stats.rounding_passed += beyond_share;
            self.share_floor.accepted(h, self.share);
            self.rounding.accepted(test.at_floor);
            if self.amplification > 1.0 {
                self.stats.held_near_singular_position(self.tolerances.rtol * self.share);
            }
            // The steps the fixed floor held, and its mean over them: their number times it is what their
            // local errors add up to (`floor_warning`).
            let floor = self.noise_floor.floor();
            if self.tolerances.floor_holds(h, floor) {
                self.stats.share_floor_steps += 1;
                self.stats.share_floor += (floor - self.stats.share_floor) / self.stats.share_floor_steps as f64;
            }
            self.noise_floor.accepted(polished.map(|leftover| leftover * noise_gain(order)));
            if test.at_floor {
                self.stats.rounding_floor_steps += 1;
                self.stats.rounding_floor = self.stats.rounding_floor.max(self.rounding.floor * self.tolerances.rtol);
            }
            break (t_new, safety);
        };
        if !self.singular.near() {
            self.smooth_step = t_new - t;
        }
        self.accept(t_new);
        if let Some(asked) = self.singular.asked {
            // The step was moved off a singular position: the next one is the size the error control asked for.
            self.change_differences(self.order, asked / (t_new - t));
            self.h = asked;
            self.n_equal_steps = 0;
            self.reuse.factored_c = None;
        }
        if let Some(condition) = self.singular.accepted(&self.model, &self.data, t_new) {
            self.stats.singular_position_steps += 1;
            self.stats.singular_position_condition = self.stats.singular_position_condition.max(condition);
        }
        self.stats.singular_positions = self.singular.passages;
        if self.config.stability_limits {
            self.stability.relax();
        }
        let filtering = self.filter_steps > 0;
        self.filter_steps = self.filter_steps.saturating_sub(1);

        // Order and step-size selection after k + 1 steps of equal size.
        if self.n_equal_steps > self.order {
            self.select_order_and_step(safety, filtering);
        }
        Ok(())
    }

    /// After `k + 1` steps of equal size: the order among `k − 1, k, k + 1` whose error estimate allows
    /// the largest next step (each bounded by its stability limit), and that step, the differences
    /// rescaled to it. `safety` is the factor the last Newton iteration allows, `filtering` whether the
    /// estimates are filtered like the error test's.
    fn select_order_and_step(&mut self, safety: f64, filtering: bool) {
        let n = self.n;
        let order = self.order;
        // The estimates at orders k − 1, k, k + 1 from ∇ᵏy, ∇ᵏ⁺¹y, ∇ᵏ⁺²y, filtered like the error test's.
        // Each as a fraction of the step's share of the tolerance (error per unit step).
        let estimate = |bdf: &mut Self, row: usize, k: usize| {
            let share = bdf.share_at_order(k);
            let x = if row == order + 1 { &bdf.corr[..] } else { &bdf.d[row * n..(row + 1) * n] };
            let norm = if filtering {
                bdf.rhs.copy_from_slice(x);
                bdf.filtered_norm(error_const(k))
            } else {
                bdf.rms_norm(x, error_const(k))
            };
            // Near a singular position an estimate within the amplified rounding passed the error test; the
            // step is chosen against that rounding itself (the stand-in where it is below 0.3 of it), and
            // the second value tells that it passed so.
            match SingularPassage::estimate_for_selection(norm, share, bdf.tolerances.rtol, bdf.amplification, k) {
                Some(error) => (error, true),
                None => (norm / share, false),
            }
        };
        let (error_m, lower_within_rounding) = if order > 1 { estimate(self, order, order - 1) } else { (f64::INFINITY, false) };
        let error_p = if order < self.config.max_order { estimate(self, order + 2, order + 1).0 } else { f64::INFINITY };
        let (error, within_rounding) = estimate(self, order + 1, order);
        // An estimate of order h^power allows the step factor e^(−1/p), p the power of h in e / share.
        let (tolerances, h, first_order_method, floor) = (self.tolerances, self.h, self.config.max_order == 1, self.noise_floor.floor());
        let factor_of = |e: f64, power: usize| {
            if e.is_finite() {
                e.max(1e-300).powf(-1.0 / error_power(&tolerances, h, power, first_order_method, floor))
            } else {
                0.0
            }
        };
        // An estimate of the current order within the rounding does not lower the order: the estimates of
        // orders k − 1 and k are then both the same stand-in, which the lower order's smaller power turns
        // into the larger step, and the order fell to 1 and stayed there (Andrews' squeezer at rtol 1e-10,
        // κ ≈ 191 at every step: orders 1 and 2 only, 911,796 steps to t = 0.0105 s of 0.03 s).
        //
        // Nor does an estimate of the lower order that passed as rounding while the current order's did
        // not: its stand-in is not its truncation error, which may be far above the current order's. The
        // double four-bar over its run at rtol 1e-8, 9 ms before its first position (κ ≈ 86): order 5's
        // estimate 0.26 of the step's share, order 4's 16 to 23 shares passed as 0.3; order 4 was chosen
        // with a longer step, and its truncation errors passed as rounding for six steps, each changing
        // the energy by 1.4e-9 J (an ordinary step there: 2e-11 J).
        let lower = if within_rounding || lower_within_rounding { 0.0 } else { factor_of(error_m, order) };
        let mut factors = [lower, factor_of(error, order + 1), factor_of(error_p, order + 2)];
        // Each order's step is also bounded by its stability limit (infinite for orders 1 and 2).
        for (i, f) in factors.iter_mut().enumerate() {
            let k = (order + i - 1).min(MAX_ORDER);
            *f = f.min(self.stability.h_limit[k] / (safety * self.h));
        }
        let (mut best, mut best_factor) =
            factors.iter().enumerate().fold((1, factors[1]), |acc, (i, f)| if *f > acc.1 { (i, *f) } else { acc });
        // Estimates at orders k and k + 1 that both passed as rounding near a singular position, each below
        // 0.3 of the rounding itself (the stand-in, `SingularPassage::estimate_for_selection`), say nothing
        // of which order is the more accurate, only that both truncation errors are below the rounding, and
        // the higher order's falls the faster with the step. Compared as they are, the lower order's equal
        // estimate allows the larger factor (0.3^(−1/k)): the double four-bar over its run at rtol 1e-6,
        // dropped to order 1 next to its fifth position, stayed there for 10,820 steps of 1e-7 to 1e-5 s,
        // each step that grew beyond the rounding failing its real order-1 estimate. The order is raised.
        if SingularPassage::is_noise(error) && SingularPassage::is_noise(error_p) && factors[2] > 0.0 {
            (best, best_factor) = (2, factors[1].max(factors[2]));
        }
        self.order = order + best - 1;
        // Held back by stability at order ≥ 3: order 2 (A-stable) may allow a larger step. The order drops
        // directly, not one at a time: the orders in between are not A-stable either (for 2 % damping their
        // unstable bands start at h ω = 0.47 to 0.81).
        if self.order >= 3 && self.stability.h_limit[self.order] <= safety * self.h * best_factor * (1.0 + 1e-12) {
            let factor_2 = factor_of(estimate(self, 3, 2).0, 3);
            if factor_2 > best_factor {
                self.order = 2;
                best_factor = factor_2;
            }
        }
        let mut factor = MAX_FACTOR.min(safety * best_factor);
        if within_rounding && self.singular.near() {
            // The estimate is the rounding, not the truncation: back towards the smooth motion's step,
            // within the order's stability limit.
            let regrowth = REGROWTH_NEAR_POSITION.min(self.smooth_step / self.h).min(self.stability.h_limit[self.order] / self.h);
            factor = factor.max(regrowth);
        }
        // Where the floor under the share holds the step, no longer than the recent mean of the steps the
        // estimates chose there (`integrate/floor_step_cap.rs`), away from the rounding that the
        // conditioning amplifies.
        let h_chosen = self.h * factor;
        let held = self.tolerances.floor_holds(h_chosen, self.noise_floor.floor()) && self.amplification == 1.0;
        factor = self.floor_cap.step(h_chosen, self.order, held) / self.h;
        self.h *= factor;
        let new_order = self.order;
        self.change_differences(new_order, factor);
        self.n_equal_steps = 0;
        self.reuse.factored_c = None;
    }

    /// The predictor of the current order from the differences, `y⁽⁰⁾ = Σ_{j≤k} ∇ʲyₙ` (`y_pred`), the
    /// history term `ψ = Σ_{1≤j≤k} γ_j ∇ʲyₙ / γ_k` (`psi`), and the error weights at the predictor of every
    /// component: the error test uses those of q and v, the Newton convergence test all of them (as IDA
    /// does), so that the multipliers converge too.
    fn predict(&mut self) {
        let (n, order) = (self.n, self.order);
        let alpha = GAMMA[order];
        for k in 0..n {
            let mut yp = 0.0;
            let mut psi = 0.0;
            for j in 0..=order {
                let dj = self.d[j * n + k];
                yp += dj;
                if j > 0 {
                    psi += dj * GAMMA[j];
                }
            }
            self.y_pred[k] = yp;
            self.psi[k] = psi / alpha;
        }
        let Tolerances { atol, rtol, .. } = self.tolerances;
        for k in 0..n {
            self.scale[k] = error_weight(atol, rtol, self.y_pred[k]);
        }
    }

    /// The weighted norm (in tolerances) of the step's change of the solution that the predictor makes,
    /// `y⁽⁰⁾ − yₙ`, over the differential components.
    fn predicted_change(&self) -> f64 {
        weighted_rms_norm((0..self.n_diff).map(|k| (self.y_pred[k] - self.d[k], self.scale[k])))
    }

    /// The weighted norm of the local error estimate `d/(k + 1)` of the converged corrector, with the
    /// error weights of the positions and velocities moved to the new values; filtered through the
    /// iteration matrix while stiff components inflate it (see [`filtered_norm`](Self::filtered_norm)).
    /// Returned as a fraction of the step's share of the tolerance ([`Tolerances::step_share`]: error per
    /// unit step), so that the step passes at 1 or less.
    fn local_error(&mut self) -> f64 {
        let Tolerances { atol, rtol, .. } = self.tolerances;
        for k in 0..self.n_diff {
            self.scale[k] = error_weight(atol, rtol, self.y_new[k]);
        }
        let order = self.order;
        let share = self.step_share();
        let mut error_norm = self.rms_norm(&self.corr, error_const(order));
        if self.filter_steps > 0 || error_norm > share {
            self.rhs.copy_from_slice(&self.corr);
            let filtered = self.filtered_norm(error_const(order));
            if filtered < FILTER_RATIO * error_norm {
                self.filter_steps = FILTER_HOLD;
            }
            if self.filter_steps > 0 {
                error_norm = filtered;
            }
        }
        error_norm / share
    }

    /// The share of the tolerance the current step size may spend at the current order
    /// ([`share_at_order`](Self::share_at_order)).
    fn step_share(&self) -> f64 {
        self.share_at_order(self.order)
    }

    /// The share of the tolerance the current step size may spend at order `order`: its share of the span
    /// ([`Tolerances::step_share`]), bounded below by [`ShareFloor`], and for a method held to order 1
    /// (`max_order = 1`) at least [`Tolerances::first_order_share`]. At the default orders, order 1 is
    /// only the first steps and the restarts after failed attempts, and keeps the share of its step size:
    /// with the first-order floor there, the 3-D energy of a free flexible body drifted by 3.6e-5 at rtol
    /// 1e-9 (1e-6 without).
    fn share_at_order(&self, order: usize) -> f64 {
        let share = self.share_floor.share_above(&self.tolerances, self.h, self.noise_floor.floor());
        if order == 1 && self.config.max_order == 1 {
            share.max(self.tolerances.first_order_share(self.h))
        } else {
            share
        }
    }

    /// The Newton tolerance of the attempt at the current step's share, the one its iteration is tested
    /// against and the rate monitor predicts for. Its floor is [`BDF_NEWTON_FLOOR`], 20 units of rounding,
    /// where the conditioning does not amplify the rounding, and the other methods' 100 units where the
    /// singular-position guard does (`amplification > 1`: there the increments are rounding at far more
    /// than either, and Andrews' squeezer, κ ≈ 191 at every step, lost accuracy with 20).
    fn newton_tolerance(&self) -> f64 {
        if self.amplification > 1.0 {
            self.tolerances.newton_tolerance_at(self.share)
        } else {
            self.tolerances.newton_tolerance_above(self.share, BDF_NEWTON_FLOOR)
        }
    }

    /// Whether the converged iteration of `test` is polished ([`polish`](Self::polish)): where its
    /// tolerance is the Newton floor [`BDF_NEWTON_FLOOR`] (the step's share is so small that the floor,
    /// not the share, decides when the iteration stops), the step is held to within [`POLISH_FROM`] of
    /// the solution (where the fixed floor under the share holds the steps or is near to), and the steps
    /// the fixed floor held so far could spend [`POLISH_SPENT`] of the tolerance (so that the short first
    /// steps of an ordinary run are not polished), away from singular positions (the guard's
    /// amplification is 1 and it is not near one), where the leftover the floor lets through is what the
    /// estimates' noise is made of.
    fn polishes(&self) -> bool {
        let held_to = self.tolerances.rtol * self.share;
        let spent = self.stats.share_floor_steps as f64 * FINE_STEP_FLOOR;
        self.amplification == 1.0
            && !self.singular.near()
            && held_to <= POLISH_FROM
            && spent >= POLISH_SPENT * self.tolerances.rtol
            && self.tolerances.newton_tolerance() * held_to <= BDF_NEWTON_FLOOR
    }

    /// One more iteration on the converged corrector: its increment, the leftover of the converged
    /// iteration, is applied, and its RMS over the positions and velocities in the error weights, times
    /// `rtol` (relative to the solution, as the estimate's floor is), returned; `None` when the solve fails
    /// (the iterate is then unchanged).
    fn polish(&mut self, t_new: f64, c: f64, c_f: f64) -> Option<f64> {
        let increment_scale = 2.0 / (1.0 + c_f / c);
        let mut corrector = Corrector { bdf: self, t_new, c, c_f, increment_scale };
        corrector.residual(0);
        if !corrector.solve() || !corrector.bdf.rhs.iter().all(|x| x.is_finite()) {
            return None;
        }
        corrector.apply();
        self.stats.newton_iterations += 1;
        Some(self.tolerances.rtol * self.rms_norm(&self.rhs, 1.0))
    }

    fn reduce_step(&mut self, factor: f64) {
        self.reuse.at_attempt = false;
        self.h *= factor;
        self.change_differences(self.order, factor);
        self.reuse.factored_c = None;
    }

    fn refresh_jacobian(&mut self, t_new: f64, c: f64) {
        for k in 0..self.n {
            self.yp[k] = self.psi[k] / c;
        }
        let (y, yp) = (std::mem::take(&mut self.y_pred), std::mem::take(&mut self.yp));
        self.evaluate_jacobian_at(t_new, &y, &yp);
        self.y_pred = y;
        self.yp = yp;
        self.reuse.at_attempt = true;
    }

    /// Simplified Newton iteration on the corrector; returns whether it converged, the iterations begun
    /// and the test with the rates it measured.
    /// `c_f` is the `c` the factors were made for; rows are scaled by it and the increments by
    /// `2/(1 + c_f/c)`, which makes the iteration exact for the `F_ẏ` part when `c_f ≠ c`.
    fn newton(&mut self, t_new: f64, c: f64, c_f: f64) -> (bool, usize, ConvergenceTest) {
        self.corr.fill(0.0);
        self.y_new.copy_from_slice(&self.y_pred);
        let mut test =
            ConvergenceTest::new(self.newton_tolerance(), NEWTON_MAXITER)
                .with_round_off(self.tolerances.round_off_at(self.share) * SingularPassage::round_off_factor(self.amplification))
                .with_rounding_floor(self.rounding.in_share(self.share))
                .with_rounding_level(self.rounding_level.map(|level| self.bounded_level(level) / self.share));
        let increment_scale = 2.0 / (1.0 + c_f / c);
        let mut corrector = Corrector { bdf: self, t_new, c, c_f, increment_scale };
        let outcome = newton::iterate(&mut corrector, &mut test, NEWTON_MAXITER);
        self.stats.newton_iterations += outcome.solves;
        (outcome.converged, outcome.iterations, test)
    }

    /// Weighted RMS norm of a Newton increment over all components, multipliers included: a chord
    /// iteration with an old iteration matrix can converge in `q`, `v` while the multipliers diverge
    /// (seen on a flexible pendulum whose spin about the beam axis has little inertia), so they must
    /// be tested too. The multipliers of this index-2 form enter the solution through `c = h/α`
    /// (their impulse over the step), so their increments are weighted by `c` (Hairer and Wanner's
    /// scaling of index-2 components).
    ///
    /// Measured against the attempt's share of the tolerance, as the local error is: the corrector's
    /// unresolved part is then small against the local error the step is held to, however small the
    /// share (with the whole tolerance as the measure, it was the estimate's floor, and error per unit
    /// step drove the step size to zero).
    fn newton_norm(&self, x: &[f64], c: f64) -> f64 {
        weighted_rms_norm((0..self.n).map(|k| {
            // Near a singular position the multipliers' rounding is amplified once more than the positions'
            // and velocities' (κ² against κ), along a direction in which they hardly act on the motion.
            let weight = if k < self.n_diff { 1.0 } else { c / self.amplification };
            (weight * x[k], self.scale[k])
        })) / self.share
    }

    /// The rounding level `level` (in tolerances) bounded as the learnt rounding floor is: only increments
    /// below [`NOISE_CEILING`] of the solution and [`CHANGE_RATIO`] of the step's change of it can be
    /// rounding (a motion that runs away has an ill-conditioned iteration matrix, and a large estimate).
    /// 0 (none) when it is above the step's share of the tolerance: the tolerance is then finer than the
    /// arithmetic resolves this model, and the learnt floor, which also covers the error estimates, takes
    /// over. The level sums the blocks' rounding, and an increment within it may still carry a correction
    /// of another block (the chain of 1,024 rods at rtol 1e-12: a level of 15 tolerances, almost all in
    /// the position constraints' multipliers, let through corrections of 1 tolerance in the velocity
    /// constraints' at the start; 800 steps and 80 error-test failures against 362 and 6 without it).
    ///
    /// Near a singular position (the guard's `amplification` above 1) the level is kept up to the
    /// rounding of the estimates there, [`SingularPassage::estimate_rounding`] (`50 · gain · 10 ε κ /
    /// rtol`), above the share, the ceiling and the step's change alike: the double four-bar over its run
    /// at rtol 1e-10 stalled 0.1 ms before its fifth position (κ = 9,200, steps down to 2e-14 s) with
    /// increments of 1.0e4 to 2.3e4 shares below a level of 3.3e4 that the ceiling (1e-9 of the solution)
    /// and the steps' change had cut away; kept, the run completes (9,902 steps, B0 1.6e-8 m off the
    /// exact path).
    fn bounded_level(&self, level: f64) -> f64 {
        let near_position = SingularPassage::estimate_rounding(self.amplification, self.tolerances.rtol, self.order);
        let ceiling = (NOISE_CEILING / self.tolerances.rtol).min(CHANGE_RATIO * self.predicted_change());
        let bounded = level.min(ceiling.max(near_position));
        if bounded <= self.share.max(near_position) {
            bounded
        } else {
            0.0
        }
    }

    /// The error estimate `rhs` filtered through the iteration matrix, `x = J⁻¹ [F_ẏ e; F_y e]` with
    /// `J = [F_ẏ + c F_y; F_y]` (differential; algebraic rows), in the norm of [`rms_norm`](Self::rms_norm).
    ///
    /// On the differential rows this is Shampine's filter `(I − c ∂f/∂y)⁻¹ e` of the local error of an
    /// implicit formula: a component of eigenvalue `λ` is divided by `1 − c λ`, so that the estimate of a
    /// stiff, damped component (`c λ ≪ −1`) shrinks to what the corrector actually leaves of it, while a
    /// non-stiff one is unchanged to `O(c λ)`. The algebraic rows keep `F_y x = F_y e`: the part of `e`
    /// that the constraints determine (across the constraint manifold) is not filtered, only the free
    /// motions are. A fully driven mechanism (no degree of freedom) therefore keeps its classical estimate,
    /// which its dense output and multipliers need. Uses the factors of the last step (`c_f`); infinite if
    /// the solve fails.
    fn filtered_norm(&mut self, factor: f64) -> f64 {
        self.jac.filter_rhs(&self.rhs, &mut self.filtered);
        if self.jac.solve_in_place(&mut self.filtered).is_err() {
            return f64::INFINITY;
        }
        self.rms_norm(&self.filtered, factor)
    }

    /// Weighted RMS norm of `factor · x` over the differential components.
    fn rms_norm(&self, x: &[f64], factor: f64) -> f64 {
        weighted_rms_norm((0..self.n_diff).map(|k| (factor * x[k], self.scale[k])))
    }

    /// Accepts `y_new` at `t_new`: renormalizes Euler parameters, updates the differences and counters.
    fn accept(&mut self, t_new: f64) {
        let n = self.n;
        let (corr, q_start) = (&mut self.corr, self.yl.q.start);
        normalize_euler_parameters(&self.model, &mut self.y_new[self.yl.q.clone()], |k, change| corr[q_start + k] += change);
        let h = t_new - self.t;
        self.t_old = self.t;
        self.t = t_new;
        self.stats.steps += 1;
        self.stats.sum_h_squared += h * h;
        self.stats.order_counts[self.order] += 1;
        self.reuse.at_attempt = false;
        self.n_equal_steps += 1;
        let order = self.order;
        for k in 0..n {
            self.d[(order + 2) * n + k] = self.corr[k] - self.d[(order + 1) * n + k];
            self.d[(order + 1) * n + k] = self.corr[k];
        }
        for i in (0..=order).rev() {
            for k in 0..n {
                self.d[i * n + k] += self.d[(i + 1) * n + k];
            }
        }
        update_angle_references(&self.model, &mut self.data);
    }

    /// The message of a step-size underflow after `failure`. The predictor of the failed attempt is still
    /// in `y_pred` and `psi` (a step-size reduction changes only the differences).
    fn describe_failure(&mut self, failure: AttemptFailure) -> String {
        failure.describe(|t_new, step| self.worst_equation(t_new, step))
    }

    /// What went wrong at the predictor, named for a person: the largest residual of the equations of
    /// motion and of the constraints, and any constraints that have become dependent (a lock or a
    /// singular position). Only called when a step fails, so it may allocate.
    fn worst_equation(&mut self, t_new: f64, c: f64) -> String {
        for k in 0..self.n {
            self.yp[k] = self.psi[k] / c;
        }
        residual(&self.model, &mut self.data, &self.yl, &self.active, t_new, &self.y_pred, &self.yp, &mut self.res);
        let (model, yl, res, n_diff) = (&self.model, &self.yl, &self.res, self.n_diff);
        diagnosis::worst_equations(
            model,
            &mut self.data,
            t_new,
            &self.y_pred[yl.q.clone()],
            &self.active,
            (0..n_diff, yl.lambda.start..self.n),
            // The differential rows' residuals are rates; times c they are the change over the step.
            |i| if i < n_diff { c * res[i] } else { res[i] },
            |row| equation_row(model, yl, row),
        )
    }
}

/// The step bounds of orders 3–5 learned from unstable steps ([`BdfConfig::stability_limits`]).
struct StabilityLimits {
    /// Largest step for each order found stable (infinite until a limit is found; orders 1, 2 never).
    h_limit: [f64; MAX_ORDER + 1],
    /// Step size and error estimate of the last accepted step.
    last_h: f64,
    last_error: f64,
}

impl StabilityLimits {
    fn new() -> Self {
        Self { h_limit: [f64::INFINITY; MAX_ORDER + 1], last_h: 0.0, last_error: f64::INFINITY }
    }

    /// An error-test failure with estimate `error_norm` at `order` and step `h`. If the estimate grew fast
    /// at an unchanged step size, a lightly damped oscillation that orders 3–5 amplify at this `h λ` (they
    /// are not A-stable), not the smooth solution, made it: the order's steps are kept below this one.
    fn error_test_failed(&mut self, order: usize, h: f64, error_norm: f64) {
        if order >= 3 && h == self.last_h && error_norm > STABILITY_GROWTH * self.last_error {
            self.h_limit[order] = self.h_limit[order].min(STABILITY_MARGIN * h);
        }
    }

    /// A step of size `h` accepted with estimate `error_norm`.
    fn accepted(&mut self, h: f64, error_norm: f64) {
        self.last_h = h;
        self.last_error = error_norm;
    }

    /// Relaxes every bound by [`STABILITY_RELAX`] (once per accepted step), so that an order is retried.
    fn relax(&mut self) {
        self.h_limit.iter_mut().for_each(|l| *l *= STABILITY_RELAX);
    }
}

/// The corrector equations `F(t_new, y⁽⁰⁾ + d, (ψ + d)/c) = 0` of one attempt, in the correction `d`
/// (`corr`, with the iterate `y_new = y⁽⁰⁾ + d`), for the Newton driver.
struct Corrector<'a> {
    bdf: &'a mut Bdf,
    t_new: f64,
    c: f64,
    /// The `c` the factors were made for, and the increments' scale `2/(1 + c_f/c)`.
    c_f: f64,
    increment_scale: f64,
}

impl NewtonSystem for Corrector<'_> {
    fn residual(&mut self, _k: usize) -> &[f64] {
        let b = &mut *self.bdf;
        for i in 0..b.n {
            b.yp[i] = (b.psi[i] + b.corr[i]) / self.c;
        }
        residual(&b.model, &mut b.data, &b.yl, &b.active, self.t_new, &b.y_new, &b.yp, &mut b.res);
        b.stats.residual_evaluations += 1;
        &b.res
    }

    fn solve(&mut self) -> bool {
        let b = &mut *self.bdf;
        for i in 0..b.n {
            b.rhs[i] = if i < b.n_diff { -self.c_f * b.res[i] } else { -b.res[i] };
        }
        if b.jac.solve_in_place(&mut b.rhs).is_err() {
            return false;
        }
        if self.increment_scale != 1.0 {
            b.rhs.iter_mut().for_each(|x| *x *= self.increment_scale);
        }
        true
    }

    fn increment_norm(&mut self) -> f64 {
        self.bdf.newton_norm(&self.bdf.rhs, self.c)
    }

    /// The increment of the residual's rounding at the iterate, `J⁻¹ (ε |J| |y|)` with the rows' signs of
    /// [`rounding_residual`], in the increments' norm; kept for the next iterations with the same factors,
    /// and bounded by [`bounded_level`](Bdf::bounded_level). Solved in the filtered estimate's scratch,
    /// which the error test fills afresh after the iteration.
    fn rounding_level(&mut self) -> f64 {
        let b = &mut *self.bdf;
        b.jac.absolute_product(&b.y_new, &mut b.filtered);
        rounding_residual(&mut b.filtered);
        if b.jac.solve_in_place(&mut b.filtered).is_err() {
            return 0.0;
        }
        let raw = self.increment_scale * b.newton_norm(&b.filtered, self.c);
        b.rounding_level = Some(raw * b.share);
        b.bounded_level(raw * b.share) / b.share
    }

    fn apply(&mut self) {
        let b = &mut *self.bdf;
        for i in 0..b.n {
            b.y_new[i] += b.rhs[i];
            b.corr[i] += b.rhs[i];
        }
    }
}

/// What row `row` of the residual is.
fn equation_row(model: &Model, yl: &YLayout, row: usize) -> EquationRow {
    if yl.q.contains(&row) {
        EquationRow::Kinematic(model.layout.position_body(row - yl.q.start))
    } else if yl.v.contains(&row) {
        EquationRow::Motion(row - yl.v.start)
    } else if yl.lambda.contains(&row) {
        EquationRow::VelocityConstraint(row - yl.lambda.start)
    } else if row - yl.mu.start < model.layout.nc {
        EquationRow::PositionConstraint(row - yl.mu.start)
    } else {
        EquationRow::Normalization(row - yl.mu.start - model.layout.nc)
    }
}

/// The matrix `R` of Shampine and Reichelt for changing the step by `factor` at order `order`.
fn compute_r(order: usize, factor: f64) -> [[f64; MAX_ORDER + 1]; MAX_ORDER + 1] {
    let mut m = [[0.0; MAX_ORDER + 1]; MAX_ORDER + 1];
    for j in 0..=order {
        m[0][j] = 1.0;
    }
    for i in 1..=order {
        for j in 1..=order {
            m[i][j] = (i as f64 - 1.0 - factor * j as f64) / i as f64;
        }
    }
    // cumulative product down the columns
    for i in 1..=order {
        for j in 0..=order {
            m[i][j] *= m[i - 1][j];
        }
    }
    m
}

/// A converged corrector is polished (its leftover measured for the floor under the share,
/// `integrate/noise_floor.rs`) where its step is held to at most this fraction of the solution, three
/// times the fixed floor [`FINE_STEP_FLOOR`]: the measurement is there when that floor would hold the
/// steps, and costs no iteration where it cannot (polished wherever the Newton floor stopped the
/// iteration, the 3-D slider-crank at rtol 1e-7 and 1e-8 took 18 % and 28 % more residual evaluations
/// for the same steps within 1 %).
const POLISH_FROM: f64 = 3.0 * FINE_STEP_FLOOR;
/// Nor before the steps the fixed floor held could spend this fraction of the tolerance, their number
/// times [`FINE_STEP_FLOOR`]: where they cannot, the floor does not decide the run's error, and the
/// measured noise, which is rounding, would only make the steps of two models of one motion differ (at
/// rtol 1e-6 the first steps of a run, 1e-8 s and shorter, are held to the floor; polished, a rigid body
/// and the same body as a modal body without modes took different steps). From rtol 1e-9 the runs that
/// the floor holds measure it after 1,000 held steps and less.
const POLISH_SPENT: f64 = 0.1;

/// The power of `h` in the ratio of an estimate of order `h^power` (of the order `power − 1`) to its
/// share of the tolerance ([`Bdf::share_at_order`]; `first_order_method`: the BDF is held to order 1).
fn error_power(tolerances: &Tolerances, h: f64, power: usize, first_order_method: bool, floor: f64) -> f64 {
    if power == 2 && first_order_method {
        tolerances.first_order_error_power(h)
    } else {
        tolerances.error_power_above(h, power, floor)
    }
}

/// The factor by which independent leftovers `δ` of the Newton iterations in the accepted states reach
/// the error estimate of order `k` (in the RMS over the leftovers' signs): the estimate is `d/(k + 1)`,
/// `d = yₙ₊₁ − y⁽⁰⁾`, and the predictor extrapolates the last `k + 1` states with the weights
/// `(−1)ʲ C(k+1, j+1)` at equal steps, so `d` carries `δₙ₊₁ − Σ (−1)ʲ C(k+1, j+1) δₙ₋ⱼ`, whose RMS is
/// `√(Σⱼ C(k+1, j)²) δ = √C(2k+2, k+1) δ`: 1.22, 1.49, 2.09, 3.17 and 5.07 at orders 1 to 5 (the worst
/// case, leftovers alternating in sign, `2^(k+1)/(k + 1)`: 10.7 at order 5).
fn noise_gain(k: usize) -> f64 {
    let central = (1..=k + 1).fold(1.0, |c: f64, j| c * (k + 1 + j) as f64 / j as f64);
    central.sqrt() / (k + 1) as f64
}

#[cfg(test)]
#[test]
fn the_noise_gain_is_the_rms_of_the_predictors_weights_over_the_error_constant() {
    let expected = [(1, 6.0_f64.sqrt() / 2.0), (2, 20.0_f64.sqrt() / 3.0), (5, 924.0_f64.sqrt() / 6.0)];
    for (k, gain) in expected {
        assert!((noise_gain(k) - gain).abs() < 1e-12, "order {k}: {} against {gain}", noise_gain(k));
    }
}

/// First step from the size of the state and its derivative (Hairer, Nørsett and Wanner, II.4).
fn initial_step(tolerances: &Tolerances, y0: &[f64], yp0: &[f64]) -> f64 {
    let Tolerances { atol, rtol, .. } = *tolerances;
    let norm = |x: &[f64]| weighted_rms_norm(x.iter().zip(y0).map(|(&xi, &yi)| (xi, error_weight(atol, rtol, yi))));
    let d0 = norm(y0);
    let d1 = norm(yp0);
    let h = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
    h.min(1e-2)
}

/// Angles of all rotational joints at the state, continued from zero.
fn state_angle_references(model: &Model, data: &mut Data, state: &State) -> Vec<f64> {
    crate::stage::kinematics(model, data, &state.q, &state.v);
    data.angle_reference.fill(0.0);
    update_angle_references(model, data);
    data.angle_reference.clone()
}

impl Integrator for Bdf {
    fn t(&self) -> f64 {
        self.t
    }
    fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError> {
        Bdf::step(self, t_stop)
    }
    fn state(&self) -> (&[f64], &[f64]) {
        let y = self.y();
        (&y[self.yl.q.clone()], &y[self.yl.v.clone()])
    }
    fn interpolate(&mut self, t: f64, q: &mut [f64], v: &mut [f64]) {
        let mut y = std::mem::take(&mut self.y_interp);
        Bdf::interpolate(self, t, &mut y);
        q.copy_from_slice(&y[self.yl.q.clone()]);
        v.copy_from_slice(&y[self.yl.v.clone()]);
        self.y_interp = y;
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
        "bdf"
    }
    fn checkpoint(&self) -> Result<IntegratorCheckpoint, CheckpointError> {
        Ok(IntegratorCheckpoint::Bdf(Bdf::checkpoint(self)))
    }
    fn restore(&mut self, checkpoint: &IntegratorCheckpoint) -> Result<(), CheckpointError> {
        match checkpoint {
            IntegratorCheckpoint::Bdf(c) => Bdf::restore(self, c),
            other => Err(CheckpointError::Method { expected: "bdf", found: other.method() }),
        }
    }
}

#[cfg(test)]
#[path = "bdf_tests.rs"]
mod tests;
