//! The complete state of an integrator between two steps, as plain data: what a resumed integrator
//! needs to continue the same step sequence (its history, order, step size, the Jacobian it reuses,
//! the pivot sequence its iteration matrix's factorizations keep, its counters), and nothing it
//! recomputes (workspaces, factors, scratch data).
//!
//! A checkpoint is restored into an integrator of the same method built for the same model
//! ([`Integrator::restore`](super::Integrator::restore)); the integrator loads the kept pivots and
//! refactors a reused Jacobian from the stored values on them, which gives the same factors and so the
//! same steps.

use serde::{Deserialize, Serialize};

use super::adams::{AdamsStepper, PartitionCheckpoint, ProjectionDrift};
use super::{RateMonitor, Stats};

/// The state of one integrator between two steps, by method.
// The BDF's and generalized-α's states are of a size (vectors and a few numbers each), made once per
// checkpoint: boxing one would only move the other above the limit.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum IntegratorCheckpoint {
    /// The BDF's state.
    Bdf(BdfCheckpoint),
    /// The Adams method's state.
    Adams(Box<AdamsCheckpoint>),
    /// The generalized-α method's state.
    GeneralizedAlpha(GeneralizedAlphaCheckpoint),
}

impl IntegratorCheckpoint {
    /// The method's name, as [`Integrator::name`](super::Integrator::name) gives it.
    pub fn method(&self) -> &'static str {
        match self {
            IntegratorCheckpoint::Bdf(_) => "bdf",
            IntegratorCheckpoint::Adams(_) => "adams",
            IntegratorCheckpoint::GeneralizedAlpha(_) => "gen-alpha",
        }
    }

    /// The time of the last accepted step (s).
    pub fn t(&self) -> f64 {
        match self {
            IntegratorCheckpoint::Bdf(c) => c.t,
            IntegratorCheckpoint::Adams(c) => c.stepper.t(),
            IntegratorCheckpoint::GeneralizedAlpha(c) => c.t,
        }
    }
}

/// The BDF's state: the backward differences and the step control, the stored parts of the iteration
/// matrix it reuses, and its counters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BdfCheckpoint {
    /// Time of the last accepted step and of the one before (s).
    pub t: f64,
    /// Start of the last accepted step (s).
    pub t_old: f64,
    /// Step size planned for the next step (s).
    pub h: f64,
    /// Current order, 1 to 5.
    pub order: usize,
    /// Accepted steps since the last change of order or step size.
    pub n_equal_steps: usize,
    /// Backward differences `∇ʲy` of `y = [q, v, λ, μ]`, rows `j = 0..=7`.
    pub differences: Vec<f64>,
    /// `∂F/∂y` and `∂F/∂ẏ` of the iteration matrix, in the order of its sparse pattern.
    pub jacobian: Vec<f64>,
    /// See [`jacobian`](Self::jacobian).
    pub jacobian_derivative: Vec<f64>,
    /// The `c = h/γ_k` the factors in use were made for (`None`: none in use).
    pub factored_c: Option<f64>,
    /// The pivot sequence the iteration matrix's factorizations keep (the position of each row in the
    /// pivot order; `None` when none is kept, or the matrix is small enough to be factored dense): the
    /// factors depend on it, so a resumed run loads it to take the same steps to the last bit. A
    /// checkpoint written before kept pivots has none: the resumed run's first factorization chooses
    /// its pivots afresh, and its steps agree with the uninterrupted run's within the tolerances only.
    #[serde(default)]
    pub kept_pivots: Option<Vec<usize>>,
    /// The Jacobian was evaluated at the predictor of the attempt in progress.
    pub jacobian_at_attempt: bool,
    /// The convergence rate of the Newton iterations, from which the next step's is predicted.
    #[serde(default)]
    pub newton_rate: RateMonitor,
    /// Accepted steps left during which the error estimates are filtered.
    pub filter_steps: usize,
    /// Stability limit of the step size for each order (s; infinite where none was found).
    #[serde(with = "extended_floats")]
    pub step_limits: Vec<f64>,
    /// Step size and weighted error estimate of the last accepted step.
    pub last_h: f64,
    /// See [`last_h`](Self::last_h).
    #[serde(with = "extended_float")]
    pub last_error: f64,
    /// The floor under a step's share of the tolerance: the last accepted step's share and the share
    /// learnt from noise (zero in checkpoints written before error per unit step).
    #[serde(default)]
    pub share_floor: [f64; 2],
    /// The rounding floor of the Newton increments and the level of the last stalled iteration of the
    /// step (zero in checkpoints written before the floor).
    #[serde(default)]
    pub newton_rounding: [f64; 2],
    /// The rounding level of the Newton increments estimated with the current factors, in tolerances
    /// (`None`: not estimated yet, and in checkpoints written before the level), so that a resumed run
    /// converges where the uninterrupted one does.
    #[serde(default)]
    pub newton_rounding_level: Option<f64>,
    /// The last step accepted away from singular positions, towards which a step near one may grow back
    /// (0 in checkpoints written before it: none).
    #[serde(default)]
    pub smooth_step: f64,
    /// The mean of the steps chosen where the floor under the share held them and the number of those
    /// selections, which bound the next such steps (zeros in checkpoints written before the bound).
    #[serde(default)]
    pub floor_step_cap: [f64; 2],
    /// The estimate's noise measured by the polishing iteration (relative to the solution), of which the
    /// fixed floor under the share is made (`None`: not measured at the last step, and in checkpoints
    /// written before it: the floor is then `FINE_STEP_FLOOR`).
    #[serde(default)]
    pub noise_level: Option<f64>,
    /// The constraint rows in force.
    pub active: Vec<bool>,
    /// Last accepted relative angle of each joint (for continuing angles past ±π).
    pub angle_reference: Vec<f64>,
    /// The counters so far.
    pub stats: Stats,
}

