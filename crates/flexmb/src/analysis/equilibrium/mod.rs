//! Static equilibrium: the configuration at which the loads at time `t` (gravity, springs, applied
//! forces, the flexible bodies' elastic forces, drivers held at their values at `t`) are balanced by
//! the joints alone, with the mechanism at rest (Adams' STATIC, DADS' static analysis).
//!
//! With `v = 0` and `v̇ = 0` the equations of motion `M v̇ + h − Q + Bᵀλ = 0` become
//!
//! ```text
//! f(q) + B(q)ᵀ λ = 0,     f = h(q, 0) − Q(q, 0, t),     Φ(q, t) = 0,
//! ```
//!
//! solved by Newton's method on the constraint manifold (Haug 1989, §9.3 on static equilibrium):
//! at each iterate `q` (held on `Φ = 0` by the assembly's projection) the multipliers are the least
//! squares `λ = argmin ‖f + Bᵀλ‖`, the residual left is `Nᵀ f` (`N` an orthonormal basis of the
//! null space of `B`: the motions the joints allow), and the step `δq = N z` solves
//!
//! ```text
//! (Nᵀ K N) z = −Nᵀ f,      K = ∂(f + Bᵀλ)/∂q   (λ held)
//! ```
//!
//! with `K` the stiffness of the engine's linearization at `v = 0`, `v̇ = 0` and these multipliers
//! ([`SparseLinearization`]: elastic, spring and gravity stiffness and the constraint forces' change
//! of direction). The positions are moved in velocity space (`p ∘ exp(δω̄)`, as
//! [`displaced_positions`](super::displaced_positions) does, so the Euler parameters stay unit) and
//! projected back onto the constraints; a backtracking line search on `‖f + Bᵀλ‖₂` accepts a step that
//! reduces it.
//!
//! Directions the reduced stiffness `Nᵀ K N` does not resist (singular values below 10⁻⁹ of the
//! largest) get no step when there is no load along them: a pendulum's free spin about its own rod is
//! neutral, and the equilibrium exists (the minimum-norm step of the truncated pseudo-inverse). With a
//! load along such a direction — a pendulum released horizontal, where gravity's stiffness vanishes —
//! or when the line search fails, the iteration falls back on damped dynamic relaxation in pseudo-time
//! ([`EquilibriumFallback::Relaxation`]), implicit: `(Nᵀ K N + σ Nᵀ M N) z = −Nᵀ f`, the step of a
//! heavily damped motion of the mechanism's own mass, with `σ` following the residual (switched
//! evolution relaxation, Mulder and van Leer 1985; Kelley and Keyes 1998): large where the residual
//! does not fall, vanishing near the equilibrium so that the last steps are Newton's. Where the
//! residual stays and the stiffness along the load stays zero, the mechanism has no equilibrium and
//! the error names the motion ([`FreeMotion`]): the bodies, each one's direction of translation and
//! axis of rotation, and the unbalanced generalized force.

mod free_motion;
mod reactions;
mod static_point;

pub use free_motion::{BodyMotion, FreeMotion};
pub use reactions::{joint_reactions, JointReaction, ReactionSide};

use faer::prelude::*;
use faer::Side;

use super::assembly::project_positions;
use super::{assemble, AssemblyError, AssemblyReport, AssemblySettings, OperatingPoint, SparseLinearization, State};
use crate::data::Data;
use crate::model::{Model, SizeCheck, SizeMismatch};
use crate::stage::{body_mass_entries, retract, run_kinematic_stages};
use static_point::StaticPoint;

/// Singular values of the reduced stiffness below this fraction of the largest are directions it does
/// not resist (above the finite-difference noise of `K`, about 10⁻⁸ relative on a column).
const NEUTRAL_TOLERANCE: f64 = 1e-9;
/// And so are those below this fraction of the largest load per unit of motion (N/m, N m/rad): a
/// stiffness that would balance the whole load only after a motion of 10⁸ m or rad (when every
/// direction is neutral, the relative test alone sees none).
const NEUTRAL_LOAD_FRACTION: f64 = 1e-8;
/// The first relaxation step moves about this far (m or rad) along the load.
const FIRST_RELAXATION_STEP: f64 = 0.1;
/// A direction along which the load would have to move the mechanism further than this (m or rad, at
/// the rate of the stiffness there) to be balanced, when the iterations have run out, is a free motion:
/// a crank driven round by a motor, whose stiffness comes only from the small change of geometry.
const FREE_MOTION_LENGTH: f64 = 1.0;
/// Relaxation steps in a row that leave the residual (to 10⁻⁶) where it was before the motion is
/// declared free.
const STALLED_STEPS: usize = 5;

