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
use crate::stage::{applied_forces, body_mass_entries, constraint_equations, inertia_forces, jacobian_entries, kinematics, measures};

/// Result of an acceleration solve.
#[derive(Clone, Debug)]
pub struct Accelerations {
    /// `v̇ = [R̈, ω̄̇, ä]` per body.
    pub vdot: Vec<f64>,
    /// Multipliers, one per constraint row.
    pub lambda: Vec<f64>,
}

/// The KKT matrix with its fixed pattern, factored at each call.
pub struct AccelerationSolver {
    lu: SparseLu,
    rhs: Vec<f64>,
    zero_v: Vec<f64>,
    pub result: Accelerations,
}

impl AccelerationSolver {
    pub fn new(model: &Model) -> Self {
        let l = &model.layout;
        let n = l.nv + l.nc;
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
        Self {
            lu: SparseLu::new(n, entries),
            rhs: vec![0.0; n],
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
        let l = &model.layout;
        kinematics(model, data, q, v);
        constraint_equations(model, data, t);
        measures(model, data);
        applied_forces(model, data, t);
        inertia_forces(model, data, &self.zero_v);
        self.lu.clear();
        for b in 0..model.bodies.len() {
            let vo = l.v_offset[b];
            let lu = &mut self.lu;
            body_mass_entries(model, data, b, |r, c, m| lu.add(vo + r, vo + c, m));
        }
        let nv = l.nv;
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
        for k in 0..nv {
            self.rhs[k] = data.applied[k] - data.inertia[k];
        }
        for (r, terms) in data.equations.iter().enumerate() {
            self.rhs[nv + r] = if active[r] { -terms.accel_bias } else { 0.0 };
        }
        self.lu.factor()?;
        self.lu.solve_in_place(&mut self.rhs)?;
        self.result.vdot.copy_from_slice(&self.rhs[..nv]);
        self.result.lambda.copy_from_slice(&self.rhs[nv..]);
        Ok(&self.result)
    }
}