/// The Adams method's state: the Shampine–Gordon stepper with its difference table, the projection's
/// records or the coordinate partition, and the counters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AdamsCheckpoint {
    /// The stepper: solution, modified divided differences, order, step size, counters.
    pub stepper: AdamsStepper,
    /// The projections' records (with projection).
    pub drift: ProjectionDrift,
    /// The partition, its factors and the last evaluation (with coordinate partitioning).
    pub partition: Option<PartitionCheckpoint>,
    /// Evaluations of the accelerations.
    pub evaluations: usize,
    /// Factorizations of the KKT matrix.
    pub factorizations: usize,
    /// The constraint rows in force.
    pub active: Vec<bool>,
    /// Last accepted relative angle of each joint.
    pub angle_reference: Vec<f64>,
    /// The counters so far.
    pub stats: Stats,
}

/// The generalized-α method's state: the accepted state with its accelerations and `ã`, the last step
/// (for the step-size dependent predictor and the dense output), the stored parts of the iteration
/// matrix, and its counters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GeneralizedAlphaCheckpoint {
    /// Time of the last accepted step (s).
    pub t: f64,
    /// Step size planned for the next step (s).
    pub h: f64,
    /// Positions, velocities, accelerations, `ã` and multipliers at `t`.
    pub q: Vec<f64>,
    /// See [`q`](Self::q).
    pub v: Vec<f64>,
    /// See [`q`](Self::q).
    pub vdot: Vec<f64>,
    /// See [`q`](Self::q).
    pub a_tilde: Vec<f64>,
    /// See [`q`](Self::q).
    pub lambda: Vec<f64>,
    /// Start and size of the last step (s), the state at its start, its position increment.
    pub t_old: f64,
    /// See [`t_old`](Self::t_old).
    pub h_last: f64,
    /// See [`t_old`](Self::t_old).
    pub q_old: Vec<f64>,
    /// See [`t_old`](Self::t_old).
    pub v_old: Vec<f64>,
    /// See [`t_old`](Self::t_old).
    pub vdot_old: Vec<f64>,
    /// The size of the step before the last and the velocities at its start, of which the error estimate
    /// takes the curvature of the accelerations (0 and empty in a checkpoint written before they were
    /// kept: the accelerations' curvature then serves the first step).
    #[serde(default)]
    pub h_before_last: f64,
    /// See [`h_before_last`](Self::h_before_last).
    #[serde(default)]
    pub v_before_last: Vec<f64>,
    /// The multipliers at the start of the last step (empty in a checkpoint written before they were
    /// kept: the predictor then holds the multipliers for the first step).
    #[serde(default)]
    pub lambda_old: Vec<f64>,
    /// See [`t_old`](Self::t_old).
    pub d_last: Vec<f64>,
    /// The finite-difference parts were evaluated during the step in progress.
    pub derivatives_current: bool,
    /// Re-evaluate them at the next step's predictor.
    pub refresh_next: bool,
    /// The floor under a step's share of the tolerance (see [`BdfCheckpoint::share_floor`]).
    #[serde(default)]
    pub share_floor: [f64; 2],
    /// The rounding floor of the Newton increments (see [`BdfCheckpoint::newton_rounding`]).
    #[serde(default)]
    pub newton_rounding: [f64; 2],
    /// The last error constant and the averaged trend of its logarithm, from which the next step is
    /// chosen (a checkpoint written before it was kept: none, the first step after it takes the estimate
    /// as it is).
    #[serde(default)]
    pub error_trend: [f64; 2],
    /// The step size the factors in use were made for (`None`: none in use), and the matrix they were
    /// made of, in the order of its sparse pattern (empty when none).
    #[serde(default)]
    pub factored_h: Option<f64>,
    /// See [`factored_h`](Self::factored_h).
    #[serde(default)]
    pub factored_matrix: Vec<f64>,
    /// The pivot sequence the iteration matrix's factorizations keep (the position of each row in the
    /// pivot order; `None` when none is kept, or the matrix is small enough to be factored dense): the
    /// factors depend on it, so a resumed run loads it to take the same steps to the last bit. A
    /// checkpoint written before kept pivots has none: the resumed run's first factorization chooses
    /// its pivots afresh, and its steps agree with the uninterrupted run's within the tolerances only.
    #[serde(default)]
    pub kept_pivots: Option<Vec<usize>>,
    /// The convergence rate of the Newton iterations, from which the next step's is predicted.
    #[serde(default)]
    pub newton_rate: RateMonitor,
    /// The convergence rate of the iterations with fresh factors of finite-difference parts evaluated
    /// at an earlier step, from which it is predicted whether they must be re-evaluated (a checkpoint
    /// written before it was kept: none measured).
    #[serde(default)]
    pub derivative_rate: RateMonitor,
    /// At a fixed step: the predictor holds `v̇` and `λ` for the rest of the run, an iteration from their
    /// extrapolation having failed (a checkpoint written before: `false`, the predictor extrapolates).
    #[serde(default)]
    pub predictor_held: bool,
    /// Stiffness and damping parts of the iteration matrix, in the order of its sparse pattern.
    pub stiffness: Vec<f64>,
    /// See [`stiffness`](Self::stiffness).
    pub damping: Vec<f64>,
    /// The constraint Jacobian at `t`, by rows of its pattern.
    pub start_jacobian: Vec<f64>,
    /// The constraint rows in force.
    pub active: Vec<bool>,
    /// Last accepted relative angle of each joint.
    pub angle_reference: Vec<f64>,
    /// The counters so far.
    pub stats: Stats,
}

