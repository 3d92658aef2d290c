//! Generalized coordinate partitioning (Wehage and Haug 1982), the DADS code's way: only the
//! independent coordinates `w` of `q` and their rates are integrated, `y = [w, ẇ]`; every evaluation
//! of `f(t, y)` recovers the dependent coordinates `u` from `Φ̂(u, w, t) = [Φ; pᵀp − 1] = 0` by Newton,
//! their rates from `Φ̂_u u̇ = −Φ̂_w ẇ − Φ̂_t`, the velocities `v = [Ṙ, ω̄ = 2 G ṗ, ȧ]`, the accelerations
//! `v̇` from the index-1 system, and returns `[ẇ, ẅ]` with `p̈ = ½ Gᵀ(p) ω̄̇ + ½ Gᵀ(ṗ) ω̄`.
//!
//! **The partition** comes from Gaussian elimination on `Φ̂_q` (the active constraint rows and one
//! normalization row per body, against all of `q`, Euler parameters and modal coordinates included),
//! with threshold full pivoting (every pivot at least a tenth of the largest entry left) and, among the
//! entries that pass, the one of least Markowitz cost ([`threshold_pivoting`]): the pivot columns are
//! dependent, the rest independent. It is re-chosen, and
//! the integration restarted at order 1 from the last accepted state, when the pivots of `Φ̂_u`
//! degrade (smallest over largest below a tenth of its value when chosen) or the Newton iteration
//! for `u` fails.
//!
//! **Sparse throughout**: `Φ̂_q` is kept by rows on the pattern of the joints' bodies (a row's
//! coordinates are those of the one or two bodies its joint connects), the elimination runs on the
//! rows with heaps of pivot candidates, its work linear in the chain's length (full pivoting's
//! choice among the joints' equal unit entries made it `O(m²)`), and `Φ̂_u` is a [`SparseLu`] with
//! kept pivots on the pattern of the dependent columns: its symbolic analysis once per partition, a
//! numeric refactorization at every evaluation (dense up to the kept-pivot matrices' dense limit, as
//! the small mechanisms' were). Above that
//! limit its rows are taken in the order of the elimination's pivots, so that its diagonal is the
//! pivots' entries: `SparseLu` puts the whole diagonal in the pattern, and in the rows' own order the
//! diagonal entry of a joint's row falls on a far body's coordinate, which ties the chain's ends
//! together and fills the factors (the chain of 1,024 rods cost 56 ms per step that way, growing
//! ×3 per doubling). So the cost of an evaluation grows with the bodies, not with their cube.
//!
//! The constraints hold to Newton tolerance at every evaluation, not only after the steps; the price
//! is a Newton solve (chord iterations with the last factors of `Φ̂_u`, plus one refactorization at the
//! converged point for the velocities) inside every evaluation, a restart of the multistep history at
//! every repartition, and an error test that sees only the independent coordinates. See
//! [`super::mechanism`] for the comparison with projection.

use std::sync::Arc;

use crate::data::Data;
use crate::integrate::{check_len, CheckpointError};
use crate::linalg::{threshold_pivoting, SingularMatrix, SparseLu, KEPT_PIVOTS_DENSE_LIMIT, PARTITION_THRESHOLD};
use crate::math::euler_parameters::g_matrix;
use crate::math::{Mat3x4, Vec3, Vec4};

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
    /// Factorizations of `Φ̂_u`.
    pub factorizations: usize,
}

/// The patterns of `B` (over the velocities) and of `Φ̂_q` (over the positions) by rows: a constraint
/// row holds the coordinates of its joint's bodies, a normalization row the body's Euler parameters.
struct JacobianPattern {
    /// `B`'s rows in force: start of each row in `b_cols`, and the velocity columns, ascending.
    b_ptr: Vec<usize>,
    b_cols: Vec<usize>,
    /// The bodies of each row in force, ascending, each once.
    row_bodies: Vec<Vec<usize>>,
    /// `Φ̂_q`: start of each row in `cols`, and the position columns, ascending.
    ptr: Vec<usize>,
    cols: Vec<usize>,
}

