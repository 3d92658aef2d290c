//! Dynamic simulation: assembly, velocity analysis, initial accelerations, then integrator steps with
//! results at the requested output times taken from the method's interpolant.
//!
//! A [`Simulation`] owns everything a run needs (the shared model, the integrator with its history,
//! the watchdog, the report), so a caller can hold it, step it, read its state, save it as a
//! [`SimulationCheckpoint`] and resume it later. [`simulate`] and [`simulate_interruptible`] run one
//! to its end.

mod checkpoint;
mod divergence;
mod global_error;
mod global_error_control;
mod output;
mod report;
mod set_state;
mod settings;
mod shadow;

use std::sync::Arc;
use std::time::Instant;

pub use checkpoint::{SimulationCheckpoint, CHECKPOINT_VERSION};
pub use global_error::{GlobalErrorEstimate, GlobalErrorNorm};
pub use global_error_control::{global_error_rerun, run_under_global_error_control, ControlledRun, GlobalErrorControl, MAX_RERUNS};
pub use output::{OutputFrame, OutputSink, OutputTable};
pub use report::{Interruption, SimulationError, SimulationFailure, SimulationReport, WorkAtStep};
pub use set_state::StateProjection;
pub use settings::{SimulationSettings, Start};

use super::outputs::{constraint_residuals, evaluate_outputs, output_columns};
use super::watchdog::{SimulationWarning, WarningKind, Watchdog};
use super::{assemble, linearize_at, static_equilibrium, velocity_analysis, AccelerationSolver, Accelerations, Linearization, State};
use crate::analysis::EquilibriumSettings;
use crate::data::Data;
use crate::integrate::Adams;
use crate::integrate::passed_rounding::passed_warning;
use crate::integrate::share_floor::floor_warning;
use crate::integrate::{Bdf, Integrator, Method};
use crate::integrate::GeneralizedAlpha;
use crate::model::{BodyId, Model};
use crate::stage::{energy, run_kinematic_stages, measures, nonconservative_power};

/// A dynamic simulation that owns its state: built from a shared model and settings, advanced step by
/// step or to a time, its outputs streamed to any [`OutputSink`] at the output times
/// `k · output_step` (and at the end time), its state and report readable between steps, and its
/// complete state saved and resumed ([`checkpoint`](Self::checkpoint), [`resume`](Self::resume)).
///
/// The steps are never shortened to land on a time asked for: [`advance_to`](Self::advance_to)
/// stops at the first step at or after it, so that pausing, reading, checkpointing and continuing
/// leaves the step sequence of an uninterrupted run (the outputs in between come from the
/// interpolant).
///
/// ```
/// use std::sync::Arc;
/// use flexmb::analysis::{OutputTable, Simulation, SimulationSettings};
/// use flexmb::body::{InitialState, Marker, RigidBody};
/// use flexmb::joint::{Joint, JointKind};
/// use flexmb::math::{Mat3, Vec3};
/// use flexmb::model::{BodyRef, ModelBuilder, OutputKind};
///
/// // A pendulum of 1 kg on a 1 m rod, pivoted at the origin about z, released horizontal.
/// let mut b = ModelBuilder::new("pendulum").gravity(Vec3::new(0.0, -9.81, 0.0));
/// let initial = InitialState { position: Vec3::new(1.0, 0.0, 0.0), ..Default::default() };
/// let inertia = Mat3::identity() * 1e-3;
/// let bob = b.add_body(RigidBody { name: "bob".into(), mass: 1.0, center_of_mass: Vec3::zeros(), inertia, initial }).unwrap();
/// let marker = |name: &str, body, origin| Marker { name: name.into(), body, origin, axes: Mat3::identity() };
/// let pivot = b.add_marker(marker("pivot", BodyRef::Ground, Vec3::zeros())).unwrap();
/// let hinge = b.add_marker(marker("hinge", BodyRef::Body(bob), Vec3::new(-1.0, 0.0, 0.0))).unwrap();
/// let center = b.add_marker(marker("center", BodyRef::Body(bob), Vec3::zeros())).unwrap();
/// b.add_joint(Joint { name: "pin".into(), kind: JointKind::Revolute, marker_i: pivot, marker_j: hinge }).unwrap();
/// b.add_output("bob", OutputKind::MarkerPosition(center)).unwrap();
/// let model = Arc::new(b.build().unwrap());
///
/// let settings = SimulationSettings { t_end: 0.5, output_step: 0.1, ..Default::default() };
/// let mut simulation = Simulation::new(model.clone(), settings).unwrap();
/// let mut table = OutputTable::new(&model);
/// simulation.advance_to(0.25, &mut table).unwrap(); // pause at the first step at or after 0.25 s
/// assert!(simulation.time() >= 0.25 && table.len() == 3);
/// let checkpoint = simulation.checkpoint().unwrap(); // serializable (serde), to resume later
/// simulation.advance_to(0.5, &mut table).unwrap();
/// assert!(simulation.is_finished() && table.len() == 6);
/// // The rod keeps its length.
/// let (x, y) = (table.column("bob.x").unwrap(), table.column("bob.y").unwrap());
/// assert!(x.iter().zip(&y).all(|(x, y)| (x.hypot(*y) - 1.0).abs() < 1e-6));
/// # let mut resumed = Simulation::resume(model.clone(), settings, &checkpoint).unwrap();
/// # let mut rest = OutputTable::new(&model);
/// # resumed.advance_to(0.5, &mut rest).unwrap();
/// # assert_eq!(rest.len(), 3);
/// ```
pub struct Simulation {
    model: Arc<Model>,
    settings: SimulationSettings,
    integrator: Box<dyn Integrator>,
    accelerations: AccelerationSolver,
    watchdog: Watchdog,
    report: SimulationReport,
    /// The constraint rows in force (they do not change during a run; copied once so that no step
    /// allocates).
    active: Vec<bool>,
    /// Index of the next output time on the grid (0: the initial state, not yet reported).
    next_output: usize,
    /// The output at an end time off the grid was reported.
    end_reported: bool,
    /// A step or an output failed: the simulation cannot continue.
    failed: bool,
    /// The current value of each parameter (also in the integrator's scratch data, where the stages
    /// read it).
    parameters: Vec<f64>,
    /// Output values, positions and velocities of the frame being reported.
    values: Vec<f64>,
    q: Vec<f64>,
    v: Vec<f64>,
    /// Whether a joint of the model depends on time (a driver, a distance of varying length) or a
    /// flexible body has interface geometric stiffness (whose power needs the multipliers and the force
    /// stage).
    power_needs_multipliers: bool,
    /// Whether the model has laws given as code, whose failures stop the run.
    has_user_laws: bool,
    /// The counters of the integrators [`set_state`](Self::set_state) replaced (added to the
    /// current integrator's in the report).
    restarted_stats: crate::integrate::Stats,
    /// The shadow run of [`SimulationSettings::divergence_check`], while it runs.
    divergence: Option<Box<divergence::DivergenceCheck>>,
    /// The shadow run of [`SimulationSettings::global_error_estimate`], while it runs.
    global_error: Option<Box<global_error::Reintegration>>,
}

