//! The Adams method applied to a mechanism: the ODE of the state `y = [q, v]`,
//!
//! ```text
//! q̇ = T(q) v                      T(q) v = [Ṙ; ½ Gᵀ(p) ω̄; ȧ] per body
//! v̇ from [M Bᵀ; B 0] [v̇; λ] = [Q − h; γ]      (the index-1 system, Haug 1989 eq. 11.1.19)
//! ```
//!
//! integrated by [`AdamsStepper`], with the constraints enforced by projection after every accepted
//! step (the [`OdeSystem::accept`] hook), before the final evaluation of the PECE step:
//!
//! 1. **Euler parameters** rescaled to unit norm.
//! 2. **Positions**: Newton on `Φ(q, t) = 0` with the minimum-norm correction in the metric of the
//!    mass matrix, `δv = argmin δvᵀ M δv` subject to `B δv = −Φ`, i.e. `[M Bᵀ; B 0] [δv; z] = [0; −Φ]`,
//!    mapped onto the positions by `q ← q ⊕ T(q) δv` (`Φ_q T = B`, so this is a Newton step) and the
//!    Euler parameters rescaled again. The first iterations reuse the factors of the predicted state's
//!    evaluation (a chord iteration; the two states differ by about the local error), refactoring at
//!    the current positions only if the convergence is slow.
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
//! accumulating. [`ProjectionDrift`] measures it: the projection moves the state by a small fraction
//! of the tolerance per step (see the tests).

use crate::analysis::{find_redundant_rows, Accelerations, State};
use crate::data::Data;
use crate::integrate::{BdfConfig, IntegrationError, Integrator, Stats};
use crate::linalg::SparseLu;
use crate::math::euler_parameters::g_matrix;
use crate::math::{Vec3, Vec4};
use crate::model::{BodyId, Model};
use crate::stage::{
    applied_forces, body_mass_entries, constraint_equations, inertia_forces, jacobian_entries, kinematics, measures,
    update_angle_references,
};

use super::method::{AdamsStepper, AttemptFailure, EvaluationFailure, OdeSystem, StepControl, StepFailure};
use super::AdamsConfig;

/// Position Newton iterations of one projection, at most.
const PROJECTION_ITERATIONS: usize = 6;
/// Converged when the last correction is this small in the error-tolerance units of the step.
const CORRECTION_TOLERANCE: f64 = 1e-3;
/// Or when the largest position residual is below this fraction of `atol`.
const RESIDUAL_TOLERANCE: f64 = 1e-2;

const SINGULAR: EvaluationFailure =
    EvaluationFailure("the mass–constraint matrix [M Bᵀ; B 0] is singular (dependent constraints or a massless body)");
const NOT_FINITE: EvaluationFailure = EvaluationFailure("the accelerations are not finite");
const NO_CONVERGENCE: EvaluationFailure =
    EvaluationFailure("the projection onto the position constraints does not converge");

/// How far the solution strayed from the constraints before each projection, and how much the
/// projection moved it: the cost of keeping the difference table while the state is projected.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
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

/// The mechanism as an [`OdeSystem`]: evaluations and projections with their workspaces.
struct MechanismOde<'m> {
    model: &'m Model,
    data: Data,
    active: Vec<bool>,
    /// `[M Bᵀ; B 0]` on the pattern of the model (redundant rows: `z_r = 0`).
    kkt: SparseLu,
    /// Right side and solution of the KKT system, length `nv + nc`.
    rhs: Vec<f64>,
    zero_v: Vec<f64>,
    /// The state before the projection, for the weighted size of its change.
    y_before: Vec<f64>,
    nq: usize,
    nv: usize,
    rtol: f64,
    atol: f64,
    /// The KKT factors are of some recent state (usable for chord iterations).
    factored: bool,
    evaluations: usize,
    factorizations: usize,
    drift: ProjectionDrift,
}