impl JacobianPattern {
    fn new(model: &Model, rows: &[usize]) -> Self {
        let l = &model.layout;
        let mut joint_of_row = vec![usize::MAX; l.nc];
        for (j, range) in l.joint_rows.iter().enumerate() {
            joint_of_row[range.clone()].iter_mut().for_each(|x| *x = j);
        }
        let (mut b_ptr, mut b_cols, mut row_bodies, mut ptr, mut cols) = (vec![0], Vec::new(), Vec::new(), vec![0], Vec::new());
        for &r in rows {
            let mut bodies: Vec<usize> = match model.joints.get(joint_of_row[r]) {
                Some(joint) => model.joint_bodies(joint).into_iter().flatten().map(|b| b.0).collect(),
                None => Vec::new(),
            };
            bodies.sort_unstable();
            bodies.dedup();
            for &b in &bodies {
                b_cols.extend(l.v_span(b));
                cols.extend(l.q_span(b));
            }
            b_ptr.push(b_cols.len());
            ptr.push(cols.len());
            row_bodies.push(bodies);
        }
        for b in 0..model.bodies.len() {
            cols.extend(l.q_offset[b] + 3..l.q_offset[b] + 7);
            ptr.push(cols.len());
        }
        Self { b_ptr, b_cols, row_bodies, ptr, cols }
    }

    /// The number of entries of `Φ̂_q`.
    fn nnz(&self) -> usize {
        self.cols.len()
    }
}

/// `Φ̂_u`, the dependent columns of `Φ̂_q`, on the pattern of a partition.
struct DependentMatrix {
    /// Its LU factors, and a second matrix on the same pattern for the outputs' evaluations.
    lu: SparseLu,
    output_lu: SparseLu,
    /// The place in `lu.values` of each entry of `Φ̂_q` (`usize::MAX` for an independent column).
    slot: Vec<usize>,
    /// Whether each position coordinate is dependent.
    is_dependent: Vec<bool>,
    /// The row of `lu` of each row of `Φ̂`, and a right side in `lu`'s rows.
    lu_row: Vec<usize>,
    work: Vec<f64>,
}

impl DependentMatrix {
    /// The matrix of the columns `dependent` (ascending) of `Φ̂_q`, each pivoted on the row
    /// `pivot_rows[j]` of `Φ̂` when the partition was chosen: its symbolic analysis.
    fn new(pattern: &JacobianPattern, nq: usize, dependent: &[usize], pivot_rows: &[usize]) -> Self {
        let m = pattern.ptr.len() - 1;
        let mut column = vec![usize::MAX; nq];
        dependent.iter().enumerate().for_each(|(j, &c)| column[c] = j);
        let mut lu_row: Vec<usize> = (0..m).collect();
        if m > KEPT_PIVOTS_DENSE_LIMIT && pivot_rows.len() == m {
            pivot_rows.iter().enumerate().for_each(|(j, &r)| lu_row[r] = j);
        }
        let lu_row = &lu_row;
        let entries = || {
            (0..m).flat_map(|i| (pattern.ptr[i]..pattern.ptr[i + 1]).map(move |e| (i, e)))
                .filter(|&(_, e)| column[pattern.cols[e]] != usize::MAX)
                .map(|(i, e)| (lu_row[i], column[pattern.cols[e]]))
        };
        let lu = SparseLu::with_kept_pivots(m, entries());
        let output_lu = SparseLu::with_kept_pivots(m, entries());
        let slot = (0..m)
            .flat_map(|i| (pattern.ptr[i]..pattern.ptr[i + 1]).map(move |e| (i, e)))
            .map(|(i, e)| match column[pattern.cols[e]] {
                usize::MAX => usize::MAX,
                j => lu.slot(lu_row[i], j).expect("an entry of the pattern"),
            })
            .collect();
        let is_dependent = column.iter().map(|&j| j != usize::MAX).collect();
        Self { lu, output_lu, slot, is_dependent, lu_row: lu_row.clone(), work: vec![0.0; m] }
    }