impl Simulation {
    /// Assembles the model's initial state, makes its velocities consistent, solves the initial
    /// accelerations and starts the integrator of `settings.method`. The output at time 0 is reported
    /// by the first call of [`step`](Self::step) or [`advance_to`](Self::advance_to).
    pub fn new(model: Arc<Model>, settings: SimulationSettings) -> Result<Self, SimulationError> {
        let mut report = SimulationReport::default();
        model.clear_user_law_failures();
        match Self::start(Arc::clone(&model), settings, &mut report) {
            Ok(mut simulation) => {
                if simulation.settings.divergence_check {
                    simulation.divergence = divergence::DivergenceCheck::start(&simulation).map(Box::new);
                }
                if simulation.settings.global_error_estimate || simulation.settings.global_error_control.is_some() {
                    match global_error::Reintegration::start(&simulation) {
                        Ok(estimate) => simulation.global_error = Some(Box::new(estimate)),
                        Err(reason) => simulation.report.warnings.push(SimulationWarning {
                            t: 0.0,
                            kind: WarningKind::Tolerance,
                            message: format!("the global error is not estimated: {reason}"),
                        }),
                    }
                }
                Ok(simulation)
            }
            Err(cause) => Err(SimulationError { cause: user_law_failure(&model).unwrap_or(cause), report: Box::new(report) }),
        }
    }

    fn start(model: Arc<Model>, settings: SimulationSettings, report: &mut SimulationReport) -> Result<Self, SimulationFailure> {
        settings.validate().map_err(SimulationFailure::Invalid)?;
        let settings = attainable_tolerances(settings, &mut report.warnings);
        let mut data = Data::new(&model);
        let mut state = State::initial(&model);
        match settings.start {
            Start::Assembly => report.assembly = Some(assemble(&model, &mut data, &mut state, settings.assembly)?),
            Start::Equilibrium(equilibrium) => {
                let given = state.v.clone();
                let equilibrium = EquilibriumSettings { assembly: settings.assembly, ..equilibrium };
                let t0 = state.t;
                let found = static_equilibrium(&model, &mut data, &mut state, t0, &equilibrium)?;
                state.v = given;
                report.assembly = Some(found.assembly.clone());
                report.equilibrium = Some(Box::new(found));
            }
        }
        report.velocity = Some(velocity_analysis(&model, &mut data, &mut state)?);
        let mut accelerations = AccelerationSolver::new(&model);
        let acc = accelerations
            .solve_at(&model, &mut data, state.t, &state.q, &state.v, &state.active)
            .map_err(|_| accelerations_failure(&model, &data, state.t))?
            .clone();
        let integrator = start_integrator(&model, &settings, &state, &acc)?;
        report.method = integrator.name();
        Ok(Self::with_integrator(model, settings, integrator, accelerations, std::mem::take(report)))
    }

    fn with_integrator(
        model: Arc<Model>,
        settings: SimulationSettings,
        integrator: Box<dyn Integrator>,
        accelerations: AccelerationSolver,
        report: SimulationReport,
    ) -> Self {
        let watchdog = Watchdog::new(&model, settings.physics_limits, settings.tolerances.atol);
        let active = integrator.active().to_vec();
        let (nq, nv) = (model.layout.nq, model.layout.nv);
        Self {
            values: vec![0.0; output_columns(&model).len()],
            q: vec![0.0; nq],
            v: vec![0.0; nv],
            settings,
            integrator,
            accelerations,
            watchdog,
            report,
            active,
            next_output: 0,
            end_reported: false,
            failed: false,
            parameters: model.parameters.iter().map(|p| p.value).collect(),
            power_needs_multipliers: model.joints.iter().any(|j| j.kind.time_function().is_some_and(|f| f.depends_on_time()))
                || model.modal.iter().flatten().filter_map(|m| m.geometric_stiffness.as_ref()).any(|g| !g.interface.is_empty()),
            has_user_laws: !model.user_laws().is_empty(),
            restarted_stats: crate::integrate::Stats::default(),
            divergence: None,
            global_error: None,
            model,
        }
    }

