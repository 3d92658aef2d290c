//! Accelerations and multipliers from the index-1 system (Haug 1989, eq. 11.1.19):
//!
//! ```text
//! [ M   Bᵀ ] [ v̇ ]   [ Q − h(q, v) ]
//! [ B   0  ] [ λ ] = [ γ           ]
//! ```
//! the dynamics end of the forward pipeline ([`forward`](crate::stage::forward)): used for consistent
//! initial accelerations, at output times for accelerations and reaction forces, and by the Adams
//! integrator at every evaluation of its ODE. A switched-off (redundant) row gets the equation `λ_k = 0`.

use crate::data::Data;
use crate::linalg::{SingularMatrix, SparseLu};
use crate::model::{Model, SizeCheck, SizeMismatch};
use crate::stage::geometric_stiffening::interface_reaction_entries;
use crate::stage::{inertia_jacobian_entries, jacobian_entries, run_force_stages, run_kinematic_stages};

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
/// equation `z_r = 0`.
struct KktMatrix {
    lu: SparseLu,
    nv: usize,
}

impl KktMatrix {
    fn new(model: &Model) -> Self {
        let l = &model.layout;
        let mut entries = Vec::new();
        for b in 0..model.bodies.len() {
            let range = l.v_span(b);
            for r in range.clone() {
                for c in range.clone() {
                    entries.push((r, c));
                }
            }
        }
        for (j, joint) in model.joints.iter().enumerate() {
            for b in model.joint_bodies(joint).into_iter().flatten() {
                for row in l.joint_rows[j].clone() {
                    for k in l.v_span(b.0) {
                        entries.push((l.nv + row, k));
                        entries.push((k, l.nv + row));
                    }
                }
            }
        }
        Self { lu: SparseLu::new(l.nv + l.nc, entries), nv: l.nv }
    }

    /// Assembles and factors the matrix at the state of the last kinematics and constraint stages.
    fn factor(&mut self, model: &Model, data: &Data, active: &[bool]) -> Result<(), SingularMatrix> {
        let nv = self.nv;
        self.lu.clear();
        for b in 0..model.bodies.len() {
            let vo = model.layout.v_offset[b];
            let lu = &mut self.lu;
            inertia_jacobian_entries(model, data, b, |r, c, m| lu.add(vo + r, vo + c, m));
        }
        let lu = &mut self.lu;
        jacobian_entries(model, data, |r, c, x| {
            if active[r] {
                lu.add(nv + r, c, x);
                lu.add(c, nv + r, x);
            }
        });
        interface_reaction_entries(model, data, |r, c, x| {
            if active[r] {
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
    fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        self.lu.solve_in_place(rhs)
    }
}

/// Why the accelerations could not be solved.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AccelerationError {
    /// `[M Bᵀ; B 0]` is singular: the constraints in force are dependent, or a body has no mass.
    #[error(transparent)]
    Singular(#[from] SingularMatrix),
    /// The solver, the workspace or a vector is not of the model's sizes.
    #[error(transparent)]
    SizeMismatch(#[from] SizeMismatch),
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

    /// Solves for `v̇, λ` at `(t, q, v)`: the [`kinematic_stages`](crate::stage::kinematic_stages), the
    /// matrix factored there, the [`force_stages`](crate::stage::force_stages) with `v̇ = 0` for the right
    /// side `Q − h`; leaves the stages evaluated at that state in `data`. `active` says which constraint
    /// rows are in force (one per row). A solver, `data` or vectors not of `model`'s sizes are an error.
    pub fn solve(
        &mut self,
        model: &Model,
        data: &mut Data,
        t: f64,
        q: &[f64],
        v: &[f64],
        active: &[bool],
    ) -> Result<&Accelerations, AccelerationError> {
        SizeCheck::new(model)
            .len("the acceleration solver (velocity coordinates and constraint rows)", self.rhs.len(), model.layout.nv + model.layout.nc)?
            .data(data)?
            .positions(q)?
            .velocities("velocities v", v)?
            .rows("the rows in force (active)", active.len())?;
        Ok(self.solve_at(model, data, t, q, v, active)?)
    }

    /// [`solve`](Self::solve) on arguments of the model's sizes (the engine's own calls).
    pub(crate) fn solve_at(
        &mut self,
        model: &Model,
        data: &mut Data,
        t: f64,
        q: &[f64],
        v: &[f64],
        active: &[bool],
    ) -> Result<&Accelerations, SingularMatrix> {
        run_kinematic_stages(model, data, t, q, v);
        self.factor(model, data, active)?;
        self.solve_factored(model, data, t, active)
    }

    /// Assembles and factors the matrix at the state of the kinematic stages in `data`.
    pub(crate) fn factor(&mut self, model: &Model, data: &Data, active: &[bool]) -> Result<(), SingularMatrix> {
        self.kkt.factor(model, data, active)
    }

    /// Runs the force stages (with `v̇ = 0`) at the state of the kinematic stages in `data` and solves for
    /// `v̇, λ` with the current factors (made at that state or, for a chord iteration, at a recent one).
    pub(crate) fn solve_factored(
        &mut self,
        model: &Model,
        data: &mut Data,
        t: f64,
        active: &[bool],
    ) -> Result<&Accelerations, SingularMatrix> {
        let nv = model.layout.nv;
        run_force_stages(model, data, t, &self.zero_v);
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

    /// Solves `[M Bᵀ; B 0] x = rhs` in place with the current factors.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        self.kkt.solve_in_place(rhs)
    }
}