/// What the equilibrium iteration may do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EquilibriumSettings {
    /// Largest force residual `|f + Bᵀλ|` accepted, relative to the largest applied generalized force at
    /// the start (N, N m, modal force). Default 10⁻¹⁰.
    pub force_tolerance: f64,
    /// Most Newton iterations before the fallback. Default 50.
    pub max_iterations: usize,
    /// What to do when Newton's method cannot go on. Default [`EquilibriumFallback::Relaxation`].
    pub fallback: EquilibriumFallback,
    /// Most iterations of the fallback. Default 200.
    pub max_relaxation_iterations: usize,
    /// The assembly of the starting configuration and the projection of each iterate onto the
    /// constraints (its tolerance is the constraint residual accepted).
    pub assembly: AssemblySettings,
}

impl Default for EquilibriumSettings {
    fn default() -> Self {
        Self {
            force_tolerance: 1e-10,
            max_iterations: 50,
            fallback: EquilibriumFallback::Relaxation,
            max_relaxation_iterations: 200,
            assembly: AssemblySettings::default(),
        }
    }
}

/// The fallback when Newton's method meets a load along a direction of zero stiffness or its line
/// search fails.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EquilibriumFallback {
    /// None: the iteration fails (naming the free motion when there is one).
    None,
    /// Damped dynamic relaxation in pseudo-time (implicit, with the mechanism's mass).
    #[default]
    Relaxation,
}

/// The method of an iteration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EquilibriumMethod {
    /// Newton's method with a line search.
    Newton,
    /// Damped dynamic relaxation in pseudo-time.
    Relaxation,
}

impl EquilibriumMethod {
    /// `newton` or `relaxation`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Newton => "newton",
            Self::Relaxation => "relaxation",
        }
    }
}

/// The residuals at one iterate and the step taken from it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EquilibriumIteration {
    /// The method of the step from this iterate (of the last iterate: the method that converged).
    pub method: EquilibriumMethod,
    /// Largest `|f + Bᵀλ|` (N, N m, modal force).
    pub force_residual: f64,
    /// Largest `|Φ|` of the constraints in force.
    pub constraint_residual: f64,
}

/// What the equilibrium iteration found.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct EquilibriumReport {
    /// The assembly of the starting configuration (redundant rows, degrees of freedom).
    pub assembly: AssemblyReport,
    /// Iterations made (Newton's and the fallback's).
    pub iterations: usize,
    /// The method of the last step: [`EquilibriumMethod::Relaxation`] when the fallback was needed.
    pub method: EquilibriumMethod,
    /// Residuals at each iterate, the start first and the equilibrium last.
    pub history: Vec<EquilibriumIteration>,
    /// Largest force residual at the equilibrium.
    pub force_residual: f64,
    /// Largest constraint residual at the equilibrium.
    pub constraint_residual: f64,
    /// The force residual accepted (the relative tolerance times the largest applied generalized force).
    pub force_tolerance: f64,
    /// Multipliers `λ`, one per constraint row (zero for the rows switched off).
    pub multipliers: Vec<f64>,
    /// The reaction of every joint and driver on its bodies.
    pub reactions: Vec<JointReaction>,
    /// Degrees of freedom of the mechanism.
    pub degrees_of_freedom: usize,
    /// Directions the stiffness at the equilibrium does not resist (neutral, without load).
    pub neutral_directions: usize,
    /// Directions of negative stiffness: more than zero for an unstable equilibrium (an inverted
    /// pendulum), which a dynamic run leaves at the least disturbance.
    pub unstable_directions: usize,
}