impl<'m> MechanismOde<'m> {
    fn new(model: &'m Model, active: Vec<bool>, rtol: f64, atol: f64) -> Self {
        let l = &model.layout;
        let n = l.nv + l.nc;
        let mut entries = Vec::new();
        for b in 0..model.bodies.len() {
            let range = l.v_range(BodyId(b));
            for r in range.clone() {
                for c in range.clone() {
                    entries.push((r, c));
                }
            }
        }
        for (j, joint) in model.joints.iter().enumerate() {
            for b in model.joint_bodies(joint).into_iter().flatten() {
                for row in l.joint_rows[j].clone() {
                    for k in l.v_range(b) {
                        entries.push((l.nv + row, k));
                        entries.push((k, l.nv + row));
                    }
                }
            }
        }
        Self {
            model,
            data: Data::new(model),
            active,
            kkt: SparseLu::new(n, entries),
            rhs: vec![0.0; n],
            zero_v: vec![0.0; l.nv],
            y_before: vec![0.0; l.nq + l.nv],
            nq: l.nq,
            nv: l.nv,
            rtol,
            atol,
            factored: false,
            evaluations: 0,
            factorizations: 0,
            drift: ProjectionDrift::default(),
        }
    }

    /// Assembles and factors `[M Bᵀ; B 0]` at the positions of the last kinematics and constraint stages.
    fn factor(&mut self) -> Result<(), EvaluationFailure> {
        let (model, nv) = (self.model, self.nv);
        self.kkt.clear();
        for b in 0..model.bodies.len() {
            let vo = model.layout.v_offset[b];
            let kkt = &mut self.kkt;
            body_mass_entries(model, &self.data, b, |r, c, m| kkt.add(vo + r, vo + c, m));
        }
        let (kkt, active) = (&mut self.kkt, &self.active);
        jacobian_entries(model, &self.data, |r, c, x| {
            if active[r] {
                kkt.add(nv + r, c, x);
                kkt.add(c, nv + r, x);
            }
        });
        for (r, a) in self.active.iter().enumerate() {
            if !a {
                self.kkt.add(nv + r, nv + r, 1.0);
            }
        }
        self.factorizations += 1;
        self.factored = false;
        self.kkt.factor().map_err(|_| SINGULAR)?;
        self.factored = true;
        Ok(())
    }

    /// `dy = [T(q) v, v̇]` with `v̇` from the factored KKT system, after the kinematics and constraint
    /// stages at `(q, v)`.
    fn accelerations(&mut self, t: f64, q: &[f64], v: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let (model, nv, nq) = (self.model, self.nv, self.nq);
        measures(model, &mut self.data);
        applied_forces(model, &mut self.data, t);
        inertia_forces(model, &mut self.data, &self.zero_v);
        for k in 0..nv {
            self.rhs[k] = self.data.applied[k] - self.data.inertia[k];
        }
        for (r, terms) in self.data.equations.iter().enumerate() {
            self.rhs[nv + r] = if self.active[r] { -terms.accel_bias } else { 0.0 };
        }
        self.evaluations += 1;
        self.kkt.solve_in_place(&mut self.rhs).map_err(|_| SINGULAR)?;
        dy[nq..].copy_from_slice(&self.rhs[..nv]);
        velocity_map(model, q, v, &mut dy[..nq]);
        if dy.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(NOT_FINITE)
        }
    }

    /// Largest `|Φ|` over the active rows (after the constraint stage).
    fn position_residual(&self) -> f64 {
        self.data.equations.iter().zip(&self.active).filter(|(_, a)| **a).fold(0.0, |m, (e, _)| m.max(e.phi.abs()))
    }

    /// Solves `[M Bᵀ; B 0] [δv; z] = [0; r]` with the current factors, `r` over the constraint rows
    /// (zero on the inactive ones) from `row_value`; `δv` is left in `rhs[..nv]`.
    fn min_norm_correction(&mut self, row_value: impl Fn(&Data, usize) -> f64) -> Result<(), EvaluationFailure> {
        let nv = self.nv;
        self.rhs[..nv].fill(0.0);
        for r in 0..self.active.len() {
            self.rhs[nv + r] = if self.active[r] { row_value(&self.data, r) } else { 0.0 };
        }
        self.kkt.solve_in_place(&mut self.rhs).map_err(|_| SINGULAR)
    }

    /// Newton on `Φ(q, t) = 0` by minimum-norm (mass metric) corrections; `v` only feeds the kinematics.
    fn project_positions(&mut self, t: f64, q: &mut [f64], v: &[f64]) -> Result<(), EvaluationFailure> {
        let model = self.model;
        let mut previous = f64::INFINITY;
        let mut fresh = false;
        for it in 0..PROJECTION_ITERATIONS {
            kinematics(model, &mut self.data, q, v);
            constraint_equations(model, &mut self.data, t);
            let residual = self.position_residual();
            if it == 0 {
                self.drift.max_position_residual = self.drift.max_position_residual.max(residual);
            }
            if residual <= RESIDUAL_TOLERANCE * self.atol {
                return Ok(());
            }
            if !residual.is_finite() || (fresh && residual > 0.5 * previous) {
                return Err(NO_CONVERGENCE);
            }
            // The predictor's factors serve while the iteration contracts fast; else refactor here.
            if !self.factored || (it > 0 && residual > 0.1 * previous) {
                self.factor()?;
                self.drift.refactorizations += 1;
                fresh = true;
            }
            previous = residual;
            self.min_norm_correction(|data, r| -data.equations[r].phi)?;
            self.drift.newton_iterations += 1;
            let size = apply_correction(model, q, &self.rhs[..self.nv], self.rtol, self.atol);
            if size <= CORRECTION_TOLERANCE {
                return Ok(());
            }
        }
        Err(NO_CONVERGENCE)
    }
}

