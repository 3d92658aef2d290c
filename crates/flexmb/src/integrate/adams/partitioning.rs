//! Generalized coordinate partitioning (Wehage and Haug 1982), the DADS code's way: only the
//! independent coordinates `w` of `q` and their rates are integrated, `y = [w, ẇ]`; every evaluation
//! of `f(t, y)` recovers the dependent coordinates `u` from `Φ̂(u, w, t) = [Φ; pᵀp − 1] = 0` by Newton,
//! their rates from `Φ̂_u u̇ = −Φ̂_w ẇ − Φ̂_t`, the velocities `v = [Ṙ, ω̄ = 2 G ṗ, ȧ]`, the accelerations
//! `v̇` from the index-1 system, and returns `[ẇ, ẅ]` with `p̈ = ½ Gᵀ(p) ω̄̇ + ½ Gᵀ(ṗ) ω̄`.
//!
//! **The partition** comes from Gaussian elimination with full pivoting on `Φ̂_q` (the active
//! constraint rows and one normalization row per body, against all of `q`, Euler parameters and modal
//! coordinates included): the pivot columns are dependent, the rest independent. It is re-chosen, and
//! the integration restarted at order 1 from the last accepted state, when the pivots of `Φ̂_u`
//! degrade (smallest over largest below a tenth of its value when chosen) or the Newton iteration
//! for `u` fails.
//!
//! The constraints hold to Newton tolerance at every evaluation, not only after the steps; the price
//! is a Newton solve (chord iterations with the last factors of `Φ̂_u`, dense here (`faer`'s LU), plus one
//! refactorization at the converged point for the velocities) inside every evaluation, a restart of
//! the multistep history at every repartition, and an error test that sees only the independent
//! coordinates. See [`super::mechanism`] for the comparison with projection.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::{MatMut, MatRef};

use crate::data::Data;
use crate::integrate::{check_len, CheckpointError};
use crate::linalg::{lu_in_place, lu_in_place_scratch, solve_with_lu};
use crate::math::euler_parameters::g_matrix;
use crate::math::{Vec3, Vec4};

use crate::model::Model;
use crate::stage::{jacobian_entries, run_kinematic_stages, kinematics, update_angle_references};

use super::kkt::Kkt;
use crate::integrate::error_norm::{error_weight, root_mean_square};
use crate::stage::position_rates;
use super::method::{EvaluationFailure, OdeSystem};

/// Newton iterations for the dependent coordinates of one evaluation, at most.
const NEWTON_ITERATIONS: usize = 8;
/// Converged when the last correction is this small in the error-tolerance units (noise in `f` is
/// amplified by the high differences, so the dependent coordinates are solved far below the tolerance).
const CORRECTION_TOLERANCE: f64 = 1e-6;
/// Repartition when the pivot ratio of `Φ̂_u` falls below this fraction of its value when chosen.
const DEGRADATION: f64 = 0.1;

const NO_CONVERGENCE: EvaluationFailure =
    EvaluationFailure("the Newton iteration for the dependent coordinates does not converge");
const SINGULAR_PARTITION: EvaluationFailure =
    EvaluationFailure("the Jacobian of the dependent coordinates is singular (the partition has degraded)");

/// Counters of the partitioned integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PartitionReport {
    /// Number of independent coordinates (positions; as many rates).
    pub independent: usize,
    /// Partitions chosen after the first (each restarts the integration at order 1).
    pub repartitions: usize,
    /// Newton iterations for the dependent coordinates over all evaluations.
    pub newton_iterations: usize,
    /// Dense factorizations of `Φ̂_u`.
    pub factorizations: usize,
}

/// A dense square matrix (column-major) with its LU factors, factored in place by `faer`'s LU with
/// partial pivoting ([`lu_in_place`]); kept in a checkpoint.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct DenseLu {
    n: usize,
    a: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
}

impl DenseLu {
    fn new(n: usize) -> Self {
        Self { n, a: vec![0.0; n * n], perm: vec![0; n], perm_inv: vec![0; n] }
    }

