//! Vectors and workspaces checked against the model they are used with: a state, a [`Data`] or a
//! solver made for another model is an error that says which, not an index out of bounds.

use crate::analysis::{Accelerations, State};
use crate::data::Data;
use crate::model::Model;

/// A vector or workspace whose size does not fit the model it was passed with (it was made for another
/// model, or has the wrong length).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} has {found} entries where model '{model}' needs {expected}: was it made for another model?")]
pub struct SizeMismatch {
    /// What was passed: `positions q`, `velocities v`, `the workspace Data (markers)`, …
    pub what: &'static str,
    /// Its size.
    pub found: usize,
    /// The model's size for it.
    pub expected: usize,
    /// The model's name.
    pub model: String,
}

/// The checks of one call's arguments against `model`, chained: `SizeCheck::new(model).data(data)?.positions(q)?`.
#[derive(Clone, Copy)]
pub(crate) struct SizeCheck<'m> {
    model: &'m Model,
}

impl<'m> SizeCheck<'m> {
    pub fn new(model: &'m Model) -> Self {
        Self { model }
    }

    /// `found` must equal `expected`.
    pub fn len(self, what: &'static str, found: usize, expected: usize) -> Result<Self, SizeMismatch> {
        if found == expected {
            Ok(self)
        } else {
            Err(SizeMismatch { what, found, expected, model: self.model.name.clone() })
        }
    }

    /// `data` was made by [`Data::new`] for this model.
    pub fn data(self, data: &Data) -> Result<Self, SizeMismatch> {
        let m = self.model;
        self.len("the workspace Data (bodies)", data.bodies.len(), m.bodies.len())?
            .len("the workspace Data (markers)", data.markers.len(), m.markers.len())?
            .len("the workspace Data (measures)", data.measures.len(), m.measures.len())?
            .len("the workspace Data (parameters)", data.parameters.len(), m.parameters.len())?
            .len("the workspace Data (joints)", data.angle_reference.len(), m.joints.len())?
            .len("the workspace Data (constraint rows)", data.equations.len(), m.layout.nc)?
            .len("the workspace Data (velocity coordinates)", data.applied.len(), m.layout.nv)?;
        for (b, modal) in data.modal.iter().enumerate() {
            self.len("the workspace Data (modal coordinates of a body)", modal.a.len(), m.layout.modes[b])?;
        }
        Ok(self)
    }

    /// Positions `q`, `nq` long.
    pub fn positions(self, q: &[f64]) -> Result<Self, SizeMismatch> {
        self.len("positions q", q.len(), self.model.layout.nq)
    }

    /// Velocities `v` (or any vector in velocity coordinates, `what`), `nv` long.
    pub fn velocities(self, what: &'static str, v: &[f64]) -> Result<Self, SizeMismatch> {
        self.len(what, v.len(), self.model.layout.nv)
    }

    /// One entry per constraint row (`active`, `λ`), `nc` long.
    pub fn rows(self, what: &'static str, len: usize) -> Result<Self, SizeMismatch> {
        self.len(what, len, self.model.layout.nc)
    }

    /// A state's positions, velocities and rows in force.
    pub fn state(self, state: &State) -> Result<Self, SizeMismatch> {
        self.positions(&state.q)?.velocities("velocities v", &state.v)?.rows("the rows in force (active)", state.active.len())
    }

    /// Accelerations `v̇` and multipliers `λ`.
    pub fn accelerations(self, acc: &Accelerations) -> Result<Self, SizeMismatch> {
        self.velocities("accelerations v̇", &acc.vdot)?.rows("multipliers λ", acc.lambda.len())
    }
}
