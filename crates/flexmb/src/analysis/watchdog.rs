//! The physics watchdog of a simulation: a run whose states have left physics warns at a first
//! threshold and stops at a second, with a diagnosis of what is likely wrong, instead of integrating
//! nonsense until the step size collapses.
//!
//! - **Non-finite states** (NaN or infinite positions, velocities, energy) stop the run at once; they
//!   are checked after every accepted step and at every output time.
//! - **Elastic deflection**: the largest elastic displacement `|Ψᵢ a|` of a node of a flexible body, as a
//!   fraction of the body's size (the diagonal of its nodes' bounding box in the body frame). A modal
//!   body is linear in its modal coordinates, so its results hold for small displacements only.
//! - **Energy balance**: the error `E(t) − E(0) − W_nc(t)` beyond what the computation of the balance
//!   itself explains, as a fraction of the energy that flowed. The energy that flowed is the larger of
//!   the largest `T + |V| + U` seen at the output times (kinetic, potential and strain energy) and the
//!   accumulated `∫ |P_nc| dt`. What the computation explains: three times the estimated error of the
//!   trapezoidal rule of `W_nc` over its nodes, the accepted steps and output times (`Σ h³/12 |P''|`), plus the energy error the
//!   integrator's absolute tolerance allows at the state, `atol (Σ |(M v)_k| + Σ |Q_k|) + atol²/2 Σ |M_rc|`
//!   (the first-order change of `T` and of the work of the applied forces for velocity and position
//!   errors of `atol`, and the second-order change of `T`), which covers the start of a run, when the
//!   motion is still below the tolerance, and a body held at rest, whose energy is round-off.
//!
//! Deflection and energy balance are checked at the output times.

use crate::data::Data;
use crate::model::Model;
use crate::stage::{body_mass_entries, Energy};

/// The thresholds of the physics watchdog (see the module documentation); the defaults are documented
/// in docs/model-file.md (`[simulation]`) and justified in docs/engine.md.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsLimits {
    /// Elastic displacement of a flexible body, as a fraction of its size, at which the run warns.
    /// Default 0.1.
    pub elastic_deflection_warning: f64,
    /// ... at which the run stops. Default 0.5.
    pub elastic_deflection_limit: f64,
    /// Energy-balance error (beyond what the quadrature and the tolerance explain), as a fraction of
    /// the energy that flowed, at which the run warns. Default 0.05.
    pub energy_balance_warning: f64,
    /// ... at which the run stops. Default 0.5: half the energy is the integrator's.
    pub energy_balance_limit: f64,
}

impl Default for PhysicsLimits {
    fn default() -> Self {
        Self {
            elastic_deflection_warning: 0.1,
            elastic_deflection_limit: 0.5,
            energy_balance_warning: 0.05,
            energy_balance_limit: 0.5,
        }
    }
}

impl PhysicsLimits {
    /// Each threshold positive, each warning at most its limit.
    pub fn validate(&self) -> Result<(), String> {
        let pairs = [
            ("elastic_deflection", self.elastic_deflection_warning, self.elastic_deflection_limit),
            ("energy_balance", self.energy_balance_warning, self.energy_balance_limit),
        ];
        for (name, warning, limit) in pairs {
            if !(warning > 0.0 && limit > 0.0) || warning.is_nan() || limit.is_nan() {
                return Err(format!("{name}_warning and {name}_limit must be positive, got {warning} and {limit}"));
            }
            if warning > limit {
                return Err(format!("{name}_warning ({warning}) must not exceed {name}_limit ({limit})"));
            }
        }
        Ok(())
    }
}

/// What a warning is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum WarningKind {
    /// A flexible body's elastic displacement.
    ElasticDeflection,
    /// The energy balance.
    EnergyBalance,
    /// A tolerance finer than the arithmetic allows, raised to the finest attainable
    /// ([`Tolerances::attainable`](crate::integrate::Tolerances::attainable)), or than the generalized-α
    /// method keeps over the run's span ([`GeneralizedAlpha::attainable`](crate::integrate::GeneralizedAlpha::attainable)).
    Tolerance,
}

impl WarningKind {
    /// `elastic_deflection` or `energy_balance`, as the settings name it.
    pub fn name(self) -> &'static str {
        match self {
            WarningKind::ElasticDeflection => "elastic_deflection",
            WarningKind::EnergyBalance => "energy_balance",
            WarningKind::Tolerance => "tolerance",
        }
    }
}

/// A threshold crossed during a run, first time only (per flexible body for deflections).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimulationWarning {
    /// Output time at which it was first seen (s).
    pub t: f64,
    /// What it is about.
    pub kind: WarningKind,
    /// What was seen and what to do, for a person.
    pub message: String,
}