impl OdeSystem for MechanismOde<'_> {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let (q, v) = y.split_at(self.nq);
        kinematics(self.model, &mut self.data, q, v);
        constraint_equations(self.model, &mut self.data, t);
        self.factor()?;
        self.accelerations(t, q, v, dy)
    }

    fn accept(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let model = self.model;
        self.y_before.copy_from_slice(y);
        let (q, v) = y.split_at_mut(self.nq);
        let normalization = normalize_euler_parameters(model, q);
        self.drift.max_normalization_error = self.drift.max_normalization_error.max(normalization);
        self.project_positions(t, q, v)?;
        // Velocities at the projected positions, with factors made there (used for v̇ too).
        kinematics(model, &mut self.data, q, v);
        constraint_equations(model, &mut self.data, t);
        self.factor()?;
        let mut velocity_residual = 0.0_f64;
        for (r, terms) in self.data.equations.iter().enumerate() {
            if self.active[r] {
                let joint = &model.joints[model.layout.equations[r].0 .0];
                let rate = terms.rate(&self.data.markers[joint.marker_i.0], &self.data.markers[joint.marker_j.0]);
                velocity_residual = velocity_residual.max(rate.abs());
            }
        }
        self.drift.max_velocity_residual = self.drift.max_velocity_residual.max(velocity_residual);
        self.min_norm_correction(|data, r| {
            let joint = &model.joints[model.layout.equations[r].0 .0];
            -data.equations[r].rate(&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0])
        })?;
        for k in 0..self.nv {
            v[k] += self.rhs[k];
        }
        kinematics(model, &mut self.data, q, v);
        constraint_equations(model, &mut self.data, t);
        self.accelerations(t, q, v, dy)?;
        update_angle_references(model, &mut self.data);
        // The size of the projection's change in the units of the error test.
        let (rtol, atol) = (self.rtol, self.atol);
        let sum: f64 =
            self.y_before.iter().zip(y.iter()).map(|(b, a)| ((a - b) / (atol + rtol * b.abs())).powi(2)).sum();
        let weighted = (sum / y.len().max(1) as f64).sqrt();
        let d = &mut self.drift;
        d.projections += 1;
        d.max_weighted_correction = d.max_weighted_correction.max(weighted);
        d.sum_squared_weighted_correction += weighted * weighted;
        Ok(())
    }
}

/// `q̇ = T(q) v`: `Ṙ`, `ṗ = ½ Gᵀ(p) ω̄`, `ȧ` per body.
fn velocity_map(model: &Model, q: &[f64], v: &[f64], qdot: &mut [f64]) {
    let l = &model.layout;
    for b in 0..model.bodies.len() {
        let (qo, vo, m) = (l.q_offset[b], l.v_offset[b], l.modes[b]);
        qdot[qo..qo + 3].copy_from_slice(&v[vo..vo + 3]);
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        let w = Vec3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
        let p_rate = 0.5 * g_matrix(&p).transpose() * w;
        qdot[qo + 3..qo + 7].copy_from_slice(p_rate.as_slice());
        qdot[qo + 7..qo + 7 + m].copy_from_slice(&v[vo + 6..vo + 6 + m]);
    }
}