/// Why no static equilibrium was found.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum EquilibriumError {
    /// The starting configuration could not be assembled, or an iterate projected onto the constraints.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// The loads drive a motion that nothing resists: there is no static equilibrium.
    #[error(
        "no static equilibrium at t = {t} s: the mechanism moves freely under its loads: {motion}; hold \
         that motion with a joint, a driver or a spring, or remove the load along it"
    )]
    FreeMotion {
        /// Time (s).
        t: f64,
        /// The motion.
        motion: FreeMotion,
    },
    /// Neither Newton's method nor the fallback brought the residuals below the tolerances.
    #[error(
        "the static equilibrium did not converge in {iterations} iterations: force residual \
         {force_residual:.3e} (tolerance {force_tolerance:.3e}), constraint residual {constraint_residual:.3e}; \
         start from a configuration closer to the equilibrium, or allow more iterations"
    )]
    NotConverged {
        /// Iterations made.
        iterations: usize,
        /// Largest force residual left.
        force_residual: f64,
        /// The force residual accepted.
        force_tolerance: f64,
        /// Largest constraint residual left.
        constraint_residual: f64,
    },
    /// The workspace or the state is not of the model's sizes.
    #[error(transparent)]
    SizeMismatch(#[from] SizeMismatch),
}

/// Moves `state` to the static equilibrium at time `t` (velocities zero): assembles it first (which
/// sets the rows in force), then Newton's method on the constrained static equations with the fallback
/// of `settings`. `data`'s stages are left evaluated at the equilibrium.
///
/// ```
/// use flexmb::analysis::{static_equilibrium, State};
/// # let model = flexmb::analysis::test_models::double_pendulum_with_spring();
/// let mut data = flexmb::Data::new(&model);
/// let mut state = State::initial(&model);
/// let report = static_equilibrium(&model, &mut data, &mut state, 0.0, &Default::default()).unwrap();
/// assert!(report.force_residual <= report.force_tolerance);
/// assert!(state.v.iter().all(|v| *v == 0.0));
/// ```
pub fn static_equilibrium(
    model: &Model,
    data: &mut Data,
    state: &mut State,
    t: f64,
    settings: &EquilibriumSettings,
) -> Result<EquilibriumReport, EquilibriumError> {
    SizeCheck::new(model).data(data)?.state(state)?;
    state.t = t;
    state.v.fill(0.0);
    let assembly = assemble(model, data, state, settings.assembly)?;
    let mut iteration = Iteration::new(model, settings, data, state);
    let point = iteration.solve(data, state)?;
    let reactions = joint_reactions(model, data, &point.lambda);
    let tangent = iteration.tangent(data, state, &point);
    let (neutral_directions, unstable_directions) = stiffness_signature(&tangent.stiffness, iteration.neutral_stiffness);
    let last = *iteration.history.last().expect("the start is recorded");
    Ok(EquilibriumReport {
        degrees_of_freedom: assembly.degrees_of_freedom,
        assembly,
        iterations: iteration.history.len() - 1,
        method: last.method,
        force_residual: last.force_residual,
        constraint_residual: last.constraint_residual,
        force_tolerance: iteration.force_tolerance,
        history: iteration.history,
        multipliers: point.lambda,
        reactions,
        neutral_directions,
        unstable_directions,
    })
}

/// The reduced equations at an iterate: `Nᵀ K N`, `Nᵀ M N` and the right side `−Nᵀ (f + K δq_Φ)`,
/// with `δq_Φ = −B⁺ Φ` the least change that closes the constraints.
struct Tangent {
    stiffness: Mat<f64>,
    mass: Mat<f64>,
    rhs: Mat<f64>,
    closing: Vec<f64>,
}

/// The state of the iteration.
struct Iteration<'a> {
    model: &'a Model,
    settings: &'a EquilibriumSettings,
    derivatives: SparseLinearization,
    force_tolerance: f64,
    /// Singular values of the reduced stiffness at or below this are neutral directions.
    neutral_stiffness: f64,
    history: Vec<EquilibriumIteration>,
    zero: Vec<f64>,
}

impl<'a> Iteration<'a> {
    fn new(model: &'a Model, settings: &'a EquilibriumSettings, data: &mut Data, state: &State) -> Self {
        let point = StaticPoint::evaluate(model, data, state);
        let load = data.applied.iter().chain(&point.force).fold(0.0_f64, |m, x| m.max(x.abs()));
        Self {
            model,
            settings,
            derivatives: SparseLinearization::new(model),
            force_tolerance: settings.force_tolerance * load,
            neutral_stiffness: NEUTRAL_LOAD_FRACTION * load,
            history: Vec::new(),
            zero: vec![0.0; model.layout.nv],
        }
    }

    fn converged(&self, point: &StaticPoint) -> bool {
        point.force_residual() <= self.force_tolerance && point.constraint_residual() <= self.settings.assembly.tolerance
    }

    fn record(&mut self, method: EquilibriumMethod, point: &StaticPoint) {
        self.history.push(EquilibriumIteration {
            method,
            force_residual: point.force_residual(),
            constraint_residual: point.constraint_residual(),
        });
    }