    /// The factors of `lu` made again in `output_lu` from its values and kept pivots (the same factors
    /// to the last bit); whether that succeeded.
    fn copy_to_output(&mut self) -> bool {
        self.output_lu.values.copy_from_slice(&self.lu.values);
        self.output_lu.keep_pivots(self.lu.kept_pivots()).is_ok() && self.output_lu.factor().is_ok()
    }

    /// Solves `Φ̂_u x = b` in place (`b` over the rows of `Φ̂`, `x` over the dependent coordinates).
    fn solve(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        for (&r, &b) in self.lu_row.iter().zip(rhs.iter()) {
            self.work[r] = b;
        }
        self.lu.solve_in_place(&mut self.work)?;
        rhs.copy_from_slice(&self.work);
        Ok(())
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
    /// The row in force of each constraint row (`usize::MAX` for a redundant one).
    row_in_force: Vec<usize>,
    m: usize,
    pattern: JacobianPattern,
    /// `B` over the active rows on its pattern, scratch of [`jacobian`](Self::jacobian).
    b_values: Vec<f64>,
    /// `2 G(p)` of each body, scratch of [`jacobian`](Self::jacobian).
    g2: Vec<Mat3x4>,
    /// `Φ̂_u` of the current partition, with its factors.
    dependent: DependentMatrix,
    phi: Vec<f64>,
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
    /// The independent and the dependent position coordinates, and the row of `Φ̂` each dependent
    /// one was pivoted on.
    pub(super) independent: Vec<usize>,
    dependent: Vec<usize>,
    pivot_rows: Vec<usize>,
    /// `Φ̂_q` on its pattern (by rows: the joints' bodies' coordinates, then each body's Euler
    /// parameters), at the positions of the last [`jacobian`](PartitionedMechanism::jacobian) call.
    jac: Vec<f64>,
    /// Whether `Φ̂_u`'s factors are of a recent state (usable for chord iterations); a checkpoint
    /// holds its values and kept pivots, and the factors are made again from them on restore.
    factored: bool,
    dependent_values: Vec<f64>,
    kept_pivots: Option<Vec<usize>>,
    /// The positions and rates of the last evaluation, kept while an output is computed.
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

impl PartitionCheckpoint {
    /// The kept pivot sequence of `Φ̂_u`'s factors (the position of each row in the pivot order), if
    /// the matrix is above the dense limit and holds one.
    pub fn kept_pivots(&self) -> Option<&[usize]> {
        self.kept_pivots.as_deref()
    }
}

impl PartitionedMechanism {
    /// The state between two steps, with the values and kept pivots of `Φ̂_u`'s factors.
    pub fn checkpoint(&self) -> PartitionCheckpoint {
        let mut c = self.state.clone();
        c.dependent_values = self.dependent.lu.values.clone();
        c.kept_pivots = self.dependent.lu.kept_pivots().map(<[usize]>::to_vec);
        c
    }

    /// Continues from `c`, taken of the same model's partitioned mechanism: the partition's `Φ̂_u`
    /// analysed again and refactored from the values and pivots kept, the same factors to the last bit.
    pub fn restore(&mut self, c: &PartitionCheckpoint) -> Result<(), CheckpointError> {
        for (what, expected, found) in [
            ("the coordinates of the partition", self.nq, c.independent.len() + c.dependent.len()),
            ("the dependent coordinates", self.m, c.dependent.len()),
            ("the constraint Jacobian", self.pattern.nnz(), c.jac.len()),
            ("the positions", self.nq, c.q.len()),
            ("the velocities", self.nv, c.v.len()),
        ] {
            check_len(what, expected, found)?;
        }
        let mut seen = vec![false; self.nq];
        let partition_error = || CheckpointError::Unsupported("the checkpoint's coordinate partition is not one of the model's coordinates".into());
        for &k in c.independent.iter().chain(&c.dependent) {
            if k >= self.nq || std::mem::replace(&mut seen[k], true) {
                return Err(partition_error());
            }
        }
        let mut rows = vec![false; self.m];
        for &r in &c.pivot_rows {
            if r >= self.m || std::mem::replace(&mut rows[r], true) {
                return Err(partition_error());
            }
        }
        if !c.dependent.is_sorted() || c.pivot_rows.len() != self.m {
            return Err(partition_error());
        }
        let mut dependent = DependentMatrix::new(&self.pattern, self.nq, &c.dependent, &c.pivot_rows);
        check_len("the dependent coordinates' matrix", dependent.lu.values.len(), c.dependent_values.len())?;
        dependent.lu.values.copy_from_slice(&c.dependent_values);
        dependent.lu.keep_pivots(c.kept_pivots.as_deref()).map_err(|_| {
            CheckpointError::Unsupported("the checkpoint's pivots of the dependent coordinates' matrix do not fit its partition".into())
        })?;
        if c.factored && !(dependent.lu.factor().is_ok() && dependent.copy_to_output()) {
            return Err(CheckpointError::Unsupported("the checkpoint's dependent coordinates' matrix is singular".into()));
        }
        self.dependent = dependent;
        self.state.clone_from(c);
        self.state.dependent_values.clear();
        self.state.kept_pivots = None;
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
        let mut row_in_force = vec![usize::MAX; l.nc];
        rows.iter().enumerate().for_each(|(k, &r)| row_in_force[r] = k);
        let m = rows.len() + model.bodies.len();
        let pattern = JacobianPattern::new(&model, &rows);
        let nnz = pattern.nnz();
        let mut qdot = vec![0.0; nq];
        position_rates(&model, q, v, &mut qdot);
        let mut s = Self {
            data: Data::new(&model),
            kkt: Kkt::new(&model, active),
            nq,
            nv,
            b_values: vec![0.0; pattern.b_cols.len()],
            g2: vec![Mat3x4::zeros(); model.bodies.len()],
            dependent: DependentMatrix::new(&pattern, nq, &[], &[]),
            pattern,
            model,
            rows,
            row_in_force,
            m,
            phi: vec![0.0; m],
            rtol,
            atol,
            evaluations: 0,
            state: PartitionCheckpoint {
                independent: Vec::with_capacity(nq),
                dependent: Vec::with_capacity(nq),
                pivot_rows: Vec::new(),
                jac: vec![0.0; nnz],
                factored: false,
                dependent_values: Vec::new(),
                kept_pivots: None,
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

    /// Chooses the partition at the last accepted state (Gaussian elimination with threshold full
    /// pivoting on `Φ̂_q`, [`threshold_pivoting`]), analyses `Φ̂_u`'s pattern and factors it there.
    pub fn choose_partition(&mut self) -> Result<(), EvaluationFailure> {
        let nq = self.nq;
        self.state.q.copy_from_slice(&self.state.q_accepted);
        self.state.v.copy_from_slice(&self.state.v_accepted);
        self.state.qdot.copy_from_slice(&self.state.qdot_accepted);
        self.state.t = self.state.t_accepted;
        self.constraint_stage(self.state.t);
        self.jacobian();
        let pattern = &self.pattern;
        let mut pivots =
            threshold_pivoting(nq, &pattern.ptr, &pattern.cols, &self.state.jac, PARTITION_THRESHOLD).ok_or(SINGULAR_PARTITION)?;
        pivots.sort_unstable_by_key(|&(_, c)| c);
        self.state.dependent = pivots.iter().map(|&(_, c)| c).collect();
        self.state.pivot_rows = pivots.iter().map(|&(r, _)| r).collect();
        self.state.independent.clear();
        self.state.independent.extend((0..nq).filter(|c| self.state.dependent.binary_search(c).is_err()));
        self.dependent = DependentMatrix::new(&self.pattern, nq, &self.state.dependent, &self.state.pivot_rows);
        self.state.pivot_ratio_at_partition = self.factor_dependent()?;
        // The outputs' matrix grows its factors' storage now, not inside a step.
        self.dependent.copy_to_output();
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
        let nr = self.rows.len();
        let l = &self.model.layout;
        self.b_values.fill(0.0);
        let (b_values, row_in_force, pattern) = (&mut self.b_values, &self.row_in_force, &self.pattern);
        jacobian_entries(&self.model, &self.data, |r, c, x| {
            let k = row_in_force[r];
            if k != usize::MAX {
                let row = pattern.b_ptr[k]..pattern.b_ptr[k + 1];
                let s = pattern.b_cols[row.clone()].binary_search(&c).expect("an entry of B on its joint's bodies");
                b_values[row.start + s] += x;
            }
        });
        let jac = &mut self.state.jac;
        for b in 0..self.model.bodies.len() {
            let qo = l.q_offset[b];
            let p = Vec4::new(self.state.q[qo + 3], self.state.q[qo + 4], self.state.q[qo + 5], self.state.q[qo + 6]);
            self.g2[b] = 2.0 * g_matrix(&p);
            let start = pattern.ptr[nr + b];
            for c in 0..4 {
                jac[start + c] = 2.0 * p[c];
            }
        }
        for (k, bodies) in pattern.row_bodies.iter().enumerate() {
            let (mut jo, mut bo) = (pattern.ptr[k], pattern.b_ptr[k]);
            for &b in bodies {
                let (modes, g2) = (l.modes[b], &self.g2[b]);
                let brow = &self.b_values[bo..bo + 6 + modes];
                let jrow = &mut jac[jo..jo + 7 + modes];
                jrow[..3].copy_from_slice(&brow[..3]);
                for c in 0..4 {
                    jrow[3 + c] = (0..3).map(|j| brow[3 + j] * g2[(j, c)]).sum();
                }
                jrow[7..].copy_from_slice(&brow[6..]);
                (jo, bo) = (jo + 7 + modes, bo + 6 + modes);
            }
        }
    }

    /// Factors `Φ̂_u` (the dependent columns of `jac`); returns its pivot ratio.
    fn factor_dependent(&mut self) -> Result<f64, EvaluationFailure> {
        let d = &mut self.dependent;
        d.lu.clear();
        for (&slot, &x) in d.slot.iter().zip(&self.state.jac) {
            if slot != usize::MAX {
                d.lu.values[slot] = x;
            }
        }
        self.state.report.factorizations += 1;
        self.state.factored = d.lu.factor().is_ok();
        if self.state.factored {
            // A matrix with kept pivots shows its pivots.
            Ok(d.lu.pivot_ratio().unwrap_or(1.0))
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
            let solved = self.dependent.solve(&mut dx);
            if solved.is_err() {
                self.phi = dx;
                self.state.needs_repartition = true;
                return Err(SINGULAR_PARTITION);
            }
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
        let nr = self.rows.len();
        for (i, &c) in self.state.independent.iter().enumerate() {
            self.state.qdot[c] = y[nd + i];
        }
        let (pattern, is_dependent) = (&self.pattern, &self.dependent.is_dependent);
        for i in 0..self.m {
            let phi_t = if i < nr { self.data.equations[self.rows[i]].phi_t } else { 0.0 };
            let jw: f64 = (pattern.ptr[i]..pattern.ptr[i + 1])
                .filter(|&e| !is_dependent[pattern.cols[e]])
                .map(|e| self.state.jac[e] * self.state.qdot[pattern.cols[e]])
                .sum();
            self.phi[i] = -phi_t - jw;
        }
        let mut rates = std::mem::take(&mut self.phi);
        let solved = self.dependent.solve(&mut rates);
        if solved.is_err() {
            self.phi = rates;
            self.state.needs_repartition = true;
            return Err(SINGULAR_PARTITION);
        }
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
        // The outputs' evaluation starts from the same factors (made again from the same values and
        // pivots) in the second matrix, and leaves the first as it was.
        let (factored, needs_repartition) = (self.state.factored, self.state.needs_repartition);
        self.state.factored = factored && self.dependent.copy_to_output();
        std::mem::swap(&mut self.dependent.lu, &mut self.dependent.output_lu);
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
        std::mem::swap(&mut self.dependent.lu, &mut self.dependent.output_lu);
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