/// Rescales every body's Euler parameters to unit norm; returns the largest `|pᵀp − 1|` found.
fn normalize_euler_parameters(model: &Model, q: &mut [f64]) -> f64 {
    let mut worst = 0.0_f64;
    for b in 0..model.bodies.len() {
        let qo = model.layout.q_offset[b];
        let norm2: f64 = (3..7).map(|k| q[qo + k].powi(2)).sum();
        worst = worst.max((norm2 - 1.0).abs());
        let norm = norm2.sqrt();
        q[qo + 3..qo + 7].iter_mut().for_each(|x| *x /= norm);
    }
    worst
}

/// `q ← q ⊕ T(q) δv` with the Euler parameters rescaled; returns the RMS of the change weighted by
/// `atol + rtol |q|`.
fn apply_correction(model: &Model, q: &mut [f64], dv: &[f64], rtol: f64, atol: f64) -> f64 {
    let l = &model.layout;
    let mut sum = 0.0;
    let mut add = |x: &mut f64, d: f64| {
        sum += (d / (atol + rtol * x.abs())).powi(2);
        *x += d;
    };
    for b in 0..model.bodies.len() {
        let (qo, vo, m) = (l.q_offset[b], l.v_offset[b], l.modes[b]);
        let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
        let dw = Vec3::new(dv[vo + 3], dv[vo + 4], dv[vo + 5]);
        let dp = 0.5 * g_matrix(&p).transpose() * dw;
        for k in 0..3 {
            add(&mut q[qo + k], dv[vo + k]);
        }
        for k in 0..4 {
            add(&mut q[qo + 3 + k], dp[k]);
        }
        for k in 0..m {
            add(&mut q[qo + 7 + k], dv[vo + 6 + k]);
        }
    }
    normalize_euler_parameters(model, q);
    (sum / l.nq.max(1) as f64).sqrt()
}

/// The Adams method on a model: [`AdamsStepper`] on `y = [q, v]` with the projections of
/// [`MechanismOde`]; one [`step`](Self::step) is one accepted step.
pub struct Adams<'m> {
    system: MechanismOde<'m>,
    stepper: AdamsStepper,
    max_steps: usize,
    stats: Stats,
    y_interp: Vec<f64>,
    yp_interp: Vec<f64>,
}

impl<'m> Adams<'m> {
    /// Starts from a consistent state (assembled, velocity-analysed) and its accelerations, with the
    /// tolerances and step limits of `tolerances` (its `max_order` is the BDF's and is ignored) and the
    /// order limit of `config`.
    pub fn new(
        model: &'m Model,
        state: &State,
        accelerations: &Accelerations,
        tolerances: BdfConfig,
        config: AdamsConfig,
    ) -> Result<Self, IntegrationError> {
        let (nq, nv) = (model.layout.nq, model.layout.nv);
        let mut y0 = vec![0.0; nq + nv];
        let mut yp0 = vec![0.0; nq + nv];
        y0[..nq].copy_from_slice(&state.q);
        y0[nq..].copy_from_slice(&state.v);
        yp0[nq..].copy_from_slice(&accelerations.vdot);
        velocity_map(model, &state.q, &state.v, &mut yp0[..nq]);
        if !y0.iter().chain(&yp0).all(|x| x.is_finite()) {
            return Err(IntegrationError::InitialConditions {
                t: state.t,
                reason: "initial positions, velocities or accelerations are not finite".into(),
            });
        }
        let mut system = MechanismOde::new(model, state.active.clone(), tolerances.rtol, tolerances.atol);
        // Joint angles continue from the initial configuration.
        kinematics(model, &mut system.data, &state.q, &state.v);
        system.data.angle_reference.fill(0.0);
        update_angle_references(model, &mut system.data);
        let control = StepControl {
            rtol: tolerances.rtol,
            atol: tolerances.atol,
            max_order: config.max_order,
            h_max: tolerances.h_max,
            h_init: tolerances.h_init,
        };
        let stepper = AdamsStepper::new(control, state.t, &y0, &yp0);
        Ok(Self {
            system,
            stepper,
            max_steps: tolerances.max_steps,
            stats: Stats::default(),
            y_interp: vec![0.0; nq + nv],
            yp_interp: vec![0.0; nq + nv],
        })
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.stepper.t()
    }
    /// Current `y = [q, v]`.
    pub fn y(&self) -> &[f64] {
        self.stepper.y()
    }
    /// The stepper (order, step size, its own counters).
    pub fn stepper(&self) -> &AdamsStepper {
        &self.stepper
    }
    /// How far the solution strayed from the constraints and how much the projections moved it.
    pub fn drift(&self) -> &ProjectionDrift {
        &self.system.drift
    }
    /// The statistics so far.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// Takes one accepted step, not passing `t_stop`.
    pub fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError> {
        if self.stats.steps >= self.max_steps {
            return Err(IntegrationError::TooManySteps { t: self.t(), max_steps: self.max_steps });
        }
        let result = self.stepper.step(&mut self.system, t_stop);
        self.update_stats();
        result.map_err(|f| self.describe(f))
    }