    /// Newton's method, then the fallback; returns the static equations at the equilibrium.
    fn solve(&mut self, data: &mut Data, state: &mut State) -> Result<StaticPoint, EquilibriumError> {
        let mut point = StaticPoint::evaluate(self.model, data, state);
        let mut method = EquilibriumMethod::Newton;
        let mut relaxation = Relaxation::default();
        let limit = self.settings.max_iterations + self.settings.max_relaxation_iterations;
        loop {
            self.record(method, &point);
            if self.converged(&point) {
                return Ok(point);
            }
            let iterations = self.history.len() - 1;
            if iterations >= limit || (method == EquilibriumMethod::Newton && iterations >= self.settings.max_iterations) {
                if method == EquilibriumMethod::Relaxation || !self.may_relax() {
                    return Err(self.failure(data, state, &point));
                }
                method = EquilibriumMethod::Relaxation;
            }
            let tangent = self.tangent(data, state, &point);
            if method == EquilibriumMethod::Newton {
                match self.newton_step(data, state, &point, &tangent) {
                    Some(next) => {
                        point = next;
                        continue;
                    }
                    None if self.may_relax() => method = EquilibriumMethod::Relaxation,
                    None => return Err(self.failure(data, state, &point)),
                }
                self.history.last_mut().expect("recorded").method = method;
            }
            point = relaxation.step(self, data, state, &point, &tangent)?;
        }
    }

    fn may_relax(&self) -> bool {
        self.settings.fallback == EquilibriumFallback::Relaxation
    }

    /// The reduced stiffness, mass and right side at the iterate `state`, `point`.
    fn tangent(&mut self, data: &mut Data, state: &State, point: &StaticPoint) -> Tangent {
        let (model, l) = (self.model, &self.model.layout);
        let at = OperatingPoint { t: state.t, q: &state.q, v: &self.zero, vdot: &self.zero, lambda: &point.lambda };
        self.derivatives.evaluate_at(model, data, &state.active, &at);
        let (k, _, _) = self.derivatives.to_dense();
        run_kinematic_stages(model, data, state.t, &state.q, &self.zero);
        let mut m = Mat::<f64>::zeros(l.nv, l.nv);
        for b in 0..model.bodies.len() {
            let vo = l.v_offset[b];
            body_mass_entries(model, data, b, |r, c, x| m[(vo + r, vo + c)] += x);
        }
        let n = &point.null_space;
        let closing: Vec<f64> = point.least_change(&point.phi).into_iter().map(|x| -x).collect();
        let closing_col = Mat::from_fn(l.nv, 1, |i, _| closing[i]);
        // `Nᵀ (f + Bᵀλ + W λ) = Nᵀ (f + W λ)`: the residual carries the joints' interface stiffening.
        let f = Mat::from_fn(l.nv, 1, |i, _| point.residual[i]);
        let rhs = -(n.transpose() * (&f + &k * &closing_col));
        Tangent { stiffness: n.transpose() * &k * n, mass: n.transpose() * &m * n, rhs, closing }
    }

    /// The velocity-space step `δq_Φ + N z`.
    fn full_step(&self, point: &StaticPoint, tangent: &Tangent, z: &Mat<f64>) -> Vec<f64> {
        let nz = &point.null_space * z;
        (0..self.model.layout.nv).map(|i| tangent.closing[i] + nz[(i, 0)]).collect()
    }

    /// `state` moved by `alpha d` and projected onto the constraints, with its static equations; `None`
    /// if the projection fails.
    fn trial(&self, data: &mut Data, state: &State, d: &[f64], alpha: f64) -> Option<(State, StaticPoint)> {
        let mut next = state.clone();
        let scaled: Vec<f64> = d.iter().map(|x| alpha * x).collect();
        retract(&self.model.layout, &state.q, &scaled, &mut next.q);
        project_positions(self.model, data, &mut next, self.settings.assembly).ok()?;
        let point = StaticPoint::evaluate(self.model, data, &next);
        point.merit().is_finite().then_some((next, point))
    }

