//! The Adams method applied to a model: [`Adams`], an [`Integrator`], with the constraints handled
//! in one of two ways ([`ConstraintHandling`](super::ConstraintHandling)):
//!
//! - **projection** (default, [`super::projection`]): the full state `y = [q, v]` with `v̇` from the
//!   index-1 system, positions and velocities projected onto the constraints after every accepted step;
//! - **generalized coordinate partitioning** (DADS, [`super::partitioning`]): the independent
//!   coordinates and their rates only, the dependent ones recovered by Newton in every evaluation, the
//!   partition re-chosen (and the integration restarted) when it degrades.
//!
//! Why projection is the default — measured at tol 1e-7 (`tests/adams.rs`,
//! `partitioning_against_projection`; both within 6e-7 m of a tight BDF reference, both keep the
//! constraints to round-off or 1 % of `atol`):
//!
//! ```text
//!                            projection                    partitioning
//!                            steps  factorizations         steps  factorizations  repartitions
//! free slider-crank, 2 s       416      847                  441     1994              0
//! heavy top (200 rad/s), 1 s   846     1694                 3703    15787            195
//! flexible pendulum, 0.5 s    2505     5202                 2550    10656              0
//! ```
//!
//! Where the partition holds, the two take about the same steps, but partitioning pays a Newton solve
//! and a factorization of `Φ̂_u` inside *every* evaluation (two per step), where projection pays a few
//! solves with factors it already has, once per step: about twice the factorizations and 1.3–1.7 times
//! the wall time. Where it does not hold, it is far worse: the spinning top's independent coordinates
//! are Euler parameters, which reach an extremum every quarter turn, so the partition degrades and is
//! re-chosen every few steps, and each repartition restarts the multistep history at order 1 (4.4×
//! the steps, about 6× the time). Partitioning also tests the error of the independent coordinates
//! only. Projection keeps the whole state under error control, never restarts, and its inconsistency
//! with the difference table is a small fraction of the tolerance (see [`ProjectionDrift`]).

use crate::analysis::{Accelerations, State};
use crate::data::Data;
use std::sync::Arc;

use crate::integrate::{
    check_len, AdamsCheckpoint, CheckpointError, IntegrationError, Integrator, IntegratorCheckpoint, Stats, Tolerances,
};
use crate::integrate::singular_position::SingularPassage;
use crate::model::Model;
use crate::stage::{kinematics, update_angle_references};

use crate::stage::position_rates;
use super::method::{AdamsStepper, AttemptFailure, EvaluationFailure, OdeSystem, StepControl, StepFailure};
use super::partitioning::{PartitionReport, PartitionedMechanism};
use super::projection::{ProjectedMechanism, ProjectionDrift};
use super::{AdamsConfig, ConstraintHandling};

/// The mechanism as an ODE, either way.
enum System {
    Projection(Box<ProjectedMechanism>),
    Partitioning(Box<PartitionedMechanism>),
}

impl OdeSystem for System {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        match self {
            System::Projection(s) => s.rhs(t, y, dy),
            System::Partitioning(s) => s.rhs(t, y, dy),
        }
    }
    fn accept(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        match self {
            System::Projection(s) => s.accept(t, y, dy),
            System::Partitioning(s) => s.accept(t, y, dy),
        }
    }
}

impl System {
    fn model(&self) -> &Arc<Model> {
        match self {
            System::Projection(s) => &s.model,
            System::Partitioning(s) => &s.model,
        }
    }
    fn data(&mut self) -> &mut Data {
        match self {
            System::Projection(s) => &mut s.data,
            System::Partitioning(s) => &mut s.data,
        }
    }
    fn active(&self) -> &[bool] {
        match self {
            System::Projection(s) => &s.kkt.active,
            System::Partitioning(s) => &s.kkt.active,
        }
    }
}