    fn update_stats(&mut self) {
        let st = &self.stepper.stats;
        let s = &mut self.stats;
        s.steps = st.steps;
        s.error_test_failures = st.error_test_failures;
        s.newton_failures = st.evaluation_failures;
        s.newton_iterations = self.system.drift.newton_iterations;
        s.residual_evaluations = self.system.evaluations;
        s.factorizations = self.system.factorizations;
        s.order_counts = st.order_counts;
        s.sum_h_squared = st.sum_h_squared;
    }

    /// The error of a failed step, named for a person (allocates; only on failure).
    fn describe(&mut self, failure: StepFailure) -> IntegrationError {
        match failure {
            StepFailure::StepSizeTooSmall { t, h, last } => {
                let reason = match last {
                    None => "the step size fell below the time resolution".to_string(),
                    Some(AttemptFailure::ErrorTest { error }) => {
                        format!("the local error test fails (weighted error {error:.2e})")
                    }
                    Some(AttemptFailure::Evaluation(e)) | Some(AttemptFailure::Acceptance(e)) => {
                        format!("{}{}", e.0, self.dependent_constraints(t))
                    }
                };
                IntegrationError::StepSizeTooSmall { t, h, reason }
            }
            StepFailure::ToleranceTooSmall { t, factor } => IntegrationError::StepSizeTooSmall {
                t,
                h: self.stepper.step_size(),
                reason: format!(
                    "rtol and atol are below what double precision resolves at this state; multiply them by at \
                     least {factor:.1}"
                ),
            },
            StepFailure::Start(e) => IntegrationError::InitialConditions { t: self.t(), reason: e.0.to_string() },
        }
    }

    /// Constraints that have become dependent at the current positions, if any (a lock or a singular
    /// position explains a singular matrix).
    fn dependent_constraints(&mut self, t: f64) -> String {
        let q = self.stepper.y()[..self.system.nq].to_vec();
        let (dependent, _) = find_redundant_rows(self.system.model, &mut self.system.data, t, &q);
        let newly: Vec<String> =
            dependent.iter().filter(|r| self.system.active[r.row]).map(|r| r.description.clone()).collect();
        if newly.is_empty() {
            String::new()
        } else {
            format!(
                "; the constraints have become dependent here (the mechanism locks or reaches a singular position): {}",
                newly.join("; ")
            )
        }
    }
}

impl Integrator for Adams<'_> {
    fn t(&self) -> f64 {
        self.stepper.t()
    }
    fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError> {
        Adams::step(self, t_stop)
    }
    fn state(&self) -> (&[f64], &[f64]) {
        self.stepper.y().split_at(self.system.nq)
    }
    fn interpolate(&mut self, t: f64, q: &mut [f64], v: &mut [f64]) {
        self.stepper.interpolate(t, &mut self.y_interp, &mut self.yp_interp);
        let nq = self.system.nq;
        q.copy_from_slice(&self.y_interp[..nq]);
        v.copy_from_slice(&self.y_interp[nq..]);
    }
    fn stats(&self) -> &Stats {
        &self.stats
    }
    fn data_mut(&mut self) -> &mut Data {
        &mut self.system.data
    }
    fn active(&self) -> &[bool] {
        &self.system.active
    }
    fn name(&self) -> &'static str {
        "adams"
    }
}
