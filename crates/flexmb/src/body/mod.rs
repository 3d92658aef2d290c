//! Bodies and the markers fixed on them: rigid bodies, and flexible bodies in modal form (a rigid
//! body whose frame carries modal coordinates).

mod high_mode_damping;
mod marker;
mod modal;
mod rigid;

pub use high_mode_damping::HighModeDamping;
pub use marker::Marker;
pub use modal::{LumpedNode, ModalBody, ModalDamping, ModalError, ModalInvariants, ModalNode};
pub use rigid::{InitialState, RigidBody};

#[cfg(test)]
mod modal_tests;