    /// Factors `a` in place with the workspace `buffer` ([`lu_in_place_scratch`]); returns the smallest
    /// over the largest pivot magnitude (0 if singular).
    fn factor(&mut self, buffer: &mut MemBuffer) -> f64 {
        let a = MatMut::from_column_major_slice_mut(&mut self.a, self.n, self.n);
        lu_in_place(a, &mut self.perm, &mut self.perm_inv, MemStack::new(buffer))
    }

    /// Solves `A x = b` in place with the factors; `work` is of the matrix's dimension.
    fn solve(&self, b: &mut [f64], work: &mut [f64]) {
        solve_with_lu(MatRef::from_column_major_slice(&self.a, self.n, self.n), &self.perm, b, work);
    }
}

/// The mechanism on its independent coordinates and their rates.
pub(super) struct PartitionedMechanism {
    pub model: Arc<Model>,
    pub data: Data,
    pub kkt: Kkt,
    nq: usize,
    nv: usize,
    /// The active constraint rows; `Φ̂` is these then one normalization row per body.
    rows: Vec<usize>,
    m: usize,
    /// `B` over the active rows, dense, scratch of [`jacobian`](Self::jacobian).
    b_dense: Vec<f64>,
    /// Scratch of the partition choice, `m × nq`, and the columns already chosen.
    elimination: Vec<f64>,
    chosen: Vec<bool>,
    phi: Vec<f64>,
    /// Workspace of the factorization of `Φ̂_u` and of its solves.
    lu_buffer: MemBuffer,
    lu_work: Vec<f64>,
    rtol: f64,
    atol: f64,
    pub evaluations: usize,
    /// The partition, its factors, the last evaluation and the last accepted state: what a checkpoint
    /// keeps.
    pub state: PartitionCheckpoint,
}

/// The state of the partitioned mechanism between two steps: the partition with its factors, the last
/// evaluation (the Newton iteration's start for the next), the last accepted state and the counters.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PartitionCheckpoint {
    /// The independent and the dependent position coordinates.
    pub(super) independent: Vec<usize>,
    dependent: Vec<usize>,
    /// `Φ̂_q`, `m × nq`, row-major, at the positions of the last [`jacobian`](PartitionedMechanism::jacobian) call.
    jac: Vec<f64>,
    /// LU factors of `Φ̂_u` (the dependent columns).
    lu: DenseLu,
    factored: bool,
    /// The factors, positions and rates of the last evaluation, kept while an output is computed.
    saved_lu: DenseLu,
    saved_q: Vec<f64>,
    saved_qdot: Vec<f64>,
    pivot_ratio_at_partition: f64,
    /// The state of the last evaluation: time, `q`, `q̇`, `v`, `v̇`, `q̈`.
    t: f64,
    pub(super) q: Vec<f64>,
    qdot: Vec<f64>,
    pub(super) v: Vec<f64>,
    vdot: Vec<f64>,
    qddot: Vec<f64>,
    /// The last accepted state.
    pub(super) q_accepted: Vec<f64>,
    pub(super) v_accepted: Vec<f64>,
    qdot_accepted: Vec<f64>,
    t_accepted: f64,
    pub(super) report: PartitionReport,
    /// The partition should be re-chosen at the last accepted state.
    pub(super) needs_repartition: bool,
}

impl PartitionedMechanism {
    /// Continues from `c`, taken of the same model's partitioned mechanism.
    pub fn restore(&mut self, c: &PartitionCheckpoint) -> Result<(), CheckpointError> {
        let current = &self.state;
        for (what, expected, found) in [
            ("the coordinates of the partition", self.nq, c.independent.len() + c.dependent.len()),
            ("the constraint Jacobian", current.jac.len(), c.jac.len()),
            ("the dependent coordinates' factors", current.lu.a.len(), c.lu.a.len()),
            ("the saved factors", current.saved_lu.a.len(), c.saved_lu.a.len()),
            ("the positions", self.nq, c.q.len()),
            ("the velocities", self.nv, c.v.len()),
        ] {
            check_len(what, expected, found)?;
        }
        self.state.clone_from(c);
        Ok(())
    }