/// From this amplification of the rounding at an attempt's end on (the condition number `κ` there, where
/// its rounding matters to the step), the Adams method evaluates `f` at its prediction projected onto the
/// constraints, and passes an error estimate within the rounding of the estimate itself
/// ([`AdamsStepper`]'s `estimate_rounding`). Off the constraints the index-1 accelerations are
/// ill-conditioned near a singular position: a prediction that misses the constraints by its own
/// truncation error `δ` gets accelerations off by about `κ δ` in the direction the constraints lose, and
/// the estimate, `h (g_k − g_{k+1}) ‖f^p − φ^p_1‖`, measures them rather than the error of the projected
/// solution. On the double four-bar over its run at rtol 1e-9 (A02, 10 s) the estimates grew so from
/// κ ≈ 300 on, every step failed and was halved, its end placed half a step before the predicted position,
/// and the ends crept onto it (t = 1.228159 s, κ infinite at the last end, the step 4e-16 s). Below this
/// level the runs are those of the unprojected prediction: the 3-D slider-crank (κ = 25) and Andrews'
/// squeezer (κ ≈ 150 to 200) at rtol 1e-12 are bit-identical; with the projection from the first
/// amplified step on, both changed (3,199 and 608 steps against 3,236 and 635).
const PROJECTED_PREDICTION_FROM: f64 = 1000.0;

/// The mechanism with the guard of its singular positions, for one call of [`AdamsStepper::step`]: the
/// attempts' ends are kept off a predicted singular position ([`SingularPassage`]), and from
/// [`PROJECTED_PREDICTION_FROM`] on the prediction is projected onto the constraints.
struct Guarded<'a> {
    system: &'a mut System,
    singular: &'a mut SingularPassage,
    t_stop: f64,
    rtol: f64,
    /// The amplification and share of the tolerance of the last attempt.
    amplification: f64,
    share: f64,
    /// The start and end of the last attempt if it crosses a predicted singular position.
    crossing: Option<(f64, f64)>,
}

impl OdeSystem for Guarded<'_> {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        self.system.rhs(t, y, dy)
    }
    fn accept(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        if let System::Projection(s) = &mut *self.system {
            s.near_singular_position = self.singular.near();
        }
        self.system.accept(t, y, dy)
    }
    fn predicted(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        match &mut *self.system {
            System::Projection(s) if self.amplification >= PROJECTED_PREDICTION_FROM => s.predicted(t, y, dy),
            _ => self.system.rhs(t, y, dy),
        }
    }
    fn rounding_amplification(&self) -> f64 {
        if self.amplification >= PROJECTED_PREDICTION_FROM {
            self.amplification
        } else {
            1.0
        }
    }
    /// A step across a predicted position ([`SingularPassage::crossing_in_one_step`]) is as long as the
    /// distance to the position asks, not the error control: its estimate passes within the rounding
    /// amplified by the `κ` at its ends, as the BDF's estimates near a position do.
    fn crossing_within_rounding(&self, error: f64, k: usize) -> bool {
        self.crossing.is_some_and(|(t, end)| self.singular.crossing_within_rounding(error, t, end, self.share, k))
    }
    fn placed_end(&mut self, t: f64, t_new: f64, share: f64) -> Option<f64> {
        // The amplified rounding at the asked end is recorded (the steps held near a position are
        // counted) but does not pass estimates as rounding, as the BDF's guard does: with the BDF's
        // allowance for a predictor of order `k` (`MARGIN · 2^(k+1)/(k+1) · 10 ε κ`, 630 times the
        // rounding at order 12) the Adams method passed truncation errors at ordinary conditioning: the
        // 3-D slider-crank (κ = 25) at rtol 1e-12 took 3,000 steps and was 4.9e-5 rad/s off in the
        // crank's rate, Andrews' squeezer (κ ≈ 191) 491 steps and 3e-6 off, where without it they take
        // 3,236 and 635 steps and agree with the BDF at 1e-10. The Adams estimate's own rounding (of the
        // extrapolated differences of `f`, times the step: `estimate_rounding`) is far smaller than the
        // BDF's; it passes estimates from `PROJECTED_PREDICTION_FROM` on.
        let amplification = self.singular.amplification(t, t_new, share);
        self.amplification =
            if SingularPassage::rounding_matters(amplification, self.rtol, share) { amplification } else { 1.0 };
        self.share = share;
        let placed = self.singular.placed_end(t, t_new, share);
        self.crossing = placed.filter(|&end| self.singular.crossing(t) && end < self.t_stop).map(|end| (t, end));
        match placed {
            Some(end) if end < self.t_stop => Some(end),
            _ => {
                self.singular.asked = None;
                None
            }
        }
    }
}

