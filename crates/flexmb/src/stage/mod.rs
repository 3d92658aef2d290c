//! The forward pipeline, one stage per file, each `fn(&Model, &mut Data, …)`:
//! kinematics → constraints → measures → forces → inertia, run in that order by [`forward`] (the
//! [`kinematic_stages`], then the [`force_stages`]); the DAE residual, the index-1 acceleration solve
//! ([`AccelerationSolver`](crate::analysis::AccelerationSolver)) and the linearization are built on it.

mod constraints;
mod coordinate_rates;
mod energy;
mod equations_of_motion;
mod forces;
mod forward;
pub(crate) mod geometric_stiffening;
mod inertia;
mod kinematics;
mod lie_group;
mod measures;
mod modal;
mod multiplier_jacobian;
mod residual;
mod state_jacobian;

pub(crate) use constraints::{add_jacobian_transpose, constraint_equations, jacobian_entries};
pub(crate) use coordinate_rates::{euler_parameter_rates, normalize_euler_parameters, position_rates};
pub use energy::Energy;
pub(crate) use equations_of_motion::equations_of_motion;
pub(crate) use energy::{energy, nonconservative_power};
pub(crate) use forces::applied_forces;
pub use forward::{force_stages, forward, kinematic_stages};
pub(crate) use forward::{run_force_stages, run_forward, run_kinematic_stages};
pub(crate) use inertia::{body_mass_entries, inertia_forces, inertia_jacobian_entries};
pub use kinematics::{BodyState, MarkerState};
pub(crate) use kinematics::kinematics;
pub(crate) use lie_group::{quaternion_product, retract, right_jacobian, right_jacobian_inverse, rotation_quaternion};
pub(crate) use measures::{measure_value, measures, update_angle_references};
pub use modal::ModalState;
pub(crate) use modal::modal_row;
pub(crate) use multiplier_jacobian::multiplier_jacobian_entries;
pub(crate) use residual::{residual, YLayout};
pub(crate) use state_jacobian::StateJacobian;
