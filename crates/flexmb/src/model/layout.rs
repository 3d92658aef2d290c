//! Where each body's coordinates and each joint's equations sit in the global vectors.
//!
//! Per body: positions `q_b = [R (3), p (4), a (m)]`, velocities `v_b = [Ṙ (3, global), ω̄ (3, body),
//! ȧ (m)]`, with `m` modal coordinates for a flexible body and none for a rigid one.
//! Constraint rows are numbered joint by joint. The integrator's unknown vector is
//! `y = [q, v, λ, μ]` with `λ` the joint multipliers (one per constraint row) and `μ` the stabilizing
//! multipliers of the position constraints (one per joint row, then one per body for `pᵀp = 1`).

use std::ops::Range;

use crate::joint::Equation;
use crate::model::{BodyId, JointId};

/// The coordinate and equation layout of a model.
///
/// The methods that take a [`BodyId`], a [`JointId`] or a coordinate index return `None` for one that
/// is not of this model.
#[derive(Clone, Debug)]
pub struct Layout {
    /// Number of position coordinates (7 + m per body).
    pub nq: usize,
    /// Number of velocity coordinates (6 + m per body).
    pub nv: usize,
    /// Number of constraint equations (rows of `Φ`).
    pub nc: usize,
    pub(crate) q_offset: Vec<usize>,
    pub(crate) v_offset: Vec<usize>,
    /// Number of modal coordinates of each body (0 for a rigid body).
    pub(crate) modes: Vec<usize>,
    pub(crate) joint_rows: Vec<Range<usize>>,
    pub(crate) equations: Vec<(JointId, Equation)>,
}

impl Layout {
    pub(crate) fn new(modes: &[usize], joint_equations: &[Vec<Equation>]) -> Self {
        let mut q_offset = Vec::with_capacity(modes.len());
        let mut v_offset = Vec::with_capacity(modes.len());
        let (mut nq, mut nv) = (0, 0);
        for &m in modes {
            q_offset.push(nq);
            v_offset.push(nv);
            nq += 7 + m;
            nv += 6 + m;
        }
        let mut joint_rows = Vec::with_capacity(joint_equations.len());
        let mut equations = Vec::new();
        for (j, eqs) in joint_equations.iter().enumerate() {
            let start = equations.len();
            equations.extend(eqs.iter().map(|e| (JointId(j), *e)));
            joint_rows.push(start..equations.len());
        }
        Self {
            nq,
            nv,
            nc: equations.len(),
            q_offset,
            v_offset,
            modes: modes.to_vec(),
            joint_rows,
            equations,
        }
    }

    /// Number of bodies.
    pub fn n_bodies(&self) -> usize {
        self.q_offset.len()
    }
    /// Position coordinates of body `b` (`R`, `p`, then its modal coordinates); `None` for an id that
    /// is not one of this model's bodies.
    pub fn q_range(&self, b: BodyId) -> Option<Range<usize>> {
        (b.0 < self.n_bodies()).then(|| self.q_span(b.0))
    }
    /// Velocity coordinates of body `b` (`Ṙ`, `ω̄`, then its modal rates); `None` for an id that is not
    /// one of this model's bodies.
    pub fn v_range(&self, b: BodyId) -> Option<Range<usize>> {
        (b.0 < self.n_bodies()).then(|| self.v_span(b.0))
    }
    /// [`q_range`](Self::q_range) of the engine's own body index `b`.
    pub(crate) fn q_span(&self, b: usize) -> Range<usize> {
        self.q_offset[b]..self.q_offset[b] + 7 + self.modes[b]
    }
    /// [`v_range`](Self::v_range) of the engine's own body index `b`.
    pub(crate) fn v_span(&self, b: usize) -> Range<usize> {
        self.v_offset[b]..self.v_offset[b] + 6 + self.modes[b]
    }
    /// Number of modal coordinates of body `b` (0 for a rigid body); `None` for an id that is not one of
    /// this model's bodies.
    pub fn modes(&self, b: BodyId) -> Option<usize> {
        self.modes.get(b.0).copied()
    }
    /// The modal coordinates `a` of body `b` within `q`; `None` for an id that is not one of this model's
    /// bodies.
    pub fn modal_q_range(&self, b: BodyId) -> Option<Range<usize>> {
        let start = self.q_offset.get(b.0)? + 7;
        Some(start..start + self.modes[b.0])
    }
    /// The modal rates `ȧ` of body `b` within `v`; `None` for an id that is not one of this model's bodies.
    pub fn modal_v_range(&self, b: BodyId) -> Option<Range<usize>> {
        let start = self.v_offset.get(b.0)? + 6;
        Some(start..start + self.modes[b.0])
    }
    /// The body whose velocity coordinates hold index `k` of `v`; `None` for `k` not below `nv`.
    pub fn body_of_velocity(&self, k: usize) -> Option<BodyId> {
        (k < self.nv).then(|| BodyId(self.velocity_body(k)))
    }
    /// The body whose position coordinates hold index `k` of `q`; `None` for `k` not below `nq`.
    pub fn body_of_position(&self, k: usize) -> Option<BodyId> {
        (k < self.nq).then(|| BodyId(self.position_body(k)))
    }
    /// [`body_of_velocity`](Self::body_of_velocity) of an index the engine knows is below `nv`.
    pub(crate) fn velocity_body(&self, k: usize) -> usize {
        self.v_offset.partition_point(|&o| o <= k) - 1
    }
    /// [`body_of_position`](Self::body_of_position) of an index the engine knows is below `nq`.
    pub(crate) fn position_body(&self, k: usize) -> usize {
        self.q_offset.partition_point(|&o| o <= k) - 1
    }
    /// Constraint rows of joint `j`; `None` for an id that is not one of this model's joints.
    pub fn joint_rows(&self, j: JointId) -> Option<Range<usize>> {
        self.joint_rows.get(j.0).cloned()
    }
    /// Number of position-level constraints of the stabilized system: joint rows plus one
    /// normalization `pᵀp = 1` per body.
    pub fn n_position_constraints(&self) -> usize {
        self.nc + self.n_bodies()
    }
}