    /// One Newton step with a backtracking line search (Armijo on the merit, halving to 1/64); `None`
    /// when a load acts along a direction of zero stiffness, the reduced stiffness has a negative
    /// direction (Newton's step would head for an unstable equilibrium, where the relaxation goes
    /// downhill) or no step reduces the merit.
    fn newton_step(&self, data: &mut Data, state: &mut State, point: &StaticPoint, tangent: &Tangent) -> Option<StaticPoint> {
        if stiffness_signature(&tangent.stiffness, self.neutral_stiffness).1 > 0 {
            return None;
        }
        let z = match self.truncated_solve(tangent) {
            ReducedStep::Step(z) => z,
            ReducedStep::LoadOnNeutral { .. } => return None,
        };
        let d = self.full_step(point, tangent, &z);
        let merit = point.merit();
        let mut alpha = 1.0;
        while alpha >= 1.0 / 64.0 {
            if let Some((next, next_point)) = self.trial(data, state, &d, alpha) {
                if next_point.merit() <= (1.0 - 1e-4 * alpha) * merit || next_point.force_residual() <= self.force_tolerance {
                    *state = next;
                    return Some(next_point);
                }
            }
            alpha *= 0.5;
        }
        None
    }

    /// The error after the iterations ran out: the free motion when a load acts along a direction
    /// of zero stiffness at the last iterate, else the residuals left.
    fn failure(&mut self, data: &mut Data, state: &State, point: &StaticPoint) -> EquilibriumError {
        let tangent = self.tangent(data, state, point);
        let free = match self.truncated_solve(&tangent) {
            ReducedStep::LoadOnNeutral { direction, load } if load > self.force_tolerance => Some((direction, load)),
            _ => self.far_direction(&tangent),
        };
        if let Some((direction, load)) = free {
            let d = &point.null_space * &direction;
            let motion = free_motion::free_motion(self.model, data, state.t, &state.q, &d, load);
            return EquilibriumError::FreeMotion { t: state.t, motion };
        }
        EquilibriumError::NotConverged {
            iterations: self.history.len() - 1,
            force_residual: point.force_residual(),
            force_tolerance: self.force_tolerance,
            constraint_residual: point.constraint_residual(),
        }
    }
}

/// Damped dynamic relaxation in pseudo-time: `(Nᵀ K N + σ Nᵀ M N) z = −Nᵀ f`, `σ` scaled by the ratio
/// of successive residuals.
#[derive(Default)]
struct Relaxation {
    sigma: Option<f64>,
    stalled: usize,
}

impl Relaxation {
    fn step(
        &mut self,
        iteration: &mut Iteration,
        data: &mut Data,
        state: &mut State,
        point: &StaticPoint,
        tangent: &Tangent,
    ) -> Result<StaticPoint, EquilibriumError> {
        let (k, m) = (&tangent.stiffness, &tangent.mass);
        let mass_norm = m.norm_l2().max(f64::MIN_POSITIVE);
        let floor = 1e-12 * k.norm_l2() / mass_norm;
        let rhs_norm = tangent.rhs.norm_l2();
        let mut sigma = self.sigma.unwrap_or(rhs_norm / (mass_norm * FIRST_RELAXATION_STEP)).max(floor);
        let merit = point.merit();
        for _ in 0..10 {
            let z = (k + sigma * m).partial_piv_lu().solve(&tangent.rhs);
            let d = iteration.full_step(point, tangent, &z);
            if let Some((next, next_point)) = iteration.trial(data, state, &d, 1.0) {
                if next_point.merit() <= 2.0 * merit {
                    let ratio = next_point.merit() / merit;
                    self.stalled = if (ratio - 1.0).abs() < 1e-6 { self.stalled + 1 } else { 0 };
                    self.sigma = Some((sigma * ratio).max(floor));
                    *state = next;
                    if self.stalled >= STALLED_STEPS {
                        if let err @ EquilibriumError::FreeMotion { .. } = iteration.failure(data, state, &next_point) {
                            return Err(err);
                        }
                    }
                    return Ok(next_point);
                }
            }
            sigma *= 4.0;
        }
        Err(iteration.failure(data, state, point))
    }
}

/// The reduced Newton step by the truncated pseudo-inverse, or the load along the neutral directions.
enum ReducedStep {
    Step(Mat<f64>),
    /// `direction`: the load's component in the neutral directions (reduced coordinates); `load`: its
    /// norm.
    LoadOnNeutral { direction: Mat<f64>, load: f64 },
}

