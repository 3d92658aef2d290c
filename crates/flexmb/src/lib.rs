//! # flexmb — dynamics of articulated structures
//!
//! Bodies located by a position `R` and Euler parameters `p`, joined by joints built from Haug's
//! primitive constraints and loaded by force elements; the equations of motion in Lagrange-multiplier
//! form are integrated by a variable-order, variable-step BDF with error control.
//!
//! The pipeline: a [`ModelBuilder`] makes an immutable [`Model`]; a [`Data`] holds all scratch
//! state; the stages in [`stage`] evaluate kinematics, constraints, forces and inertia; the
//! [`analysis`] module assembles the mechanism, finds consistent velocities and runs the dynamics with
//! the integrators of [`integrate`].
//!
//! [`ModelBuilder`] checks every element as it is added and returns a [`ModelError`](model::ModelError)
//! that names it (an id the builder did not hand out, a name used twice, a mass, inertia, frame or
//! spring constant out of range): its documentation builds a pendulum.
//!
//! A run is an [`analysis::Simulation`]: built from a shared model (`Arc<Model>`) and
//! [`analysis::SimulationSettings`], stepped ([`step`](analysis::Simulation::step),
//! [`advance_to`](analysis::Simulation::advance_to), [`run`](analysis::Simulation::run)) with its
//! outputs streamed to any [`analysis::OutputSink`] (an [`analysis::OutputTable`] keeps them in
//! memory by column name), its state, parameters and report readable between steps, and its complete
//! state saved as an [`analysis::SimulationCheckpoint`] (serde) and resumed with the same steps. See
//! `examples/pendulum.rs`.
//!
//! References: E. J. Haug, *Computer Aided Kinematics and Dynamics of Mechanical Systems* (1989);
//! W. S. Yoo and E. J. Haug, *Dynamics of Articulated Structures* (1986); K. E. Brenan, S. L. Campbell,
//! L. R. Petzold, *Numerical Solution of Initial-Value Problems in DAEs* (1996); L. F. Shampine and
//! M. W. Reichelt, *The MATLAB ODE Suite* (1997); C. W. Gear, B. Leimkuhler, G. K. Gupta, *Automatic
//! integration of Euler–Lagrange equations with constraints* (1985).

#![warn(missing_docs)]

pub mod analysis;
pub mod body;
mod data;
pub mod force;
pub mod function;
pub mod integrate;
pub mod joint;
pub mod linalg;
pub mod math;
pub mod measure;
pub mod model;
pub mod stage;
#[cfg(test)]
mod test_support;

pub use data::Data;
pub use model::{Model, ModelBuilder};
