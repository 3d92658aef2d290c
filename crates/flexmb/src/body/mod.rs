//! Bodies and the markers fixed on them: rigid bodies, and flexible bodies in modal form (a rigid
//! body whose frame carries modal coordinates).

mod marker;
mod modal;
mod rigid;

pub use marker::Marker;
pub use modal::{LumpedNode, ModalBody, ModalDamping, ModalError, ModalInvariants, ModalNode};
pub use rigid::{InitialState, RigidBody};

#[cfg(test)]
mod modal_tests;