/// The Adams method on a model; one [`step`](Self::step) is one accepted step.
pub struct Adams {
    system: System,
    /// The approach to a singular position: its predicted window, which the step ends avoid.
    singular: SingularPassage,
    rtol: f64,
    stepper: AdamsStepper,
    max_steps: usize,
    stats: Stats,
    y_interp: Vec<f64>,
    yp_interp: Vec<f64>,
}

impl Adams {
    /// Starts from a consistent state (assembled, velocity-analysed) and its accelerations, with the
    /// tolerances and step limits of `tolerances` and the
    /// order limit and constraint handling of `config`.
    pub fn new(
        model: Arc<Model>,
        state: &State,
        accelerations: &Accelerations,
        tolerances: Tolerances,
        config: AdamsConfig,
    ) -> Result<Self, IntegrationError> {
        crate::integrate::check_start(&model, state, accelerations)?;
        let (nq, nv) = (model.layout.nq, model.layout.nv);
        if !state.q.iter().chain(&state.v).chain(&accelerations.vdot).all(|x| x.is_finite()) {
            return Err(IntegrationError::InitialConditions {
                t: state.t,
                reason: "initial positions, velocities or accelerations are not finite".into(),
            });
        }
        if !(tolerances.atol > 0.0 && tolerances.rtol >= 0.0) {
            return Err(IntegrationError::InitialConditions {
                t: state.t,
                reason: format!(
                    "the Adams method needs atol > 0 and rtol ≥ 0, got atol {} and rtol {}",
                    tolerances.atol, tolerances.rtol
                ),
            });
        }
        let tolerances = tolerances.attainable().0;
        let control = StepControl {
            rtol: tolerances.rtol,
            atol: tolerances.atol,
            span: tolerances.span.seconds(),
            max_order: config.max_order,
            h_max: tolerances.h_max,
            h_init: tolerances.h_init,
        };
        let active = state.active.clone();
        let (mut system, y0, yp0) = match config.constraints {
            ConstraintHandling::Projection => {
                let system = ProjectedMechanism::new(Arc::clone(&model), active, tolerances.rtol, tolerances.atol);
                let mut y0 = vec![0.0; nq + nv];
                let mut yp0 = vec![0.0; nq + nv];
                y0[..nq].copy_from_slice(&state.q);
                y0[nq..].copy_from_slice(&state.v);
                yp0[nq..].copy_from_slice(&accelerations.vdot);
                position_rates(&model, &state.q, &state.v, &mut yp0[..nq]);
                (System::Projection(Box::new(system)), y0, yp0)
            }
            ConstraintHandling::Partitioning => {
                let initial = |e: EvaluationFailure| IntegrationError::InitialConditions {
                    t: state.t,
                    reason: format!("no partition of the coordinates: {}", e.0),
                };
                let mut system = PartitionedMechanism::new(
                    Arc::clone(&model),
                    active,
                    tolerances.rtol,
                    tolerances.atol,
                    state.t,
                    &state.q,
                    &state.v,
                )
                .map_err(initial)?;
                let mut y0 = vec![0.0; system.len()];
                let mut yp0 = vec![0.0; system.len()];
                system.accepted_y(&mut y0);
                system.rhs(state.t, &y0, &mut yp0).map_err(initial)?;
                (System::Partitioning(Box::new(system)), y0, yp0)
            }
        };
        // Joint angles continue from the initial configuration.
        let data = system.data();
        kinematics(&model, data, &state.q, &state.v);
        data.angle_reference.fill(0.0);
        update_angle_references(&model, data);
        let stepper = AdamsStepper::new(control, state.t, &y0, &yp0);
        let n = y0.len();
        let singular = SingularPassage::new(&model, &state.active, tolerances.rtol).crossing_in_one_step();
        let mut adams = Self {
            system,
            singular,
            rtol: tolerances.rtol,
            stepper,
            max_steps: tolerances.max_steps,
            stats: Stats::default(),
            y_interp: vec![0.0; n],
            yp_interp: vec![0.0; n],
        };
        adams.update_stats();
        Ok(adams)
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.stepper.t()
    }
    /// The integrated variables: `[q, v]` with projection, `[w, ẇ]` with partitioning.
    pub fn y(&self) -> &[f64] {
        self.stepper.y()
    }
    /// The stepper (order, step size, its own counters).
    pub fn stepper(&self) -> &AdamsStepper {
        &self.stepper
    }
    /// With projection: how far the solution strayed from the constraints and how much the projections
    /// moved it.
    pub fn drift(&self) -> Option<&ProjectionDrift> {
        match &self.system {
            System::Projection(s) => Some(&s.drift),
            System::Partitioning(_) => None,
        }
    }
    /// With partitioning: the independent coordinates, repartitions, Newton iterations.
    pub fn partition(&self) -> Option<&PartitionReport> {
        match &self.system {
            System::Projection(_) => None,
            System::Partitioning(s) => Some(&s.state.report),
        }
    }
    /// The complete state between two steps.
    pub fn checkpoint(&self) -> AdamsCheckpoint {
        let (drift, partition, evaluations, kkt, data) = match &self.system {
            System::Projection(s) => (s.drift, None, s.evaluations, &s.kkt, &s.data),
            System::Partitioning(s) => (ProjectionDrift::default(), Some(s.checkpoint()), s.evaluations, &s.kkt, &s.data),
        };
        AdamsCheckpoint {
            stepper: self.stepper.clone(),
            drift,
            partition,
            evaluations,
            factorizations: kkt.factorizations,
            active: kkt.active.clone(),
            angle_reference: data.angle_reference.clone(),
            stats: self.stats,
        }
    }