/// Why the watchdog stopped a run.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum Unphysical {
    /// A position, velocity, energy or power is NaN or infinite.
    #[error("the state is not finite at t = {t:.6} s: {what} is {value}; the equations of motion produced NaN or infinity (a force or driver expression that is not finite there, or an instability)")]
    NonFinite {
        /// Time (s).
        t: f64,
        /// What is not finite.
        what: String,
        /// Its value.
        value: f64,
    },
    /// A flexible body deflected beyond the limit.
    #[error("the run has left physics: {}", .0.describe("elastic_deflection_limit"))]
    ElasticDeflection(Box<Deflection>),
    /// The energy balance is off beyond the limit.
    #[error("the run has left physics: {}", .0.describe("energy_balance_limit"))]
    EnergyBalance(Balance),
}

/// The largest elastic displacement of a flexible body at one output time.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Deflection {
    /// Output time (s).
    pub t: f64,
    /// The flexible body.
    pub body: String,
    /// Label of the node that moved most.
    pub node: u64,
    /// Its elastic displacement `|Ψ a|` (m).
    pub deflection: f64,
    /// The body's size: the diagonal of its nodes' bounding box (m).
    pub size: f64,
    /// The threshold crossed (a fraction of the size).
    pub threshold: f64,
    /// The magnitude of the body frame's angular velocity (rad/s).
    pub angular_velocity: f64,
    /// The lowest natural frequency of the body's reduced model (rad/s), if it has one.
    pub lowest_frequency: Option<f64>,
    /// Whether the body has geometric stiffening (then its spin stiffens it and does not explain a
    /// large deflection).
    #[serde(default)]
    pub geometric_stiffening: bool,
}

impl Deflection {
    /// What was seen, what is likely wrong, what to do, and which setting moves the threshold.
    pub fn describe(&self, setting: &str) -> String {
        let mut s = format!(
            "at t = {:.4} s the elastic displacement of flexible body '{}' is {:.3e} m at node {}, {:.0} % of its size {:.3} m \
             ([simulation] {setting} = {}). ",
            self.t,
            self.body,
            self.deflection,
            self.node,
            100.0 * self.deflection / self.size,
            self.size,
            self.threshold
        );
        match self.lowest_frequency {
            Some(w1) if self.angular_velocity >= 0.5 * w1 && !self.geometric_stiffening => s += &format!(
                "The body turns at {:.3} rad/s, {} its lowest modal frequency {:.3} rad/s ({:.3} Hz): a modal body is a linear \
                 model, here without geometric (centrifugal) stiffening (its flexible-body file has no geometric-stiffness \
                 terms, or `geometric_stiffening = false`), so spinning it softens its bending modes instead of \
                 stiffening them, and near or above that frequency its deflection grows without bound. Turn geometric \
                 stiffening on (a beam model reduced by this version has the terms), split it into several flexible \
                 bodies joined together, keep its speed well below {:.3} rad/s, or model it as a nonlinear beam.",
                self.angular_velocity,
                if self.angular_velocity >= w1 { "above" } else { "more than half" },
                w1,
                w1 / std::f64::consts::TAU,
                w1
            ),
            _ => s += "A modal body is linear in its modal coordinates: its results hold for small elastic displacements \
                       only. Check the loads and their units, the FE model's material and supports, and its mode set \
                       (vibration modes alone may need large amplitudes to fit a joint, where static correction modes \
                       at the joint's nodes do not); a large deformation needs several flexible bodies or a nonlinear \
                       model.",
        }
        s
    }
}

/// The energy balance at one output time.
#[derive(Clone, Debug, PartialEq)]
pub struct Balance {
    /// Output time (s).
    pub t: f64,
    /// `E(t) − E(0) − W_nc(t)` (J).
    pub error: f64,
    /// The energy that flowed (J), the scale of the error.
    pub scale: f64,
    /// The threshold crossed (a fraction of the scale).
    pub threshold: f64,
}

impl Balance {
    /// What was seen, what is likely wrong, what to do, and which setting moves the threshold.
    pub fn describe(&self, setting: &str) -> String {
        format!(
            "at t = {:.4} s the energy balance is off by {:.3e} J, {:.1} % of the {:.3e} J of energy that flowed \
             ([simulation] {setting} = {}): the energy is not what the work of the forces put in. The integration \
             has gone unstable or lost accuracy (tighten rtol and atol; with the BDF, max_order = 2 keeps the \
             A-stable orders), or a force's power is not resolved by the output step (shorten output_step).",
            self.t,
            self.error,
            100.0 * self.error.abs() / self.scale,
            self.scale,
            self.threshold
        )
    }
}

