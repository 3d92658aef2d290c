//! Accelerations and multipliers from the index-1 system (Haug 1989, eq. 11.1.19):
//!
//! ```text
//! [ M   Bᵀ ] [ v̇ ]   [ Q − h(q, v) ]
//! [ B   0  ] [ λ ] = [ γ           ]
//! ```
//! used for consistent initial accelerations and, at output times, for accelerations and reaction forces.
//! A switched-off (redundant) row gets the equation `λ_k = 0`.

use crate::data::Data;
use crate::linalg::{SingularMatrix, SparseLu};
use crate::model::Model;
use crate::model::BodyId;
use crate::stage::{body_mass_entries, forward, jacobian_entries};

/// Result of an acceleration solve.
#[derive(Clone, Debug)]
pub struct Accelerations {
    /// `v̇ = [R̈, ω̄̇, ä]` per body.
    pub vdot: Vec<f64>,
    /// Multipliers, one per constraint row.
    pub lambda: Vec<f64>,
}

/// The matrix `[M Bᵀ; B 0]` on its fixed sparse pattern (the mass block of every body, the Jacobian
/// blocks of every joint), refactored at each state; a switched-off (redundant) row `r` gets the
/// equation `z_r = 0`. Shared by the acceleration solve and the Adams integrator.
pub(crate) struct KktMatrix {
    lu: SparseLu,
    nv: usize,
}

impl KktMatrix {
    pub(crate) fn new(model: &Model) -> Self {
        let l = &model.layout;
        let mut entries = Vec::new();
        for b in 0..model.bodies.len() {
            let range = l.v_range(BodyId(b));
            for r in range.clone() {
                for c in range.clone() {
                    entries.push((r, c));
                }
            }
        }
        for (j, joint) in model.joints.iter().enumerate() {
            for b in model.joint_bodies(joint).into_iter().flatten() {
                for row in l.joint_rows[j].clone() {
                    for k in l.v_range(b) {
                        entries.push((l.nv + row, k));
                        entries.push((k, l.nv + row));
                    }
                }
            }
        }
        Self { lu: SparseLu::new(l.nv + l.nc, entries), nv: l.nv }
    }

    /// Assembles and factors the matrix at the state of the last kinematics and constraint stages.
    pub(crate) fn factor(&mut self, model: &Model, data: &Data, active: &[bool]) -> Result<(), SingularMatrix> {
        let nv = self.nv;
        self.lu.clear();
        for b in 0..model.bodies.len() {
            let vo = model.layout.v_offset[b];
            let lu = &mut self.lu;
            body_mass_entries(model, data, b, |r, c, m| lu.add(vo + r, vo + c, m));
        }
        let lu = &mut self.lu;
        jacobian_entries(model, data, |r, c, x| {
            if active[r] {
                lu.add(nv + r, c, x);
                lu.add(c, nv + r, x);
            }
        });
        for (r, a) in active.iter().enumerate() {
            if !a {
                self.lu.add(nv + r, nv + r, 1.0);
            }
        }
        self.lu.factor()
    }

    /// Solves with the current factors in place.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        self.lu.solve_in_place(rhs)
    }
}

/// The KKT matrix with its fixed pattern, factored at each call.
pub struct AccelerationSolver {
    kkt: KktMatrix,
    rhs: Vec<f64>,
    zero_v: Vec<f64>,
    /// The last solution.
    pub result: Accelerations,
}

impl AccelerationSolver {
    /// A solver for `model`, its matrix pattern made once.
    pub fn new(model: &Model) -> Self {
        let l = &model.layout;
        Self {
            kkt: KktMatrix::new(model),
            rhs: vec![0.0; l.nv + l.nc],
            zero_v: vec![0.0; l.nv],
            result: Accelerations { vdot: vec![0.0; l.nv], lambda: vec![0.0; l.nc] },
        }
    }

    /// Solves for `v̇, λ` at `(t, q, v)`; leaves the stages evaluated at that state in `data`.
    pub fn solve(
        &mut self,
        model: &Model,
        data: &mut Data,
        t: f64,
        q: &[f64],
        v: &[f64],
        active: &[bool],
    ) -> Result<&Accelerations, SingularMatrix> {
        let nv = model.layout.nv;
        forward(model, data, t, q, v, &self.zero_v);
        self.kkt.factor(model, data, active)?;
        for k in 0..nv {
            self.rhs[k] = data.applied[k] - data.inertia[k];
        }
        for (r, terms) in data.equations.iter().enumerate() {
            self.rhs[nv + r] = if active[r] { -terms.accel_bias } else { 0.0 };
        }
        self.kkt.solve_in_place(&mut self.rhs)?;
        self.result.vdot.copy_from_slice(&self.rhs[..nv]);
        self.result.lambda.copy_from_slice(&self.rhs[nv..]);
        Ok(&self.result)
    }
}