    /// Continues a run from `checkpoint`, taken of a simulation of the same model with the same
    /// method and tolerances: the following steps and outputs are those the checkpointed simulation
    /// would have produced. `settings.t_end` may differ from the checkpointed run's (to run further), and
    /// so may `output_step` (the outputs continue on the new grid after the checkpoint's time); other
    /// tolerances than the checkpointed run's give other steps from the checkpoint on.
    pub fn resume(model: Arc<Model>, settings: SimulationSettings, checkpoint: &SimulationCheckpoint) -> Result<Self, SimulationError> {
        let fail = |cause| SimulationError { cause, report: Box::new(checkpoint.report.clone()) };
        settings.validate().map_err(|e| fail(SimulationFailure::Invalid(e)))?;
        // The checkpointed run warned already, if it had to.
        let settings = attainable_tolerances(settings, &mut Vec::new());
        if checkpoint.version != CHECKPOINT_VERSION {
            return Err(fail(SimulationFailure::Invalid(format!(
                "the checkpoint has layout version {}, this flexmb reads version {CHECKPOINT_VERSION}",
                checkpoint.version
            ))));
        }
        let laws: Vec<String> = model.user_laws().into_iter().map(str::to_string).collect();
        if checkpoint.user_laws != laws {
            return Err(fail(SimulationFailure::Invalid(format!(
                "the checkpoint was taken of a run with the laws given as code [{}], the model given has [{}]: \
                 give the model the same laws before resuming (they are code, not in the checkpoint)",
                checkpoint.user_laws.join(", "),
                laws.join(", ")
            ))));
        }
        model.clear_user_law_failures();
        let l = &model.layout;
        for (what, expected, found) in [
            ("the positions", l.nq, checkpoint.q.len()),
            ("the velocities", l.nv, checkpoint.v.len()),
            ("the multipliers", l.nc, checkpoint.multipliers.len()),
            ("the constraint rows in force", l.nc, checkpoint.active.len()),
            ("the parameters", model.parameters.len(), checkpoint.parameters.len()),
        ] {
            crate::integrate::check_len(what, expected, found).map_err(|e| fail(e.into()))?;
        }
        let state = State { t: checkpoint.t, q: checkpoint.q.clone(), v: checkpoint.v.clone(), active: checkpoint.active.clone() };
        // The integrator is started at the checkpoint's state, then its history is restored over what
        // it started with: the accelerations only seed what is overwritten.
        let acc = Accelerations { vdot: vec![0.0; l.nv], lambda: checkpoint.multipliers.clone() };
        let integrator = start_integrator(&model, &settings, &state, &acc).map_err(fail)?;
        let mut report = checkpoint.report.clone();
        report.method = integrator.name();
        report.interrupted = None;
        let accelerations = AccelerationSolver::new(&model);
        let mut simulation = Self::with_integrator(model, settings, integrator, accelerations, report);
        simulation.integrator.restore(&checkpoint.integrator).map_err(|e| fail(e.into()))?;
        simulation.watchdog.restore(&checkpoint.watchdog).map_err(|e| fail(e.into()))?;
        for (p, &value) in checkpoint.parameters.iter().enumerate() {
            simulation.write_parameter(p, value);
        }
        simulation.next_output = if checkpoint.output_step == settings.output_step || checkpoint.next_output == 0 {
            checkpoint.next_output
        } else {
            // The outputs up to `t` were reported on the old grid: the new grid's first time after `t`,
            // by the test the output loop makes.
            let reported = |k: usize| k as f64 * settings.output_step <= checkpoint.t * (1.0 + 1e-12);
            let mut k = (checkpoint.t / settings.output_step).floor() as usize;
            while k > 0 && !reported(k) {
                k -= 1;
            }
            while reported(k + 1) {
                k += 1;
            }
            k + 1
        };
        simulation.end_reported = checkpoint.end_reported;
        simulation.restarted_stats = checkpoint.restarted_stats;
        if checkpoint.last_output_row.len() == simulation.values.len() {
            simulation.values.copy_from_slice(&checkpoint.last_output_row);
        }
        Ok(simulation)
    }

    /// The complete state after the last accepted step (also after an interruption), to save and
    /// [`resume`](Self::resume). Fails after a failure.
    pub fn checkpoint(&mut self) -> Result<SimulationCheckpoint, SimulationFailure> {
        self.usable()?;
        let integrator = self.integrator.checkpoint()?;
        let multipliers = self.multipliers()?.to_vec();
        let (q, v) = self.integrator.state();
        Ok(SimulationCheckpoint {
            version: CHECKPOINT_VERSION,
            t: self.integrator.t(),
            q: q.to_vec(),
            v: v.to_vec(),
            multipliers,
            active: self.active.clone(),
            integrator,
            report: self.report.clone(),
            watchdog: self.watchdog.checkpoint(),
            parameters: self.parameters.clone(),
            next_output: self.next_output,
            output_step: self.settings.output_step,
            end_reported: self.end_reported,
            user_laws: self.model.user_laws().into_iter().map(str::to_string).collect(),
            restarted_stats: self.restarted_stats,
            last_output_row: self.values.clone(),
        })
    }

    /// The model simulated.
    pub fn model(&self) -> &Arc<Model> {
        &self.model
    }

    /// The settings of the run.
    pub fn settings(&self) -> &SimulationSettings {
        &self.settings
    }

    /// Time of the last accepted step (s).
    pub fn time(&self) -> f64 {
        self.integrator.t()
    }

    /// The end time has been reached and its outputs reported.
    pub fn is_finished(&self) -> bool {
        self.reached_end() && self.next_output > 0 && (self.end_reported || !self.settings.end_off_grid())
    }

    /// Positions `q` at the last accepted step (per body `R, p, a`).
    pub fn positions(&self) -> &[f64] {
        self.integrator.state().0
    }