    /// Continues from `c`, taken of an Adams integrator on the same model with the same settings.
    pub fn restore(&mut self, c: &AdamsCheckpoint) -> Result<(), CheckpointError> {
        if matches!(self.system, System::Partitioning(_)) != c.partition.is_some() {
            return Err(CheckpointError::Unsupported(
                "the checkpoint's constraint handling (projection or partitioning) differs from the simulation's".into(),
            ));
        }
        check_len("the integrated variables", self.stepper.y().len(), c.stepper.y().len())?;
        let (evaluations, kkt, data) = match (&mut self.system, &c.partition) {
            (System::Projection(s), None) => {
                s.drift = c.drift;
                (&mut s.evaluations, &mut s.kkt, &mut s.data)
            }
            (System::Partitioning(s), Some(partition)) => {
                s.restore(partition)?;
                (&mut s.evaluations, &mut s.kkt, &mut s.data)
            }
            _ => unreachable!("the constraint handling was compared above"),
        };
        check_len("the constraint rows in force", kkt.active.len(), c.active.len())?;
        check_len("the joint angles", data.angle_reference.len(), c.angle_reference.len())?;
        *evaluations = c.evaluations;
        kkt.factorizations = c.factorizations;
        kkt.active.copy_from_slice(&c.active);
        data.angle_reference.copy_from_slice(&c.angle_reference);
        self.stepper = c.stepper.clone();
        self.stats = c.stats;
        Ok(())
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
        // Partitioning: a partition found degraded during the last step is replaced now, not right
        // after that step, so that the outputs within it still come from its interpolant.
        self.repartition_if_needed()?;
        let mut result = self.guarded_step(t_stop);
        // A step that failed on a degraded partition is retried once with a new one.
        if result.is_err() && self.repartition_if_needed()? {
            result = self.guarded_step(t_stop);
        }
        self.update_stats();
        result.map_err(|f| self.describe(f))
    }

    /// One accepted step of the stepper with the guard of singular positions; after it, the conditioning
    /// at its end measured and the passages counted.
    fn guarded_step(&mut self, t_stop: f64) -> Result<(), StepFailure> {
        let steps = self.stepper.stats.steps;
        let mut guarded =
            Guarded { system: &mut self.system, singular: &mut self.singular, t_stop, rtol: self.rtol, amplification: 1.0, share: 1.0, crossing: None };
        self.stepper.step(&mut guarded, t_stop)?;
        let (amplification, share) = (guarded.amplification, guarded.share);
        if self.stepper.stats.steps == steps {
            return Ok(());
        }
        if amplification > 1.0 {
            self.stats.held_near_singular_position(self.rtol * share);
        }
        if let Some(asked) = self.singular.asked.take() {
            // The step was moved off a singular position: the next one is the size the error control asked for.
            self.stepper.set_step_size(asked);
        }
        let t = self.stepper.t();
        let model = Arc::clone(self.system.model());
        if let Some(condition) = self.singular.accepted(&model, self.system.data(), t) {
            self.stats.singular_position_steps += 1;
            self.stats.singular_position_condition = self.stats.singular_position_condition.max(condition);
        }
        self.stats.singular_positions = self.singular.passages;
        Ok(())
    }

