//! Bodies and the markers fixed on them: rigid bodies, and flexible bodies in modal form (a rigid
//! body whose frame carries modal coordinates).

mod geometric_stiffness;
mod high_mode_damping;
mod marker;
mod massless_motion;
mod modal;
mod rigid;

pub use geometric_stiffness::{inertia_load_factors, InterfaceGeometricStiffness, ModalGeometricStiffness, INERTIA_CASES, INTERFACE_CASES};
pub use high_mode_damping::HighModeDamping;
pub use marker::Marker;
pub use massless_motion::MasslessMotion;
pub use modal::{LumpedNode, ModalBody, ModalDamping, ModalError, ModalInvariants, ModalNode};
pub use rigid::{InitialState, RigidBody};

#[cfg(test)]
mod modal_tests;