    /// Velocities `v` at the last accepted step (per body `Ṙ, ω̄, ȧ`).
    pub fn velocities(&self) -> &[f64] {
        self.integrator.state().1
    }

    /// Modal coordinates `a` of `body` at the last accepted step (empty for a rigid body); `None` for an
    /// id that is not one of the model's bodies.
    pub fn modal_coordinates(&self, body: BodyId) -> Option<&[f64]> {
        let range = self.model.layout.modal_q_range(body)?;
        Some(&self.positions()[range])
    }

    /// Modal rates `ȧ` of `body` at the last accepted step (empty for a rigid body); `None` for an id
    /// that is not one of the model's bodies.
    pub fn modal_rates(&self, body: BodyId) -> Option<&[f64]> {
        let range = self.model.layout.modal_v_range(body)?;
        Some(&self.velocities()[range])
    }

    /// Lagrange multipliers `λ` at the last accepted step (one per constraint row, zero on the rows
    /// switched off as redundant), from the equations of motion at that state.
    pub fn multipliers(&mut self) -> Result<&[f64], SimulationFailure> {
        Ok(&self.solve_accelerations()?.lambda)
    }

    /// Accelerations `v̇` at the last accepted step, from the equations of motion at that state.
    pub fn accelerations(&mut self) -> Result<&[f64], SimulationFailure> {
        Ok(&self.solve_accelerations()?.vdot)
    }

    fn solve_accelerations(&mut self) -> Result<&Accelerations, SimulationFailure> {
        let t = self.integrator.t();
        let (q, v) = self.integrator.state();
        self.q.copy_from_slice(q);
        self.v.copy_from_slice(v);
        let data = self.integrator.data_mut();
        self.accelerations
            .solve_at(&self.model, data, t, &self.q, &self.v, &self.active)
            .map_err(|_| accelerations_failure(&self.model, data, t))
    }

