//! The non-stiff method of the DADS code: a variable-order (1–12), variable-step Adams–Bashforth–
//! Moulton predictor–corrector with local error control, of the Shampine–Gordon class.
//!
//! - [`method`]: the method itself, a generic stepper for `ẏ = f(t, y)` ([`AdamsStepper`], the STEP and
//!   INTRP algorithms of Shampine and Gordon 1975), tested alone on ODEs with known solutions;
//! - `mechanism`: the method applied to a model as [`Adams`], an [`Integrator`](super::Integrator),
//!   by default (`projection`) on the state `y = [q, v]` with `q̇ = T(q) v` and `v̇` from the index-1
//!   (KKT) system, and after every accepted step the positions projected onto `Φ(q, t) = 0`, `pᵀp = 1`
//!   and the velocities onto `B v + Φ_t = 0`, both in the metric of the mass matrix; or
//!   (`partitioning`) by generalized coordinate partitioning as in DADS.
//!
//! **Statistics** ([`Stats`](super::Stats)): `steps`, `error_test_failures`; `newton_failures` are
//! attempts abandoned because the mass–constraint matrix was singular or the projection (or the
//! partition's Newton iteration) did not converge; `newton_iterations` are those of the projections (or
//! of the dependent coordinates); `residual_evaluations` count the evaluations of `f`, each one solve
//! of the index-1 system for `v̇` (two per accepted step, one per rejected attempt); `factorizations`
//! count the factorizations of `[M Bᵀ; B 0]` (one per evaluation; with partitioning also those of
//! `Φ̂_u`); `order_counts[k]` the steps at predictor order `k` (1–12); no Jacobian is evaluated.
//!
//! **Dense output**: the interpolating polynomial of the last step (INTRP) at any time in it; with
//! projection the interpolated state is projected onto the constraints as an accepted step is, with
//! partitioning the dependent coordinates are recovered from the interpolated independent
//! ones.

mod kkt;
mod mechanism;
pub mod method;
#[cfg(test)]
mod method_tests;
mod partitioning;
mod projection;
#[cfg(test)]
mod projection_tests;
mod rounding_projection;

pub use mechanism::Adams;
pub use method::{
    AdamsStepper, AttemptFailure, EvaluationFailure, OdeSystem, StepControl, StepFailure, StepperStats, MAX_ORDER,
};
pub use partitioning::{PartitionCheckpoint, PartitionReport};
pub use projection::ProjectionDrift;

/// Settings of the Adams method that the other methods do not share (tolerances, step limits and the
/// step count limit are in [`Tolerances`](super::Tolerances)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdamsConfig {
    /// Highest order `k` of the Adams–Bashforth predictor, 1 to 12; the Adams–Moulton corrector, with
    /// local extrapolation, is of order `k + 1`. Default 12, as in Shampine and Gordon's STEP.
    pub max_order: usize,
    /// How the constraints are kept. Default [`ConstraintHandling::Projection`].
    pub constraints: ConstraintHandling,
}

impl Default for AdamsConfig {
    fn default() -> Self {
        Self { max_order: MAX_ORDER, constraints: ConstraintHandling::Projection }
    }
}

/// How the Adams method keeps a mechanism on its constraints (see the module docs of `mechanism` for
/// the comparison).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ConstraintHandling {
    /// Integrate `y = [q, v]` and project positions and velocities onto the constraints after every
    /// accepted step (mass-matrix metric). The default.
    #[default]
    Projection,
    /// Generalized coordinate partitioning (Wehage and Haug 1982, the DADS code): integrate the
    /// independent coordinates and their rates, recover the dependent ones by Newton in every
    /// evaluation, re-choose the partition when it degrades.
    Partitioning,
}

impl AdamsConfig {
    /// Checks that the order limit is in 1..=12.
    pub fn validate(&self) -> Result<(), String> {
        if (1..=MAX_ORDER).contains(&self.max_order) {
            Ok(())
        } else {
            Err(format!("the Adams method's max_order must be 1 to {MAX_ORDER}, got {}", self.max_order))
        }
    }
}
