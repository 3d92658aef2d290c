//! What both ways of handling the constraints need: the index-1 system
//! `[M Bᵀ; B 0] [v̇; λ] = [Q − h; γ]` (Haug 1989, eq. 11.1.19) on a fixed sparse pattern, factored once
//! per state and solved for several right sides, and the kinematic map `q̇ = T(q) v`.

use crate::data::Data;
use crate::integrate::adams::method::EvaluationFailure;
use crate::analysis::AccelerationSolver;
use crate::model::Model;

pub(super) const SINGULAR: EvaluationFailure =
    EvaluationFailure("the mass–constraint matrix [M Bᵀ; B 0] is singular (dependent constraints or a massless body)");
pub(super) const NOT_FINITE: EvaluationFailure = EvaluationFailure("the accelerations are not finite");

/// `[M Bᵀ; B 0]` with its factors (the forward dynamics' [`AccelerationSolver`]); a redundant
/// (switched-off) row `r` gets the equation `z_r = 0`.
pub(super) struct Kkt {
    solver: AccelerationSolver,
    /// Right side and solution of the minimum-norm correction, length `nv + nc`.
    pub rhs: Vec<f64>,
    pub active: Vec<bool>,
    nv: usize,
    /// The factors are of some recent state (usable for chord iterations).
    pub factored: bool,
    pub factorizations: usize,
}

impl Kkt {
    pub fn new(model: &Model, active: Vec<bool>) -> Self {
        let l = &model.layout;
        Self {
            solver: AccelerationSolver::new(model),
            rhs: vec![0.0; l.nv + l.nc],
            active,
            nv: l.nv,
            factored: false,
            factorizations: 0,
        }
    }

    /// Assembles and factors the matrix at the positions of the last kinematics and constraint stages.
    pub fn factor(&mut self, model: &Model, data: &Data) -> Result<(), EvaluationFailure> {
        self.factorizations += 1;
        self.factored = false;
        self.solver.factor(model, data, &self.active).map_err(|_| SINGULAR)?;
        self.factored = true;
        Ok(())
    }

    /// `v̇` into `vdot` from the factored system, after the kinematics and constraint stages at `(q, v)`
    /// (runs the measure, force and inertia stages).
    pub fn accelerations(
        &mut self,
        model: &Model,
        data: &mut Data,
        t: f64,
        vdot: &mut [f64],
    ) -> Result<(), EvaluationFailure> {
        let acc = self.solver.solve_factored(model, data, t, &self.active).map_err(|_| SINGULAR)?;
        vdot.copy_from_slice(&acc.vdot);
        if vdot.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(NOT_FINITE)
        }
    }

    /// Solves `[M Bᵀ; B 0] [δv; z] = [0; r]` with the current factors, `r` over the constraint rows
    /// (zero on the switched-off ones) from `row_value`: the correction `δv` of least kinetic energy
    /// with `B δv = r`, left in `rhs[..nv]`.
    pub fn min_norm_correction(
        &mut self,
        data: &Data,
        row_value: impl Fn(&Data, usize) -> f64,
    ) -> Result<(), EvaluationFailure> {
        let nv = self.nv;
        self.rhs[..nv].fill(0.0);
        for r in 0..self.active.len() {
            self.rhs[nv + r] = if self.active[r] { row_value(data, r) } else { 0.0 };
        }
        self.solver.solve_in_place(&mut self.rhs).map_err(|_| SINGULAR)
    }
}

/// The largest `|Φ|` over the active rows (after the constraint stage).
pub(super) fn position_residual(data: &Data, active: &[bool]) -> f64 {
    data.equations.iter().zip(active).filter(|(_, a)| **a).fold(0.0, |m, (e, _)| m.max(e.phi.abs()))
}

/// `Φ̇ = B v + Φ_t` of constraint row `r` (after the kinematics and constraint stages).
pub(super) fn constraint_rate(model: &Model, data: &Data, r: usize) -> f64 {
    let joint = &model.joints[model.layout.equations[r].0 .0];
    data.equations[r].rate(&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0])
}