    /// The current value of the parameter named `name` (declared with
    /// [`ModelBuilder::add_parameter`](crate::ModelBuilder::add_parameter)).
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.model.find_parameter(name).map(|p| self.parameters[p.0])
    }

    /// Changes the parameter named `name` to `value` from the next step on (the expressions that read
    /// it see the new value in every later evaluation). The integrator keeps its history: a change that
    /// makes the forces jump is absorbed by its error control, which shortens the steps after it.
    pub fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), SimulationFailure> {
        self.usable()?;
        let Some(p) = self.model.find_parameter(name) else {
            let names: Vec<&str> = self.model.parameters.iter().map(|p| p.name.as_str()).collect();
            let known = if names.is_empty() { "it has none".to_string() } else { format!("it has {}", names.join(", ")) };
            return Err(SimulationFailure::Invalid(format!("the model has no parameter '{name}': {known}")));
        };
        if !value.is_finite() {
            return Err(SimulationFailure::Invalid(format!("parameter '{name}' must be finite, got {value}")));
        }
        self.write_parameter(p.0, value);
        Ok(())
    }

    fn write_parameter(&mut self, p: usize, value: f64) {
        self.parameters[p] = value;
        self.integrator.data_mut().parameters[p] = value;
    }

    /// The equations of motion linearized at the last accepted step, with its accelerations and
    /// multipliers and the current parameter values (see [`linearize`](crate::analysis::linearize)).
    pub fn linearize(&mut self) -> Result<Linearization, SimulationFailure> {
        let acc = self.solve_accelerations()?.clone();
        let state = State { t: self.integrator.t(), q: self.q.clone(), v: self.v.clone(), active: self.active.clone() };
        Ok(linearize_at(&self.model, self.integrator.data_mut(), &state, &acc))
    }

    /// The last accepted step as an operating point of a linearization: a copy of the evaluation
    /// data (parameters, joint-angle continuation), the state, and its accelerations and multipliers.
    pub fn operating_point(&mut self) -> Result<(Data, State, Accelerations), SimulationFailure> {
        let acc = self.solve_accelerations()?.clone();
        let state = State { t: self.integrator.t(), q: self.q.clone(), v: self.v.clone(), active: self.active.clone() };
        Ok((self.integrator.data_mut().clone(), state, acc))
    }

    /// The integrator's counters so far (with those of the integrators a
    /// [`set_state`](Self::set_state) replaced).
    pub fn stats(&self) -> &crate::integrate::Stats {
        &self.report.stats
    }

    /// The report so far.
    pub fn report(&self) -> &SimulationReport {
        &self.report
    }

    /// Records in the report the runs that global error control ran again before this one
    /// ([`SimulationReport::global_error_control`]), for a caller that runs them as [`simulate`] does.
    pub fn record_earlier_runs(&mut self, earlier: Vec<ControlledRun>) {
        self.report.global_error_control = earlier;
    }

    /// The report, ending the simulation.
    pub fn into_report(self) -> SimulationReport {
        self.report
    }

    /// Records in the report that the run was stopped from outside at its current time, for `reason`.
    pub fn interrupt(&mut self, reason: String) {
        self.report.interrupted = Some(Interruption { t: self.integrator.t(), reason });
    }

    /// Takes one accepted step and reports to `sink` the outputs up to its end (the output at time 0
    /// first, at the first call; the output at the end time, at the last step). Does nothing once the
    /// simulation [`is_finished`](Self::is_finished).
    pub fn step(&mut self, sink: &mut dyn OutputSink) -> Result<(), SimulationFailure> {
        self.guarded(|s| {
            s.integrate_step(sink)?;
            s.report_end(sink)
        })
    }

    /// Steps until the time reaches `t` (or the end time), reporting the outputs passed to `sink`.
    /// The last step may end after `t`: steps are not shortened to land on it.
    pub fn advance_to(&mut self, t: f64, sink: &mut dyn OutputSink) -> Result<(), SimulationFailure> {
        self.advance_to_interruptible(t, sink, &|| None)
    }

    /// [`advance_to`](Self::advance_to), asking `interrupt` after every accepted step whether to stop,
    /// as [`run`](Self::run) does: when it answers with a reason, the simulation pauses there and its
    /// report carries [`SimulationReport::interrupted`] (it may be checkpointed or advanced further).
    pub fn advance_to_interruptible(
        &mut self,
        t: f64,
        sink: &mut dyn OutputSink,
        interrupt: &dyn Fn() -> Option<String>,
    ) -> Result<(), SimulationFailure> {
        self.guarded(|s| s.report_initial(sink))?;
        while !self.is_finished() && (self.time() < t || self.reached_end()) {
            self.step(sink)?;
            if let Some(reason) = interrupt() {
                self.interrupt(reason);
                break;
            }
        }
        Ok(())
    }

    /// Runs to the end time, asking `interrupt` after every accepted step (once its outputs are
    /// reported) whether to stop; when it answers with a reason, the run pauses there and its report
    /// carries [`SimulationReport::interrupted`] (it may be checkpointed or continued).
    pub fn run(&mut self, sink: &mut dyn OutputSink, interrupt: &dyn Fn() -> Option<String>) -> Result<(), SimulationFailure> {
        self.guarded(|s| {
            while !s.reached_end() {
                s.integrate_step(sink)?;
                if let Some(reason) = interrupt() {
                    s.interrupt(reason);
                    return Ok(());
                }
            }
            s.integrate_step(sink)?;
            s.report_end(sink)
        })
    }

    /// Runs `f`, adding its wall time to the report; a failure makes the simulation unusable.
    fn guarded(&mut self, f: impl FnOnce(&mut Self) -> Result<(), SimulationFailure>) -> Result<(), SimulationFailure> {
        self.usable()?;
        let start = Instant::now();
        let wall_time = self.report.wall_time;
        let mut result = f(self);
        if let Some(failure) = self.has_user_laws.then(|| user_law_failure(&self.model)).flatten() {
            result = Err(failure);
        }
        self.report.wall_time = wall_time + start.elapsed().as_secs_f64();
        self.failed = result.is_err();
        result
    }

    fn usable(&self) -> Result<(), SimulationFailure> {
        if self.failed {
            return Err(SimulationFailure::Invalid("the simulation has failed and cannot continue".into()));
        }
        Ok(())
    }

    fn reached_end(&self) -> bool {
        self.integrator.t() >= self.settings.t_end
    }

    /// The output at time 0 if not yet reported, then one accepted step (unless at the end time) and
    /// the grid outputs up to its end.
    fn integrate_step(&mut self, sink: &mut dyn OutputSink) -> Result<(), SimulationFailure> {
        self.report_initial(sink)?;
        if self.reached_end() {
            return Ok(());
        }
        let step = self.integrator.step(self.settings.t_end);
        let (rounding_before, singular_before) = (self.report.stats.rounding_floor_steps, self.report.stats.singular_positions);
        let floor_spent_before = self.report.stats.share_floor_spent();
        self.report.stats = self.restarted_stats.followed_by(self.integrator.stats());
        let (t, tolerances) = (self.integrator.t(), &self.settings.tolerances);
        if let Some(message) = floor_warning(floor_spent_before, &self.report.stats, tolerances.rtol, tolerances.span.seconds(), t, self.settings.t_end) {
            self.report.warnings.push(SimulationWarning { t, kind: WarningKind::Tolerance, message });
        }
        if rounding_before == 0 && self.report.stats.rounding_floor_steps > 0 {
            let message = rounding_floor_warning(self.report.stats.rounding_floor, self.settings.tolerances.rtol);
            self.report.warnings.push(SimulationWarning { t: self.integrator.t(), kind: WarningKind::Tolerance, message });
        }
        if self.report.stats.singular_positions > singular_before {
            let stats = &self.report.stats;
            let (condition, rtol) = (stats.singular_position_condition, self.settings.tolerances.rtol);
            let (held, near) = (stats.singular_position_tolerance, stats.singular_position_steps);
            if let Some(message) = singular_position_warning(condition, rtol, held, near) {
                self.report.warnings.push(SimulationWarning { t: self.integrator.t(), kind: WarningKind::Tolerance, message });
            }
        }
        // At the end of the run, after the warnings of its last step.
        let tolerances = &self.settings.tolerances;
        if step.is_ok() && t >= self.settings.t_end {
            if let Some(message) = passed_warning(&self.report.stats, tolerances.rtol, tolerances.span.seconds(), self.settings.t_end) {
                self.report.warnings.push(SimulationWarning { t, kind: WarningKind::Tolerance, message });
            }
        }
        self.report.t_reached = self.integrator.t();
        if let Some(failure) = self.has_user_laws.then(|| user_law_failure(&self.model)).flatten() {
            return Err(failure);
        }
        if let Err(crate::integrate::IntegrationError::StepSizeTooSmall { t, h, .. }) = &step {
            if let Some(failure) = driver_failure_ahead(&self.model, *t, *h) {
                return Err(failure);
            }
        }
        step?;
        self.copy_state();
        let t = self.integrator.t();
        Watchdog::check_finite(&self.model, t, &self.q, &self.v)?;
        check_step(&self.model, self.integrator.as_mut(), &self.q, &self.v, &self.active, &mut self.report);
        let power = self.step_power(t)?;
        let (n_outputs, output_step) = (self.settings.grid_outputs(), self.settings.output_step);
        while self.next_output <= n_outputs && self.next_output as f64 * output_step <= t * (1.0 + 1e-12) {
            let t_out = self.next_output as f64 * output_step;
            self.integrator.interpolate(t_out.min(t), &mut self.q, &mut self.v);
            self.report_frame(t_out, sink)?;
            self.next_output += 1;
        }
        add_work(&mut self.report, &mut self.watchdog, t, power);
        Ok(())
    }

    /// The output at time 0, if not yet reported.
    fn report_initial(&mut self, sink: &mut dyn OutputSink) -> Result<(), SimulationFailure> {
        if self.next_output == 0 {
            self.copy_state();
            self.report_frame(0.0, sink)?;
            self.next_output = 1;
        }
        Ok(())
    }

    /// The output at the end time when it is not on the output grid, once the end is reached.
    fn report_end(&mut self, sink: &mut dyn OutputSink) -> Result<(), SimulationFailure> {
        if self.reached_end() && !self.end_reported && self.settings.end_off_grid() {
            self.copy_state();
            self.report_frame(self.settings.t_end, sink)?;
            self.end_reported = true;
        }
        Ok(())
    }

    /// The power of the non-conservative forces at the accepted step that ended at `t` (the state in
    /// `self.q`, `self.v`, whose kinematics and constraints `check_step` evaluated). The power of the
    /// constraints that depend on time (drivers, distances whose length is a function of time) and the
    /// interface stiffening's need the multipliers and the force stage, solved for only in a model that
    /// has them; other constraints do no work.
    fn step_power(&mut self, t: f64) -> Result<f64, SimulationFailure> {
        let model = &*self.model;
        let data = self.integrator.data_mut();
        Ok(if self.power_needs_multipliers {
            let acc = self
                .accelerations
                .solve_at(model, data, t, &self.q, &self.v, &self.active)
                .map_err(|_| accelerations_failure(model, data, t))?;
            nonconservative_power(model, data, t, &acc.lambda)
        } else {
            measures(model, data);
            nonconservative_power(model, data, t, &[])
        })
    }

    fn copy_state(&mut self) {
        let (q, v) = self.integrator.state();
        self.q.copy_from_slice(q);
        self.v.copy_from_slice(v);
    }

    /// Evaluates the outputs at `(t, self.q, self.v)`, updates the report's energies and residuals,
    /// checks the state and hands the frame to `sink`, then lets the watchdog check it.
    fn report_frame(&mut self, t: f64, sink: &mut dyn OutputSink) -> Result<(), SimulationFailure> {
        let model = &*self.model;
        let (q, v, values, report) = (&self.q, &self.v, &mut self.values, &mut self.report);
        let data = self.integrator.data_mut();
        let acc = self
            .accelerations
            .solve_at(model, data, t, q, v, &self.active)
            .map_err(|_| accelerations_failure(model, data, t))?;
        let power = nonconservative_power(model, data, t, &acc.lambda);
        evaluate_outputs(model, data, (t, q, v), acc, &self.active, values, report.output_frames > 0);
        let (p, vel) = constraint_residuals(model, data, &self.active);
        report.max_output_position_residual = report.max_output_position_residual.max(p);
        report.max_output_velocity_residual = report.max_output_velocity_residual.max(vel);
        let e = energy(model, data, q, v);
        if report.output_frames == 0 {
            report.energy_initial = e.total();
        }
        report.energy_final = e.total();
        Watchdog::check_finite_frame(model, (t, q, v), &e, power)?;
        add_work(report, &mut self.watchdog, t, power);
        report.nonconservative_work = report.work_at_step.work;
        let balance_error = report.energy_final - report.energy_initial - report.nonconservative_work;
        report.output_frames += 1;
        sink.write_frame(&OutputFrame { t, values, q, v }).map_err(|message| SimulationFailure::Output { t, message })?;
        self.watchdog
            .check_frame(model, data, (t, q, v), (&e, balance_error), &mut report.warnings, &mut report.physics)?;
        if let Some(check) = self.divergence.as_mut() {
            check.compare(t, &self.q, &self.v, &mut self.report.warnings);
        }
        if let Some(estimate) = self.global_error.as_mut() {
            estimate.compare(t, (&self.values, &self.q, &self.v), &mut self.report);
        }
        Ok(())
    }
}

