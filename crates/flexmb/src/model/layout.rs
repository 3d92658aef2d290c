//! Where each body's coordinates and each joint's equations sit in the global vectors.
//!
//! Per rigid body: positions `q_b = [R (3), p (4)]`, velocities `v_b = [Ṙ (3, global), ω̄ (3, body)]`.
//! Constraint rows are numbered joint by joint. The integrator's unknown vector is
//! `y = [q, v, λ, μ]` with `λ` the joint multipliers (one per constraint row) and `μ` the stabilizing
//! multipliers of the position constraints (one per joint row, then one per body for `pᵀp = 1`).

use std::ops::Range;

use crate::joint::Equation;
use crate::model::{BodyId, JointId};

/// The coordinate and equation layout of a model.
#[derive(Clone, Debug)]
pub struct Layout {
    /// Number of position coordinates (7 per rigid body).
    pub nq: usize,
    /// Number of velocity coordinates (6 per rigid body).
    pub nv: usize,
    /// Number of constraint equations (rows of `Φ`).
    pub nc: usize,
    pub(crate) q_offset: Vec<usize>,
    pub(crate) v_offset: Vec<usize>,
    pub(crate) joint_rows: Vec<Range<usize>>,
    pub(crate) equations: Vec<(JointId, Equation)>,
}

impl Layout {
    pub(crate) fn new(n_bodies: usize, joint_equations: &[Vec<Equation>]) -> Self {
        let q_offset = (0..n_bodies).map(|b| 7 * b).collect();
        let v_offset = (0..n_bodies).map(|b| 6 * b).collect();
        let mut joint_rows = Vec::with_capacity(joint_equations.len());
        let mut equations = Vec::new();
        for (j, eqs) in joint_equations.iter().enumerate() {
            let start = equations.len();
            equations.extend(eqs.iter().map(|e| (JointId(j), *e)));
            joint_rows.push(start..equations.len());
        }
        Self {
            nq: 7 * n_bodies,
            nv: 6 * n_bodies,
            nc: equations.len(),
            q_offset,
            v_offset,
            joint_rows,
            equations,
        }
    }

    /// Number of bodies.
    pub fn n_bodies(&self) -> usize {
        self.q_offset.len()
    }
    /// Position coordinates of body `b`.
    pub fn q_range(&self, b: BodyId) -> Range<usize> {
        self.q_offset[b.0]..self.q_offset[b.0] + 7
    }
    /// Velocity coordinates of body `b`.
    pub fn v_range(&self, b: BodyId) -> Range<usize> {
        self.v_offset[b.0]..self.v_offset[b.0] + 6
    }
    /// Constraint rows of joint `j`.
    pub fn joint_rows(&self, j: JointId) -> Range<usize> {
        self.joint_rows[j.0].clone()
    }
    /// Number of position-level constraints of the stabilized system: joint rows plus one
    /// normalization `pᵀp = 1` per body.
    pub fn n_position_constraints(&self) -> usize {
        self.nc + self.n_bodies()
    }
}
