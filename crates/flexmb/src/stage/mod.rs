//! The forward pipeline, one stage per file, each `fn(&Model, &mut Data, …)`:
//! kinematics → constraints → measures → forces → inertia; the DAE residual and the index-1
//! acceleration solve are built from them.

mod constraints;
mod energy;
mod forces;
mod inertia;
mod kinematics;
mod measures;
mod modal;
mod residual;

pub(crate) use constraints::{add_jacobian_transpose, constraint_equations, jacobian_entries};
pub use energy::Energy;
pub(crate) use energy::{energy, nonconservative_power};
pub(crate) use forces::applied_forces;
pub(crate) use inertia::{body_mass_entries, inertia_forces};
pub use kinematics::{BodyState, MarkerState};
pub(crate) use kinematics::kinematics;
pub(crate) use measures::{measure_value, measures, update_angle_references};
pub use modal::ModalState;
pub(crate) use modal::modal_row;
pub(crate) use residual::{residual, YLayout};