/// The earliest failure of the model's laws given as code, as the simulation's failure.
fn user_law_failure(model: &Model) -> Option<SimulationFailure> {
    model.user_law_failure().map(|f| SimulationFailure::UserLaw { law: f.law, t: f.t, message: f.message })
}

/// Why the accelerations at `t` could not be solved: a constraint equation whose value or rate is not
/// finite there (a driver's function outside its domain, or with an infinite rate, as `sqrt(t0 − t)`
/// at `t0`), named; otherwise a singular mass matrix or constraint Jacobian.
fn accelerations_failure(model: &Model, data: &Data, t: f64) -> SimulationFailure {
    match super::assembly::check_finite(model, data, t) {
        Err(non_finite) => non_finite.into(),
        Ok(()) => SimulationFailure::SingularAccelerations { t, detail: String::new() },
    }
}

/// Why the steps shrank to nothing at `t` (the last attempt `h`), where a driver's or distance's
/// function of time stops being finite just ahead, as `sqrt(t0 − t)` does at `t0`: its rate grows
/// without bound as `t0` nears, so the error test fails step after step before a step ends past `t0`.
/// The function is probed at `t + h` and a little further (1e-9 and 1e-6 of the time scale); where one
/// is not finite, the first time it is not is found by bisection from `t` and named as the failure.
fn driver_failure_ahead(model: &Model, t: f64, h: f64) -> Option<SimulationFailure> {
    let scale = 1.0 + t.abs();
    for (j, joint) in model.joints.iter().enumerate() {
        let (Some(function), Some(row)) = (joint.kind.time_function(), model.layout.joint_rows[j].clone().next()) else {
            continue;
        };
        let finite = |at: f64| {
            let [value, rate, _] = function.eval(at);
            value.is_finite() && rate.is_finite()
        };
        if !finite(t) {
            continue;
        }
        let Some(mut beyond) = [t + h, t + 1e-9 * scale, t + 1e-6 * scale].into_iter().find(|&at| !finite(at)) else {
            continue;
        };
        let mut before = t;
        loop {
            let middle = before + 0.5 * (beyond - before);
            if middle <= before || middle >= beyond {
                break;
            }
            if finite(middle) {
                before = middle;
            } else {
                beyond = middle;
            }
        }
        let [value, rate, _] = function.eval(beyond);
        let (what, value) = if value.is_finite() { ("time derivative", rate) } else { ("value", value) };
        let equation = model.describe_constraint_row(row);
        return Some(super::assembly::AssemblyError::NonFinite { t: beyond, equation, what, value }.into());
    }
    None
}