/// Why a checkpoint cannot be taken of an integrator or restored into one.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum CheckpointError {
    /// The checkpoint is of another method.
    #[error("the checkpoint is of the {found} method, the simulation uses {expected}")]
    Method {
        /// The simulation's method.
        expected: &'static str,
        /// The checkpoint's method.
        found: &'static str,
    },
    /// An array's length does not fit the model.
    #[error("the checkpoint does not fit the model: it has {found} values for {what}, the model {expected}")]
    Size {
        /// Which array.
        what: &'static str,
        /// The model's length.
        expected: usize,
        /// The checkpoint's length.
        found: usize,
    },
    /// The checkpoint's configuration differs from the integrator's (e.g. the Adams method's constraint
    /// handling).
    #[error("{0}")]
    Unsupported(String),
}

/// Checks that `found` has the length `expected`.
pub(crate) fn check_len(what: &'static str, expected: usize, found: usize) -> Result<(), CheckpointError> {
    if expected == found {
        Ok(())
    } else {
        Err(CheckpointError::Size { what, expected, found })
    }
}

/// Serde for an `f64` that may be infinite or NaN (JSON has no such numbers): finite values as
/// numbers, the others as the strings `inf`, `-inf`, `NaN`.
pub(crate) mod extended_float {
    use serde::{Deserialize, Deserializer, Serializer};

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Repr {
        Number(f64),
        Text(String),
    }

    /// Writes `x`.
    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if x.is_finite() {
            s.serialize_f64(*x)
        } else if x.is_nan() {
            s.serialize_str("NaN")
        } else if *x > 0.0 {
            s.serialize_str("inf")
        } else {
            s.serialize_str("-inf")
        }
    }

    /// Reads what [`serialize`] wrote.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        match Repr::deserialize(d)? {
            Repr::Number(x) => Ok(x),
            Repr::Text(t) => match t.as_str() {
                "inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                "NaN" => Ok(f64::NAN),
                other => Err(serde::de::Error::custom(format!("expected a number, inf, -inf or NaN, got '{other}'"))),
            },
        }
    }
}

/// [`extended_float`] for a vector.
pub(crate) mod extended_floats {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    struct Float(#[serde(with = "super::extended_float")] f64);

    /// Writes `xs`.
    pub fn serialize<S: Serializer>(xs: &[f64], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(xs.iter().map(|&x| Float(x)))
    }

    /// Reads what [`serialize`] wrote.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Ok(Vec::<Float>::deserialize(d)?.into_iter().map(|f| f.0).collect())
    }
}