/// The largest values the watchdog measured, whether or not they crossed a threshold.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PhysicsMeasures {
    /// The largest elastic deflection relative to its body's size, over the flexible bodies and the
    /// output times (`None` without flexible bodies).
    pub largest_deflection: Option<Deflection>,
    /// The largest energy-balance error `|E − E0 − W_nc|` beyond what the quadrature and the tolerance
    /// explain, relative to the energy that flowed, and when.
    pub largest_balance_fraction: f64,
    /// The output time of that largest error (s).
    pub largest_balance_time: f64,
    /// The energy that flowed by the end of the run (J).
    pub energy_scale: f64,
}

/// The watchdog's running sums and the warnings it has given, for a checkpoint of a simulation.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WatchdogCheckpoint {
    /// The largest `T + |V| + U` seen (J).
    pub largest_energy: f64,
    /// `∫ |P_nc| dt` so far (J).
    pub absolute_work: f64,
    /// The trapezoidal rule's estimated error so far (J).
    pub quadrature_error: f64,
    /// The last two `(t, P_nc)`, latest first.
    pub last_powers: [Option<(f64, f64)>; 2],
    /// The energy-balance warning was given.
    pub warned_energy: bool,
    /// The deflection warning was given, per flexible body the watchdog follows.
    pub warned_deflection: Vec<bool>,
}

/// A flexible body as the watchdog sees it.
struct FlexibleExtent {
    body: usize,
    size: f64,
    lowest_frequency: Option<f64>,
    warned: bool,
}

/// The energy that flowed up to an output time, and how much of the energy-balance error the
/// trapezoidal rule of `W_nc` may explain by itself.
#[derive(Default)]
pub(super) struct EnergyFlow {
    /// The largest `T + |V| + U` seen (J).
    largest_energy: f64,
    /// `∫ |P_nc| dt` (J), by the trapezoidal rule.
    absolute_work: f64,
    /// `Σ h³/12 |P''|` over the intervals so far (J), `P''` the second divided difference of the last
    /// three powers (the first interval: `h |ΔP| / 4`): the trapezoidal rule's own error, estimated.
    pub(super) quadrature_error: f64,
    /// The last two `(t, P_nc)`, latest first.
    last: [Option<(f64, f64)>; 2],
}

impl EnergyFlow {
    /// Adds an output time with energy `e` and a step with non-conservative power `power` at the
    /// same time.
    #[cfg(test)]
    pub(super) fn add(&mut self, t: f64, e: &Energy, power: f64) {
        self.add_energy(e);
        self.add_power(t, power);
    }

    /// Adds the energy at an output time.
    pub(super) fn add_energy(&mut self, e: &Energy) {
        self.largest_energy = self.largest_energy.max(e.kinetic.abs() + e.potential.abs() + e.strain.abs());
    }

    /// Adds the non-conservative power at an accepted step (the trapezoidal rule's nodes).
    pub(super) fn add_power(&mut self, t: f64, power: f64) {
        if let [Some((t1, p1)), previous] = self.last {
            let h = t - t1;
            self.absolute_work += 0.5 * (p1.abs() + power.abs()) * h;
            self.quadrature_error += match previous {
                Some((t2, p2)) => {
                    let second_difference = 2.0 * ((power - p1) / h - (p1 - p2) / (t1 - t2)) / (t - t2);
                    h.powi(3) / 12.0 * second_difference.abs()
                }
                None => h * (power - p1).abs() / 4.0,
            };
        }
        self.last = [Some((t, power)), self.last[0]];
    }

    /// The energy that flowed: the larger of the largest energy seen and `∫ |P_nc| dt`.
    pub(super) fn scale(&self) -> f64 {
        self.largest_energy.max(self.absolute_work)
    }

    /// The part of a balance error that neither the quadrature (with a factor 3 of margin on its
    /// estimate) nor the integrator's tolerance `tolerated` explains, as a fraction of the energy
    /// that flowed.
    pub(super) fn unexplained_fraction(&self, balance_error: f64, tolerated: f64) -> f64 {
        let scale = self.scale();
        if scale > 0.0 {
            (balance_error.abs() - 3.0 * self.quadrature_error - tolerated).max(0.0) / scale
        } else {
            0.0
        }
    }
}

/// The watchdog's state during one run.
pub(crate) struct Watchdog {
    limits: PhysicsLimits,
    /// The integrator's absolute tolerance.
    atol: f64,
    bodies: Vec<FlexibleExtent>,
    flow: EnergyFlow,
    warned_energy: bool,
    /// One body's `M v`, allocated once.
    momentum: Vec<f64>,
}