impl Iteration<'_> {
    /// The singular direction of the reduced stiffness along which the load would move the mechanism
    /// furthest, `|u_kᵀ Nᵀ f| / s_k`, with its load, if that is more than [`FREE_MOTION_LENGTH`].
    fn far_direction(&self, tangent: &Tangent) -> Option<(Mat<f64>, f64)> {
        let (k, rhs) = (&tangent.stiffness, &tangent.rhs);
        let n = k.nrows();
        let svd = k.svd().ok()?;
        let (u, s) = (svd.U(), svd.S().column_vector());
        let mut far: Option<(usize, f64, f64)> = None;
        for i in 0..n {
            let c = (0..n).map(|r| u[(r, i)] * rhs[(r, 0)]).sum::<f64>();
            let reach = c.abs() / s[i];
            if c.abs() > self.force_tolerance && reach > FREE_MOTION_LENGTH && far.is_none_or(|(_, r, _)| reach > r) {
                far = Some((i, reach, c));
            }
        }
        far.map(|(i, _, c)| (Mat::from_fn(n, 1, |r, _| u[(r, i)] * c), c.abs()))
    }

    /// `z = −(Nᵀ K N)⁺ Nᵀ f` over the singular values above [`NEUTRAL_TOLERANCE`] of the largest and
    /// above the neutral stiffness; when the right side has a component along the others (larger than
    /// 10⁻¹² of its norm and a tenth of the force tolerance), that component.
    fn truncated_solve(&self, tangent: &Tangent) -> ReducedStep {
        let (k, rhs) = (&tangent.stiffness, &tangent.rhs);
        let n = k.nrows();
        if n == 0 {
            return ReducedStep::Step(Mat::zeros(0, 1));
        }
        let Ok(svd) = k.svd() else { return ReducedStep::LoadOnNeutral { direction: rhs.clone(), load: rhs.norm_l2() } };
        let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
        let largest = (0..n).map(|i| s[i]).fold(0.0, f64::max);
        let floor = (NEUTRAL_TOLERANCE * largest).max(self.neutral_stiffness);
        let mut z = Mat::<f64>::zeros(n, 1);
        let mut neutral = Mat::<f64>::zeros(n, 1);
        for i in 0..n {
            let c = (0..n).map(|r| u[(r, i)] * rhs[(r, 0)]).sum::<f64>();
            if s[i] > floor && s[i] > 0.0 {
                for r in 0..n {
                    z[(r, 0)] += v[(r, i)] * c / s[i];
                }
            } else {
                for r in 0..n {
                    neutral[(r, 0)] += u[(r, i)] * c;
                }
            }
        }
        let load = neutral.norm_l2();
        if load > 1e-12 * rhs.norm_l2() && load > 0.1 * self.force_tolerance {
            ReducedStep::LoadOnNeutral { direction: neutral, load }
        } else {
            ReducedStep::Step(z)
        }
    }
}

/// Neutral and negative directions of the symmetric part of the reduced stiffness.
fn stiffness_signature(k: &Mat<f64>, neutral_stiffness: f64) -> (usize, usize) {
    let n = k.nrows();
    if n == 0 {
        return (0, 0);
    }
    let symmetric = Mat::from_fn(n, n, |i, j| 0.5 * (k[(i, j)] + k[(j, i)]));
    let Ok(values) = symmetric.self_adjoint_eigenvalues(Side::Lower) else { return (0, 0) };
    let largest = values.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let floor = (NEUTRAL_TOLERANCE * largest).max(neutral_stiffness);
    let neutral = values.iter().filter(|x| x.abs() <= floor).count();
    let unstable = values.iter().filter(|x| **x < -floor).count();
    (neutral, unstable)
}

/// The values of the model's outputs ([`output_columns`](super::output_columns)) at the static
/// equilibrium `state` with its `multipliers` (accelerations zero): positions, deformations, reactions,
/// measures, energies, one value per column. Leaves the stages evaluated there in `data`.
pub fn equilibrium_outputs(model: &Model, data: &mut Data, state: &State, multipliers: &[f64]) -> Result<Vec<f64>, SizeMismatch> {
    SizeCheck::new(model).data(data)?.state(state)?.rows("the multipliers", multipliers.len())?;
    let zero = vec![0.0; model.layout.nv];
    crate::stage::run_forward(model, data, state.t, &state.q, &zero, &zero);
    let at_rest = super::Accelerations { vdot: zero.clone(), lambda: multipliers.to_vec() };
    let mut values = vec![0.0; super::output_columns(model).len()];
    super::outputs::evaluate_outputs(model, data, (state.t, &state.q, &zero), &at_rest, &state.active, &mut values, false);
    Ok(values)
}