    /// The system at a consistent state `(t, q, v)` with the partition chosen there.
    pub fn new(
        model: Arc<Model>,
        active: Vec<bool>,
        rtol: f64,
        atol: f64,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> Result<Self, EvaluationFailure> {
        let l = &model.layout;
        let (nq, nv) = (l.nq, l.nv);
        let rows: Vec<usize> = (0..l.nc).filter(|r| active[*r]).collect();
        let m = rows.len() + model.bodies.len();
        let mut qdot = vec![0.0; nq];
        position_rates(&model, q, v, &mut qdot);
        let mut s = Self {
            data: Data::new(&model),
            kkt: Kkt::new(&model, active),
            model,
            nq,
            nv,
            b_dense: vec![0.0; rows.len() * nv],
            rows,
            m,
            elimination: vec![0.0; m * nq],
            chosen: vec![false; nq],
            phi: vec![0.0; m],
            lu_buffer: MemBuffer::new(lu_in_place_scratch(m)),
            lu_work: vec![0.0; m],
            rtol,
            atol,
            evaluations: 0,
            state: PartitionCheckpoint {
                independent: Vec::with_capacity(nq),
                dependent: Vec::with_capacity(nq),
                jac: vec![0.0; m * nq],
                lu: DenseLu::new(m),
                factored: false,
                saved_lu: DenseLu::new(m),
                saved_q: vec![0.0; nq],
                saved_qdot: vec![0.0; nq],
                pivot_ratio_at_partition: 1.0,
                t,
                q: q.to_vec(),
                qdot: qdot.clone(),
                v: v.to_vec(),
                vdot: vec![0.0; nv],
                qddot: vec![0.0; nq],
                q_accepted: q.to_vec(),
                v_accepted: v.to_vec(),
                qdot_accepted: qdot,
                t_accepted: t,
                report: PartitionReport::default(),
                needs_repartition: false,
            },
        };
        // Joint angles continue from the initial configuration.
        kinematics(&s.model, &mut s.data, q, v);
        s.data.angle_reference.fill(0.0);
        update_angle_references(&s.model, &mut s.data);
        s.choose_partition()?;
        s.state.report.repartitions = 0;
        Ok(s)
    }

    /// Number of integrated variables, `2 × independent`.
    pub fn len(&self) -> usize {
        2 * self.state.independent.len()
    }

    /// `y = [w, ẇ]` of the last accepted state.
    pub fn accepted_y(&self, y: &mut [f64]) {
        let nd = self.state.independent.len();
        for (i, &c) in self.state.independent.iter().enumerate() {
            y[i] = self.state.q_accepted[c];
            y[nd + i] = self.state.qdot_accepted[c];
        }
    }

    /// Chooses the partition at the last accepted state (Gaussian elimination with full pivoting on
    /// `Φ̂_q`) and factors `Φ̂_u` there.
    pub fn choose_partition(&mut self) -> Result<(), EvaluationFailure> {
        let (m, nq) = (self.m, self.nq);
        self.state.q.copy_from_slice(&self.state.q_accepted);
        self.state.v.copy_from_slice(&self.state.v_accepted);
        self.state.qdot.copy_from_slice(&self.state.qdot_accepted);
        self.state.t = self.state.t_accepted;
        self.constraint_stage(self.state.t);
        self.jacobian();
        self.elimination.copy_from_slice(&self.state.jac);
        let e = &mut self.elimination;
        self.state.dependent.clear();
        self.chosen.fill(false);
        for k in 0..m {
            let (mut best, mut bi, mut bj) = (0.0_f64, k, usize::MAX);
            for i in k..m {
                for j in 0..nq {
                    if !self.chosen[j] && e[i * nq + j].abs() > best {
                        (best, bi, bj) = (e[i * nq + j].abs(), i, j);
                    }
                }
            }
            if bj == usize::MAX {
                return Err(SINGULAR_PARTITION);
            }
            for j in 0..nq {
                e.swap(k * nq + j, bi * nq + j);
            }
            let pivot = e[k * nq + bj];
            for i in k + 1..m {
                let f = e[i * nq + bj] / pivot;
                if f != 0.0 {
                    for j in 0..nq {
                        e[i * nq + j] -= f * e[k * nq + j];
                    }
                }
            }
            self.state.dependent.push(bj);
            self.chosen[bj] = true;
        }
        self.state.dependent.sort_unstable();
        self.state.independent.clear();
        self.state.independent.extend((0..nq).filter(|c| self.state.dependent.binary_search(c).is_err()));
        self.state.pivot_ratio_at_partition = self.factor_dependent()?;
        self.state.report.repartitions += 1;
        self.state.report.independent = self.state.independent.len();
        self.state.needs_repartition = false;
        Ok(())
    }

    /// Kinematics and constraint stages at `self.state.q` (velocities `self.state.v`), and `Φ̂` into `phi`.
    fn constraint_stage(&mut self, t: f64) {
        run_kinematic_stages(&self.model, &mut self.data, t, &self.state.q, &self.state.v);
        let nr = self.rows.len();
        for (k, &r) in self.rows.iter().enumerate() {
            self.phi[k] = self.data.equations[r].phi;
        }
        for b in 0..self.model.bodies.len() {
            let qo = self.model.layout.q_offset[b];
            self.phi[nr + b] = (3..7).map(|k| self.state.q[qo + k].powi(2)).sum::<f64>() - 1.0;
        }
    }

    /// `Φ̂_q` at `self.state.q` (after [`constraint_stage`](Self::constraint_stage)): `Φ_R = B_Ṙ`,
    /// `Φ_p = B_ω̄ 2G(p)`, `Φ_a = B_ȧ`, `(pᵀp)_p = 2pᵀ`.
    fn jacobian(&mut self) {
        let (nq, nv, nr) = (self.nq, self.nv, self.rows.len());
        let l = &self.model.layout;
        self.b_dense.fill(0.0);
        let (b_dense, rows) = (&mut self.b_dense, &self.rows);
        jacobian_entries(&self.model, &self.data, |r, c, x| {
            if let Ok(k) = rows.binary_search(&r) {
                b_dense[k * nv + c] += x;
            }
        });
        self.state.jac.fill(0.0);
        for b in 0..self.model.bodies.len() {
            let (qo, vo, modes) = (l.q_offset[b], l.v_offset[b], l.modes[b]);
            let p = Vec4::new(self.state.q[qo + 3], self.state.q[qo + 4], self.state.q[qo + 5], self.state.q[qo + 6]);
            let g2 = 2.0 * g_matrix(&p);
            for k in 0..nr {
                let brow = &self.b_dense[k * nv..(k + 1) * nv];
                let jrow = &mut self.state.jac[k * nq..(k + 1) * nq];
                jrow[qo..qo + 3].copy_from_slice(&brow[vo..vo + 3]);
                for c in 0..4 {
                    jrow[qo + 3 + c] = (0..3).map(|j| brow[vo + 3 + j] * g2[(j, c)]).sum();
                }
                jrow[qo + 7..qo + 7 + modes].copy_from_slice(&brow[vo + 6..vo + 6 + modes]);
            }
            for c in 0..4 {
                self.state.jac[(nr + b) * nq + qo + 3 + c] = 2.0 * p[c];
            }
        }
    }

    /// Factors `Φ̂_u` (the dependent columns of `jac`); returns its pivot ratio.
    fn factor_dependent(&mut self) -> Result<f64, EvaluationFailure> {
        let (m, nq) = (self.m, self.nq);
        for i in 0..m {
            for (j, &c) in self.state.dependent.iter().enumerate() {
                self.state.lu.a[j * m + i] = self.state.jac[i * nq + c];
            }
        }
        self.state.report.factorizations += 1;
        let ratio = self.state.lu.factor(&mut self.lu_buffer);
        self.state.factored = ratio > 0.0;
        if self.state.factored {
            Ok(ratio)
        } else {
            Err(SINGULAR_PARTITION)
        }
    }

    /// Newton (chord, with the last factors of `Φ̂_u`) for the dependent coordinates at `self.state.q`.
    fn solve_dependent_positions(&mut self, t: f64) -> Result<(), EvaluationFailure> {
        let mut previous = f64::INFINITY;
        for _ in 0..NEWTON_ITERATIONS {
            self.constraint_stage(t);
            let residual = self.phi.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
            if !residual.is_finite() {
                break;
            }
            if residual == 0.0 {
                return Ok(());
            }
            if !self.state.factored {
                self.jacobian();
                self.factor_dependent()?;
            }
            let mut dx = std::mem::take(&mut self.phi);
            dx.iter_mut().for_each(|x| *x = -*x);
            self.state.lu.solve(&mut dx, &mut self.lu_work);
            let mut sum = 0.0;
            let mut at_round_off = true;
            for (j, &c) in self.state.dependent.iter().enumerate() {
                sum += (dx[j] / error_weight(self.atol, self.rtol, self.state.q[c])).powi(2);
                at_round_off &= dx[j].abs() <= 16.0 * f64::EPSILON * self.state.q[c].abs().max(1.0);
                self.state.q[c] += dx[j];
            }
            self.phi = dx;
            self.state.report.newton_iterations += 1;
            let size = root_mean_square(sum, self.m);
            // Converged far below the tolerance, or as far as the precision allows.
            if size <= CORRECTION_TOLERANCE || at_round_off {
                return Ok(());
            }
            // Slow contraction with old factors: refactor at the current point.
            if size > 0.2 * previous {
                self.state.factored = false;
            }
            previous = size;
        }
        self.state.needs_repartition = true;
        Err(NO_CONVERGENCE)
    }

    /// From `y = [w, ẇ]` at `t`: the dependent coordinates and rates, `v`; with `accelerations`, also
    /// `v̇` and `q̈`.
    fn complete_state(&mut self, t: f64, y: &[f64], accelerations: bool) -> Result<(), EvaluationFailure> {
        let nd = self.state.independent.len();
        // Start the Newton iteration from the last state moved along its rates.
        let dt = t - self.state.t;
        for &c in &self.state.dependent {
            self.state.q[c] += dt * self.state.qdot[c];
        }
        for (i, &c) in self.state.independent.iter().enumerate() {
            self.state.q[c] = y[i];
        }
        self.state.t = t;
        self.solve_dependent_positions(t)?;
        // Φ̂_u at the converged positions, for the rates (and the next chord iterations).
        self.constraint_stage(t);
        self.jacobian();
        let ratio = self.factor_dependent()?;
        if ratio < DEGRADATION * self.state.pivot_ratio_at_partition {
            self.state.needs_repartition = true;
        }
        // Φ̂_u u̇ = −Φ̂_t − Φ̂_w ẇ.
        let (nq, nr) = (self.nq, self.rows.len());
        for (i, &c) in self.state.independent.iter().enumerate() {
            self.state.qdot[c] = y[nd + i];
        }
        for i in 0..self.m {
            let phi_t = if i < nr { self.data.equations[self.rows[i]].phi_t } else { 0.0 };
            let jw: f64 = self.state.independent.iter().map(|&c| self.state.jac[i * nq + c] * self.state.qdot[c]).sum();
            self.phi[i] = -phi_t - jw;
        }
        let mut rates = std::mem::take(&mut self.phi);
        self.state.lu.solve(&mut rates, &mut self.lu_work);
        for (j, &c) in self.state.dependent.iter().enumerate() {
            self.state.qdot[c] = rates[j];
        }
        self.phi = rates;
        // v = [Ṙ, 2 G(p) ṗ, ȧ].
        let l = &self.model.layout;
        for b in 0..self.model.bodies.len() {
            let (qo, vo, modes) = (l.q_offset[b], l.v_offset[b], l.modes[b]);
            let p = Vec4::new(self.state.q[qo + 3], self.state.q[qo + 4], self.state.q[qo + 5], self.state.q[qo + 6]);
            let p_rate = Vec4::new(self.state.qdot[qo + 3], self.state.qdot[qo + 4], self.state.qdot[qo + 5], self.state.qdot[qo + 6]);
            let w = 2.0 * g_matrix(&p) * p_rate;
            self.state.v[vo..vo + 3].copy_from_slice(&self.state.qdot[qo..qo + 3]);
            self.state.v[vo + 3..vo + 6].copy_from_slice(w.as_slice());
            self.state.v[vo + 6..vo + 6 + modes].copy_from_slice(&self.state.qdot[qo + 7..qo + 7 + modes]);
        }
        if !accelerations {
            return Ok(());
        }
        run_kinematic_stages(&self.model, &mut self.data, t, &self.state.q, &self.state.v);
        self.kkt.factor(&self.model, &self.data)?;
        self.kkt.accelerations(&self.model, &mut self.data, t, &mut self.state.vdot)?;
        self.evaluations += 1;
        // q̈ = [R̈, ½ Gᵀ(p) ω̄̇ + ½ Gᵀ(ṗ) ω̄, ä].
        for b in 0..self.model.bodies.len() {
            let (qo, vo, modes) = (l.q_offset[b], l.v_offset[b], l.modes[b]);
            let p = Vec4::new(self.state.q[qo + 3], self.state.q[qo + 4], self.state.q[qo + 5], self.state.q[qo + 6]);
            let p_rate = Vec4::new(self.state.qdot[qo + 3], self.state.qdot[qo + 4], self.state.qdot[qo + 5], self.state.qdot[qo + 6]);
            let w = Vec3::new(self.state.v[vo + 3], self.state.v[vo + 4], self.state.v[vo + 5]);
            let w_rate = Vec3::new(self.state.vdot[vo + 3], self.state.vdot[vo + 4], self.state.vdot[vo + 5]);
            let p_acc = 0.5 * g_matrix(&p).transpose() * w_rate + 0.5 * g_matrix(&p_rate).transpose() * w;
            self.state.qddot[qo..qo + 3].copy_from_slice(&self.state.vdot[vo..vo + 3]);
            self.state.qddot[qo + 3..qo + 7].copy_from_slice(p_acc.as_slice());
            self.state.qddot[qo + 7..qo + 7 + modes].copy_from_slice(&self.state.vdot[vo + 6..vo + 6 + modes]);
        }
        Ok(())
    }

    /// Positions and velocities from the interpolated `y` at `t` (between steps, for outputs). Leaves
    /// the state the next step starts from as it was, so that outputs do not change the steps.
    pub fn positions_and_velocities(&mut self, t: f64, y: &[f64], q: &mut [f64], v: &mut [f64]) {
        self.state.saved_lu.a.copy_from_slice(&self.state.lu.a);
        self.state.saved_lu.perm.copy_from_slice(&self.state.lu.perm);
        self.state.saved_lu.perm_inv.copy_from_slice(&self.state.lu.perm_inv);
        let (factored, needs_repartition) = (self.state.factored, self.state.needs_repartition);
        self.state.saved_q.copy_from_slice(&self.state.q);
        self.state.saved_qdot.copy_from_slice(&self.state.qdot);
        let t_saved = self.state.t;
        // Start from the accepted state; a failure leaves the best iterate, which is reported as is.
        self.state.q.copy_from_slice(&self.state.q_accepted);
        self.state.qdot.copy_from_slice(&self.state.qdot_accepted);
        self.state.t = self.state.t_accepted;
        let _ = self.complete_state(t, y, false);
        q.copy_from_slice(&self.state.q);
        v.copy_from_slice(&self.state.v);
        std::mem::swap(&mut self.state.lu, &mut self.state.saved_lu);
        (self.state.factored, self.state.needs_repartition) = (factored, needs_repartition);
        self.state.q.copy_from_slice(&self.state.saved_q);
        self.state.qdot.copy_from_slice(&self.state.saved_qdot);
        self.state.t = t_saved;
    }
}

impl OdeSystem for PartitionedMechanism {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        self.complete_state(t, y, true)?;
        let nd = self.state.independent.len();
        dy[..nd].copy_from_slice(&y[nd..]);
        for (i, &c) in self.state.independent.iter().enumerate() {
            dy[nd + i] = self.state.qddot[c];
        }
        Ok(())
    }

    fn accept(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        self.rhs(t, y, dy)?;
        update_angle_references(&self.model, &mut self.data);
        self.state.q_accepted.copy_from_slice(&self.state.q);
        self.state.v_accepted.copy_from_slice(&self.state.v);
        self.state.qdot_accepted.copy_from_slice(&self.state.qdot);
        self.state.t_accepted = t;
        Ok(())
    }
}