    /// With partitioning, when the partition has degraded: a new one at the last accepted state and a
    /// restart of the stepper there. Returns whether it repartitioned.
    fn repartition_if_needed(&mut self) -> Result<bool, IntegrationError> {
        let System::Partitioning(s) = &mut self.system else { return Ok(false) };
        if !s.state.needs_repartition {
            return Ok(false);
        }
        let t = self.stepper.t();
        let fail = |e: EvaluationFailure| IntegrationError::StepSizeTooSmall {
            t,
            h: 0.0,
            reason: format!("no new partition of the coordinates: {}", e.0),
        };
        s.choose_partition().map_err(fail)?;
        s.accepted_y(&mut self.y_interp);
        s.rhs(t, &self.y_interp, &mut self.yp_interp).map_err(fail)?;
        s.state.needs_repartition = false;
        self.stepper.restart(t, &self.y_interp, &self.yp_interp);
        Ok(true)
    }

    fn update_stats(&mut self) {
        let st = &self.stepper.stats;
        let s = &mut self.stats;
        s.steps = st.steps;
        s.error_test_failures = st.error_test_failures;
        s.newton_failures = st.evaluation_failures;
        s.order_counts = st.order_counts;
        s.sum_h_squared = st.sum_h_squared;
        match &self.system {
            System::Projection(p) => {
                s.newton_iterations = p.drift.newton_iterations;
                s.residual_evaluations = p.evaluations;
                s.factorizations = p.kkt.factorizations;
            }
            System::Partitioning(p) => {
                s.newton_iterations = p.state.report.newton_iterations;
                s.residual_evaluations = p.evaluations;
                s.factorizations = p.kkt.factorizations + p.state.report.factorizations;
            }
        }
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
        let q = Integrator::state(self).0.to_vec();
        let model = Arc::clone(self.system.model());
        let active = self.system.active().to_vec();
        crate::integrate::diagnosis::dependent_constraints(&model, self.system.data(), t, &q, &active)
    }
}

impl Integrator for Adams {
    fn checkpoint(&self) -> Result<IntegratorCheckpoint, CheckpointError> {
        Ok(IntegratorCheckpoint::Adams(Box::new(Adams::checkpoint(self))))
    }
    fn restore(&mut self, checkpoint: &IntegratorCheckpoint) -> Result<(), CheckpointError> {
        match checkpoint {
            IntegratorCheckpoint::Adams(c) => Adams::restore(self, c),
            other => Err(CheckpointError::Method { expected: "adams", found: other.method() }),
        }
    }
    fn t(&self) -> f64 {
        self.stepper.t()
    }
    fn step(&mut self, t_stop: f64) -> Result<(), IntegrationError> {
        Adams::step(self, t_stop)
    }
    fn state(&self) -> (&[f64], &[f64]) {
        match &self.system {
            System::Projection(s) => self.stepper.y().split_at(s.nq),
            System::Partitioning(s) => (&s.state.q_accepted, &s.state.v_accepted),
        }
    }
    fn interpolate(&mut self, t: f64, q: &mut [f64], v: &mut [f64]) {
        self.stepper.interpolate(t, &mut self.y_interp, &mut self.yp_interp);
        match &mut self.system {
            System::Projection(s) => {
                q.copy_from_slice(&self.y_interp[..s.nq]);
                v.copy_from_slice(&self.y_interp[s.nq..]);
                // Onto the constraints, as the accepted steps are; should the projection not converge,
                // the interpolated state (off by about the local error) is kept.
                if s.project_output(t, q, v).is_err() {
                    q.copy_from_slice(&self.y_interp[..s.nq]);
                    v.copy_from_slice(&self.y_interp[s.nq..]);
                }
            }
            System::Partitioning(s) => s.positions_and_velocities(t, &self.y_interp, q, v),
        }
    }
    fn stats(&self) -> &Stats {
        &self.stats
    }
    fn data_mut(&mut self) -> &mut Data {
        self.system.data()
    }
    fn active(&self) -> &[bool] {
        self.system.active()
    }
    fn name(&self) -> &'static str {
        "adams"
    }
}