/// Adds the work of the non-conservative forces from the last node of the quadrature (an accepted step
/// or an output time, in the order of time) to `t`, where the power is `power`
/// ([`WorkAtStep::add`]), and hands the power to the watchdog, which bounds the quadrature's error
/// from the same nodes by the trapezoid's.
fn add_work(report: &mut SimulationReport, watchdog: &mut Watchdog, t: f64, power: f64) {
    let last = report.work_at_step;
    if report.output_frames == 0 {
        report.work_at_step = WorkAtStep { t, power, work: 0.0, previous: None };
        watchdog.add_power(t, power);
    } else if t > last.t {
        report.work_at_step = last.add(t, power);
        watchdog.add_power(t, power);
    }
}

/// The warning of the first step whose Newton increments were the rounding of its equations (see
/// [`Stats::rounding_floor_steps`](crate::integrate::Stats::rounding_floor_steps)), resolved to `level` of
/// the solution where `rtol` was asked.
fn rounding_floor_warning(level: f64, rtol: f64) -> String {
    format!(
        "tolerance finer than the equations can be resolved here: the Newton increments are the rounding of the \
         residual amplified by the iteration matrix (a near-singular constraint Jacobian, at a singular position, \
         or large forces), and the steps are resolved to about {level:.1e} of the solution instead of rtol {rtol:e}; \
         the statistics rounding_floor_steps and rounding_floor count such steps and give the coarsest level"
    )
}

/// The warning of a step just past a singular position whose conditioning limits what the steps near it
/// resolve: the constraint Jacobian's condition number `condition` at their ends (the largest so far), which
/// amplifies the rounding of the constrained solution to about `500 ε condition` of it (where the Newton
/// increments are taken as converged); `None` when that is within what the steps there were held to: `rtol`
/// with error per step, `held` (the finest `rtol` times a step's share of the tolerance,
/// [`Stats::singular_position_tolerance`](crate::integrate::Stats::singular_position_tolerance); 0: none)
/// with error per unit step, and there only where the `near` steps accepted near the positions so far
/// ([`Stats::singular_position_steps`](crate::integrate::Stats::singular_position_steps)), each resolved to
/// that level at worst, may spend more than a tenth of the tolerance: with error per unit step the local
/// errors of the whole run add up to the tolerance, and a few steps resolved more coarsely than their share
/// but far finer than `rtol` do not break that promise (the double four-bar over its 10 s at rtol 1e-6:
/// 66 such steps at 6.5e-10, 4e-8 of the solution at most, its `E` 2.4e-6; it warned at five passages).
fn singular_position_warning(condition: f64, rtol: f64, held: f64, near: usize) -> Option<String> {
    let level = crate::integrate::singular_position::SingularPassage::resolution(condition);
    let over_span = held > 0.0 && held < rtol;
    let asked = if over_span {
        format!("the {held:.1e} they are held to (rtol {rtol:e} times their share of the tolerance span)")
    } else {
        format!("rtol {rtol:e}")
    };
    let coarser = if over_span { level > held && near as f64 * level > 0.1 * rtol } else { level > rtol };
    coarser.then(|| {
        format!(
            "tolerance finer than the equations can be resolved near the singular position just passed: the constraint \
             Jacobian's condition number reached {condition:.1e} at the step ends near it (kept about half a step away \
             from it), which amplifies the rounding of the constrained solution there: the steps near it are resolved \
             to about {level:.1e} of the solution instead of {asked}; the statistics singular_positions, singular_position_steps, \
             singular_position_condition and singular_position_tolerance count them and give the largest condition number \
             and the finest level asked"
        )
    })
}

/// `settings` with tolerances finer than the arithmetic allows raised to the finest attainable (for the
/// BDF and the generalized-α method over the run's span, to the finest each keeps, [`Bdf::attainable`],
/// [`GeneralizedAlpha::attainable`]), and a
/// warning at the start saying so (and one for generalized-α's spectral radius near 1 under error control,
/// [`GeneralizedAlphaConfig::undamped_warning`](crate::integrate::GeneralizedAlphaConfig::undamped_warning)), and the span of the tolerance
/// [`ToleranceSpan::Run`](crate::integrate::ToleranceSpan::Run) made the run's length, `t_end`.
fn attainable_tolerances(settings: SimulationSettings, warnings: &mut Vec<SimulationWarning>) -> SimulationSettings {
    let (mut tolerances, raised) = settings.tolerances.attainable();
    if let Some(message) = raised {
        warnings.push(SimulationWarning { t: 0.0, kind: WarningKind::Tolerance, message });
    }
    // The BDF and generalized-α keep no tolerance below their finest over the run's span (before the span
    // is made seconds: an explicit span takes the tolerance as given).
    let raised;
    (tolerances, raised) = attainable_by_method(&tolerances, &settings.method);
    if let Some(message) = raised {
        warnings.push(SimulationWarning { t: 0.0, kind: WarningKind::Tolerance, message });
    }
    if let Method::GeneralizedAlpha(config) = &settings.method {
        if let Some(message) = config.undamped_warning() {
            warnings.push(SimulationWarning { t: 0.0, kind: WarningKind::Tolerance, message });
        }
    }
    tolerances.span = tolerances.span.over_run(settings.t_end);
    SimulationSettings { tolerances, ..settings }
}