impl Watchdog {
    pub(crate) fn new(model: &Model, limits: PhysicsLimits, atol: f64) -> Self {
        let bodies = model
            .modal
            .iter()
            .enumerate()
            .filter_map(|(b, modal)| {
                let modal = modal.as_ref()?;
                let mut lo = crate::math::Vec3::repeat(f64::INFINITY);
                let mut hi = crate::math::Vec3::repeat(f64::NEG_INFINITY);
                for n in &modal.nodes {
                    lo = lo.inf(&n.position);
                    hi = hi.sup(&n.position);
                }
                let size = (hi - lo).norm();
                (modal.modes() > 0 && size > 0.0 && size.is_finite()).then(|| FlexibleExtent {
                    body: b,
                    size,
                    lowest_frequency: modal.lowest_frequency(),
                    warned: false,
                })
            })
            .collect();
        let momentum = vec![0.0; model.layout.modes.iter().map(|m| 6 + m).max().unwrap_or(6)];
        Self { limits, atol, bodies, flow: EnergyFlow::default(), warned_energy: false, momentum }
    }

    /// Its running sums and warnings given.
    pub(crate) fn checkpoint(&self) -> WatchdogCheckpoint {
        WatchdogCheckpoint {
            largest_energy: self.flow.largest_energy,
            absolute_work: self.flow.absolute_work,
            quadrature_error: self.flow.quadrature_error,
            last_powers: self.flow.last,
            warned_energy: self.warned_energy,
            warned_deflection: self.bodies.iter().map(|b| b.warned).collect(),
        }
    }

    /// Continues from `c`, taken of the watchdog of a run of the same model.
    pub(crate) fn restore(&mut self, c: &WatchdogCheckpoint) -> Result<(), crate::integrate::CheckpointError> {
        crate::integrate::check_len("the watchdog's flexible bodies", self.bodies.len(), c.warned_deflection.len())?;
        self.flow = EnergyFlow {
            largest_energy: c.largest_energy,
            absolute_work: c.absolute_work,
            quadrature_error: c.quadrature_error,
            last: c.last_powers,
        };
        self.warned_energy = c.warned_energy;
        for (body, &warned) in self.bodies.iter_mut().zip(&c.warned_deflection) {
            body.warned = warned;
        }
        Ok(())
    }

    /// Adds the non-conservative power at an accepted step (and at time 0), the nodes of the
    /// trapezoidal rule whose error the balance allows for.
    pub(crate) fn add_power(&mut self, t: f64, power: f64) {
        self.flow.add_power(t, power);
    }

    /// Stops at a non-finite position or velocity (after every accepted step and at output times).
    pub(crate) fn check_finite(model: &Model, t: f64, q: &[f64], v: &[f64]) -> Result<(), Unphysical> {
        let bad = |x: &[f64]| x.iter().position(|x| !x.is_finite());
        let layout = &model.layout;
        let (k, offsets, name) = if let Some(k) = bad(q) {
            (k, &layout.q_offset, "position")
        } else if let Some(k) = bad(v) {
            (k, &layout.v_offset, "velocity")
        } else {
            return Ok(());
        };
        let value = if name == "position" { q[k] } else { v[k] };
        let b = offsets.iter().rposition(|&o| o <= k).unwrap_or(0);
        let what = format!("{name} coordinate {} of body '{}'", k - offsets[b], model.bodies[b].name);
        Err(Unphysical::NonFinite { t, what, value })
    }

    /// Stops at a non-finite state, energy or power at an output time (before it is reported).
    pub(crate) fn check_finite_frame(model: &Model, (t, q, v): (f64, &[f64], &[f64]), e: &Energy, power: f64) -> Result<(), Unphysical> {
        Self::check_finite(model, t, q, v)?;
        for (what, value) in [("the energy", e.total()), ("the power of the non-conservative forces", power)] {
            if !value.is_finite() {
                return Err(Unphysical::NonFinite { t, what: what.to_string(), value });
            }
        }
        Ok(())
    }

    /// Checks a reported output time: the elastic deflections at `q`, `v`, and the energy balance
    /// `E − E0 − W_nc` with the energy `e` (the powers of the steps added by [`add_power`](Self::add_power)), at the state whose
    /// stages (forces and kinematics) are in `data`. Warnings go to `warnings`, the largest values to
    /// `measures`.
    pub(crate) fn check_frame(
        &mut self,
        model: &Model,
        data: &Data,
        (t, q, v): (f64, &[f64], &[f64]),
        (e, balance_error): (&Energy, f64),
        warnings: &mut Vec<SimulationWarning>,
        measures: &mut PhysicsMeasures,
    ) -> Result<(), Unphysical> {
        self.check_deflections(model, (t, q, v), warnings, measures)?;
        let tolerated = self.tolerated_energy_error(model, data, v);
        self.check_energy(t, e, (balance_error, tolerated), warnings, measures)
    }

