//! Bodies and the markers fixed on them.

mod marker;
mod rigid;

pub use marker::Marker;
pub use rigid::{InitialState, RigidBody};