/// `tolerances` with an `rtol` or `atol` below the finest `method` keeps raised to it, and what was raised
/// and why: over the run's span the BDF's [`Bdf::attainable`] and generalized-α's
/// [`GeneralizedAlpha::attainable`]; the Adams method keeps every tolerance down to [`Tolerances::FINEST`](crate::integrate::Tolerances::FINEST).
/// A [`Simulation`] applies it at its start (with a warning where it raised one); `flexmb compare
/// --tolerances` leaves out a tolerance it would raise.
pub fn attainable_by_method(tolerances: &crate::integrate::Tolerances, method: &Method) -> (crate::integrate::Tolerances, Option<String>) {
    match method {
        Method::Bdf(_) => Bdf::attainable(tolerances),
        Method::GeneralizedAlpha(config) => GeneralizedAlpha::attainable(tolerances, config),
        Method::Adams(_) => (*tolerances, None),
    }
}

/// The finest tolerance `method` keeps over the run's span: what [`attainable_by_method`] raises a vanishing
/// one to (the BDF's 1e-10, generalized-α's 1e-7), at least [`Tolerances::FINEST`](crate::integrate::Tolerances::FINEST) (the Adams method's).
pub(crate) fn finest_over_run(method: &Method) -> f64 {
    let vanishing = crate::integrate::Tolerances::new(f64::MIN_POSITIVE, f64::MIN_POSITIVE);
    attainable_by_method(&vanishing, method).0.rtol.max(crate::integrate::Tolerances::FINEST)
}

/// The integrator of `settings.method`, started at a consistent state and its accelerations.
fn start_integrator(
    model: &Arc<Model>,
    settings: &SimulationSettings,
    state: &State,
    acc: &Accelerations,
) -> Result<Box<dyn Integrator>, SimulationFailure> {
    let model = Arc::clone(model);
    Ok(match settings.method {
        Method::Bdf(config) => Box::new(Bdf::new(model, state, acc, settings.tolerances, config)?),
        Method::Adams(config) => {
            config.validate().map_err(SimulationFailure::Invalid)?;
            Box::new(Adams::new(model, state, acc, settings.tolerances, config)?)
        }
        Method::GeneralizedAlpha(config) => {
            config.validate().map_err(SimulationFailure::Invalid)?;
            Box::new(GeneralizedAlpha::new(model, state, acc, settings.tolerances, config)?)
        }
    })
}

/// Runs a simulation and hands every output frame to `observer` as soon as it is computed.
pub fn simulate(
    model: &Model,
    settings: &SimulationSettings,
    observer: &mut dyn FnMut(&OutputFrame),
) -> Result<SimulationReport, SimulationError> {
    simulate_interruptible(model, settings, observer, &|| None)
}

/// [`simulate`], asking `interrupt` after every accepted step (once its output frames are reported)
/// whether to stop; when it answers with a reason, the run ends there and its report carries
/// [`SimulationReport::interrupted`]. A [`Simulation`] on a copy of `model`, run to its end; with
/// [`SimulationSettings::global_error_control`], again from the start as long as
/// [`global_error_rerun`] asks (`observer` then sees each run's frames from t = 0, the last run's being
/// the results; the report is the last run's, with the earlier ones in
/// [`SimulationReport::global_error_control`]).
pub fn simulate_interruptible(
    model: &Model,
    settings: &SimulationSettings,
    observer: &mut dyn FnMut(&OutputFrame),
    interrupt: &dyn Fn() -> Option<String>,
) -> Result<SimulationReport, SimulationError> {
    let model = Arc::new(model.clone());
    let (result, _, earlier) = run_under_global_error_control(settings, |settings| {
        let result = Simulation::new(Arc::clone(&model), *settings).and_then(|mut simulation| {
            let run = simulation.run(&mut |frame: &OutputFrame| observer(frame), interrupt);
            let report = simulation.into_report();
            match run {
                Ok(()) => Ok(report),
                Err(cause) => Err(SimulationError { cause, report: Box::new(report) }),
            }
        });
        let completed = result.as_ref().ok().cloned();
        (result, completed)
    });
    match result {
        Ok(mut report) => {
            report.global_error_control = earlier;
            Ok(report)
        }
        Err(mut e) => {
            e.report.global_error_control = earlier;
            Err(e)
        }
    }
}

/// Records the constraint residuals and the Euler-parameter normalization at an accepted step.
fn check_step(model: &Model, integrator: &mut dyn Integrator, q: &[f64], v: &[f64], active: &[bool], report: &mut SimulationReport) {
    let t = integrator.t();
    let data = integrator.data_mut();
    run_kinematic_stages(model, data, t, q, v);
    let (p, vel) = constraint_residuals(model, data, active);
    report.max_position_residual = report.max_position_residual.max(p);
    report.max_velocity_residual = report.max_velocity_residual.max(vel);
    for b in 0..model.bodies.len() {
        let qo = model.layout.q_offset[b];
        let norm2: f64 = (3..7).map(|k| q[qo + k].powi(2)).sum();
        report.max_normalization_error = report.max_normalization_error.max((norm2 - 1.0).abs());
    }
}