    /// `atol (Σ |(M v)_k| + Σ |Q_k|) + atol²/2 Σ |M_rc|`: how much the energy may be off at a state
    /// known to `atol` in every position and velocity coordinate: to first order `δT = (M v)ᵀ δv` and
    /// the applied forces' work over `δq`; to second order `δvᵀ M δv / 2`, which is what is left when
    /// the velocities are zero (a body held at rest has a kinetic energy of the size of round-off,
    /// the whole of the energy that flowed).
    fn tolerated_energy_error(&mut self, model: &Model, data: &Data, v: &[f64]) -> f64 {
        let mut sum: f64 = data.applied.iter().map(|q| q.abs()).sum();
        let mut mass_sum = 0.0;
        for b in 0..model.bodies.len() {
            let vo = model.layout.v_offset[b];
            let momentum = &mut self.momentum[..6 + model.layout.modes[b]];
            momentum.fill(0.0);
            body_mass_entries(model, data, b, |r, c, m| {
                momentum[r] += m * v[vo + c];
                mass_sum += m.abs();
            });
            sum += momentum.iter().map(|p| p.abs()).sum::<f64>();
        }
        self.atol * sum + 0.5 * self.atol * self.atol * mass_sum
    }

    fn check_deflections(
        &mut self,
        model: &Model,
        (t, q, v): (f64, &[f64], &[f64]),
        warnings: &mut Vec<SimulationWarning>,
        measures: &mut PhysicsMeasures,
    ) -> Result<(), Unphysical> {
        let limits = self.limits;
        for extent in &mut self.bodies {
            let b = extent.body;
            let Some(modal) = &model.modal[b] else { continue };
            let (qo, vo, m) = (model.layout.q_offset[b], model.layout.v_offset[b], modal.modes());
            let a = nalgebra::DVectorView::from_slice(&q[qo + 7..qo + 7 + m], m);
            let (node, deflection) = modal
                .nodes
                .iter()
                .map(|n| (n.label, (&n.psi * a).norm()))
                .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best });
            let angular_velocity = crate::math::Vec3::from_column_slice(&v[vo + 3..vo + 6]).norm();
            let seen = |threshold| Deflection {
                t,
                body: model.bodies[b].name.clone(),
                node,
                deflection,
                size: extent.size,
                threshold,
                angular_velocity,
                lowest_frequency: extent.lowest_frequency,
                geometric_stiffening: modal.geometric_stiffness.is_some(),
            };
            let fraction = deflection / extent.size;
            if measures.largest_deflection.as_ref().is_none_or(|d| fraction > d.deflection / d.size) {
                measures.largest_deflection = Some(seen(0.0));
            }
            if fraction >= limits.elastic_deflection_warning && !extent.warned {
                extent.warned = true;
                let message = seen(limits.elastic_deflection_warning).describe("elastic_deflection_warning");
                warnings.push(SimulationWarning { t, kind: WarningKind::ElasticDeflection, message });
            }
            if fraction >= limits.elastic_deflection_limit {
                return Err(Unphysical::ElasticDeflection(Box::new(seen(limits.elastic_deflection_limit))));
            }
        }
        Ok(())
    }

    fn check_energy(
        &mut self,
        t: f64,
        e: &Energy,
        (balance_error, tolerated): (f64, f64),
        warnings: &mut Vec<SimulationWarning>,
        measures: &mut PhysicsMeasures,
    ) -> Result<(), Unphysical> {
        self.flow.add_energy(e);
        let scale = self.flow.scale();
        measures.energy_scale = scale;
        let fraction = self.flow.unexplained_fraction(balance_error, tolerated);
        if fraction > measures.largest_balance_fraction {
            measures.largest_balance_fraction = fraction;
            measures.largest_balance_time = t;
        }
        let seen = |threshold| Balance { t, error: balance_error, scale, threshold };
        if fraction >= self.limits.energy_balance_warning && !self.warned_energy {
            self.warned_energy = true;
            let message = seen(self.limits.energy_balance_warning).describe("energy_balance_warning");
            warnings.push(SimulationWarning { t, kind: WarningKind::EnergyBalance, message });
        }
        if fraction >= self.limits.energy_balance_limit {
            return Err(Unphysical::EnergyBalance(seen(self.limits.energy_balance_limit)));
        }
        Ok(())
    }
}
