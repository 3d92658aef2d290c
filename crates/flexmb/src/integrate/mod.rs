//! Time integration of the equations of motion.
//!
//! Three methods implement [`Integrator`], chosen by [`Method`] (with each method's own settings), all
//! reading one record of error tolerances and step limits, [`Tolerances`]. The default is a variable-order (1–5),
//! variable-step BDF in the backward-difference form of Shampine and Reichelt (the MATLAB `ode15s`
//! family, with `κ = 0`, i.e. true BDF as in DASSL) applied to the stabilized index-2 form of the
//! equations (see [`crate::stage`] `residual`).
//!
//! Why this formulation: the Gear–Gupta–Leimkuhler form keeps both position and velocity constraints
//! satisfied to Newton tolerance at every step (no drift, no projection step that the error control
//! would not see), its multipliers `λ, μ` are index-2 variables that BDF handles reliably when they are
//! left out of the error test, and unlike the index-3 form it needs no step-size dependent scaling and
//! keeps the velocities accurate. The cost is `nc + nb` extra unknowns `μ`, which are zero at the
//! solution.
//!
//! [`GeneralizedAlpha`] (`Method::GeneralizedAlpha`) is the generalized-α method of
//! Chung and Hulbert in Arnold and Brüls's form, with stabilized index-2 constraints, the positions updated
//! on their Lie group and the step size from a local error estimate: second order, with numerical damping
//! of unresolved high frequencies set by `ρ∞` (see [`generalized_alpha`]).
//!
//! [`Adams`] (`Method::Adams`) is the seed's non-stiff method: the variable-order (1–12), variable-step
//! Adams–Bashforth–Moulton PECE method of Shampine and Gordon on `y = [q, v]`, the constraints kept by
//! projection after each step or by generalized coordinate partitioning (see [`adams`]).

pub mod adams;
mod bdf;
mod bdf_finest_tolerance;
mod checkpoint;
mod config;
mod convergence_rate;
mod diagnosis;
mod error;
mod error_norm;
mod floor_step_cap;
pub mod generalized_alpha;
mod integrator;
mod iteration_matrix;
mod newton;
mod newton_rounding;
mod noise_floor;
pub(crate) mod passed_rounding;
mod rounding_level;
pub(crate) mod share_floor;
pub(crate) mod singular_position;
mod stats;
mod tolerance_span;
mod tolerances;

pub use adams::{Adams, AdamsConfig};
pub use bdf::Bdf;
pub(crate) use checkpoint::{check_len, extended_float};
pub use checkpoint::{AdamsCheckpoint, BdfCheckpoint, CheckpointError, GeneralizedAlphaCheckpoint, IntegratorCheckpoint};
pub use config::{BdfConfig, Method};
pub use config::GeneralizedAlphaConfig;
pub use convergence_rate::RateMonitor;
pub(crate) use error::AttemptFailure;
pub use error::IntegrationError;
pub use generalized_alpha::GeneralizedAlpha;
pub use integrator::Integrator;
pub use stats::Stats;
pub use tolerance_span::ToleranceSpan;
pub use tolerances::Tolerances;

/// The smallest step an integrator takes at `t` toward `t_stop` before it declares a failure: ten
/// units of rounding of the time scale `max(|t|, |t_stop|)`, as in DASSL (`|t|` alone when there is no
/// stop). At t = 0, `|t|` alone let the step halve down to 1e-307.
pub(crate) fn smallest_step(t: f64, t_stop: f64) -> f64 {
    let time_scale = if t_stop.is_finite() { t.abs().max(t_stop.abs()) } else { t.abs() };
    10.0 * (time_scale * f64::EPSILON).max(f64::MIN_POSITIVE)
}

/// The start of an integrator, a state and its accelerations, of `model`'s sizes: one made for another
/// model is an initial-condition error that names what does not fit.
pub(crate) fn check_start(
    model: &crate::Model,
    state: &crate::analysis::State,
    accelerations: &crate::analysis::Accelerations,
) -> Result<(), IntegrationError> {
    crate::model::SizeCheck::new(model)
        .state(state)
        .and_then(|c| c.accelerations(accelerations))
        .map(|_| ())
        .map_err(|e| IntegrationError::InitialConditions { t: state.t, reason: e.to_string() })
}
