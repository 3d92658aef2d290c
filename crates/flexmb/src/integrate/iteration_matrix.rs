//! The Newton iteration matrix `∂F/∂y + (1/c) ∂F/∂ẏ` of the DAE residual (rows with a derivative scaled by
//! `c`), on a sparse pattern derived once from the model's coupling graph.
//!
//! `∂F/∂y` comes from finite differences of the residual with the columns grouped by a greedy colouring
//! (Curtis, Powell and Reid 1974): columns of bodies that share no equation are perturbed together, so
//! the cost grows with the colour count, not the model size. `∂F/∂ẏ` is exact: the identity on the
//! kinematic rows and the body mass matrices on the dynamic rows. Both are kept, so a change of step size
//! only refactors: `values = c·F_y + F_ẏ` on the differential rows.

use std::ops::Range;

use crate::data::Data;
use crate::linalg::{SingularMatrix, SparseLu};
use crate::model::{BodyId, Model};
use crate::stage::{body_mass_entries, residual, YLayout};

/// A set of columns (or rows) belonging to one body or joint.
#[derive(Clone, Debug)]
struct Block {
    range: Range<usize>,
}

/// Iteration matrix with stored derivative parts and reusable LU factors.
pub(crate) struct IterationMatrix {
    lu: SparseLu,
    f_y: Vec<f64>,
    f_yp: Vec<f64>,
    n_differential: usize,
    /// Column blocks grouped by colour.
    colors: Vec<Vec<Block>>,
    f0: Vec<f64>,
    f1: Vec<f64>,
    y_work: Vec<f64>,
}

impl IterationMatrix {
    pub fn new(model: &Model, yl: &YLayout) -> Self {
        let l = &model.layout;
        let nb = model.bodies.len();
        let nj = model.joints.len();
        // Row blocks: Fq_b, Fv_b, λ_k, μ_k, normalization_b.
        let fq = |b: usize| {
            let r = l.q_range(BodyId(b));
            yl.q.start + r.start..yl.q.start + r.end
        };
        let fv = |b: usize| {
            let r = l.v_range(BodyId(b));
            yl.v.start + r.start..yl.v.start + r.end
        };
        let lam = |k: usize| yl.lambda.start + l.joint_rows[k].start..yl.lambda.start + l.joint_rows[k].end;
        let mu = |k: usize| yl.mu.start + l.joint_rows[k].start..yl.mu.start + l.joint_rows[k].end;
        let norm = |b: usize| yl.mu.start + l.nc + b..yl.mu.start + l.nc + b + 1;
        let id_fq = |b: usize| b;
        let id_fv = |b: usize| nb + b;
        let id_lam = |k: usize| 2 * nb + k;
        let id_mu = |k: usize| 2 * nb + nj + k;
        let id_norm = |b: usize| 2 * nb + 2 * nj + b;
        let n_row_blocks = 3 * nb + 2 * nj;
        let mut row_ranges = vec![0..0; n_row_blocks];
        for b in 0..nb {
            row_ranges[id_fq(b)] = fq(b);
            row_ranges[id_fv(b)] = fv(b);
            row_ranges[id_norm(b)] = norm(b);
        }
        for k in 0..nj {
            row_ranges[id_lam(k)] = lam(k);
            row_ranges[id_mu(k)] = mu(k);
        }

        let joint_bodies: Vec<Vec<usize>> =
            model.joints.iter().map(|j| model.joint_bodies(j).into_iter().flatten().map(|b| b.0).collect()).collect();
        let mut joints_of: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for (k, bodies) in joint_bodies.iter().enumerate() {
            for &b in bodies {
                joints_of[b].push(k);
            }
        }
        // readers[b]: bodies whose dynamic rows depend on the state of body b.
        let mut readers: Vec<Vec<usize>> = (0..nb).map(|b| vec![b]).collect();
        for bodies in &joint_bodies {
            for &a in bodies {
                readers[a].extend(bodies.iter().copied());
            }
        }
        for (acted, read) in force_couplings(model) {
            for &r in &read {
                readers[r].extend(acted.iter().copied());
            }
        }
        let mut joint_neighbours: Vec<Vec<usize>> = (0..nb).map(|b| vec![b]).collect();
        for bodies in &joint_bodies {
            for &a in bodies {
                joint_neighbours[a].extend(bodies.iter().copied());
            }
        }
        for list in readers.iter_mut().chain(joint_neighbours.iter_mut()) {
            list.sort_unstable();
            list.dedup();
        }

        // Column blocks and the row blocks each one touches.
        let mut columns: Vec<(Block, Vec<usize>)> = Vec::new();
        for b in 0..nb {
            let mut touched: Vec<usize> = joint_neighbours[b].iter().map(|&n| id_fq(n)).collect();
            touched.extend(readers[b].iter().map(|&c| id_fv(c)));
            touched.extend(joints_of[b].iter().flat_map(|&k| [id_lam(k), id_mu(k)]));
            touched.push(id_norm(b));
            columns.push((Block { range: fq(b) }, touched));
            let mut touched: Vec<usize> = vec![id_fq(b)];
            touched.extend(readers[b].iter().map(|&c| id_fv(c)));
            touched.extend(joints_of[b].iter().map(|&k| id_lam(k)));
            columns.push((Block { range: fv(b) }, touched));
            columns.push((Block { range: norm(b) }, vec![id_fq(b)]));
        }
        for (k, bodies) in joint_bodies.iter().enumerate() {
            if l.joint_rows[k].is_empty() {
                continue;
            }
            let mut touched: Vec<usize> = bodies.iter().map(|&b| id_fv(b)).collect();
            touched.push(id_lam(k));
            columns.push((Block { range: lam(k) }, touched));
            let mut touched: Vec<usize> = bodies.iter().map(|&b| id_fq(b)).collect();
            touched.push(id_mu(k));
            columns.push((Block { range: mu(k) }, touched));
        }

        let mut entries = Vec::new();
        for (block, touched) in &columns {
            for &rb in touched {
                for r in row_ranges[rb].clone() {
                    for c in block.range.clone() {
                        entries.push((r, c));
                    }
                }
            }
        }
        let n = yl.len();
        let lu = SparseLu::new(n, entries);

        // Greedy colouring: blocks of one colour touch disjoint row blocks.
        let mut colors: Vec<Vec<Block>> = Vec::new();
        let mut used: Vec<Vec<bool>> = Vec::new();
        for (block, touched) in columns {
            let slot = used.iter().position(|u| touched.iter().all(|&rb| !u[rb]));
            let c = slot.unwrap_or_else(|| {
                colors.push(Vec::new());
                used.push(vec![false; n_row_blocks]);
                colors.len() - 1
            });
            touched.iter().for_each(|&rb| used[c][rb] = true);
            colors[c].push(block);
        }
        let nnz = lu.values.len();
        Self {
            lu,
            f_y: vec![0.0; nnz],
            f_yp: vec![0.0; nnz],
            n_differential: yl.n_differential(),
            colors,
            f0: vec![0.0; n],
            f1: vec![0.0; n],
            y_work: vec![0.0; n],
        }
    }

    /// Number of residual evaluations one Jacobian costs (besides the base point).
    pub fn evaluations_per_jacobian(&self) -> usize {
        self.colors.iter().map(|c| c.iter().map(|b| b.range.len()).max().unwrap_or(0)).sum()
    }

    /// Re-evaluates `F_y` (finite differences) and `F_ẏ` at `(t, y, ẏ)`. Returns the residual evaluations used.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &mut self,
        model: &Model,
        data: &mut Data,
        yl: &YLayout,
        active: &[bool],
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> usize {
        let mut evaluations = 1;
        residual(model, data, yl, active, t, y, yp, &mut self.f0);
        // F_ẏ at the base point (the stages still hold its kinematics).
        self.f_yp.fill(0.0);
        for b in 0..model.bodies.len() {
            for k in model.layout.q_range(BodyId(b)) {
                let s = self.lu.slot(yl.q.start + k, yl.q.start + k).expect("diagonal is in the pattern");
                self.f_yp[s] = 1.0;
            }
            let v0 = yl.v.start + model.layout.v_offset[b];
            let (lu, f_yp) = (&self.lu, &mut self.f_yp);
            body_mass_entries(model, data, b, |r, c, m| {
                let s = lu.slot(v0 + r, v0 + c).expect("mass block is in the pattern");
                f_yp[s] += m;
            });
        }
        self.y_work.copy_from_slice(y);
        self.f_y.fill(0.0);
        for color in &self.colors {
            let width = color.iter().map(|b| b.range.len()).max().unwrap_or(0);
            for local in 0..width {
                for block in color.iter().filter(|b| local < b.range.len()) {
                    let c = block.range.start + local;
                    self.y_work[c] = y[c] + perturbation(y[c]);
                }
                residual(model, data, yl, active, t, &self.y_work, yp, &mut self.f1);
                evaluations += 1;
                for block in color.iter().filter(|b| local < b.range.len()) {
                    let c = block.range.start + local;
                    let delta = self.y_work[c] - y[c];
                    self.y_work[c] = y[c];
                    let (range, rows) = self.lu.column(c);
                    for (s, &r) in range.zip(rows) {
                        self.f_y[s] = (self.f1[r] - self.f0[r]) / delta;
                    }
                }
            }
        }
        evaluations
    }

    /// Forms `c·F_y + F_ẏ` (differential rows) and `F_y` (algebraic rows) and factors it.
    pub fn factor(&mut self, c: f64) -> Result<(), SingularMatrix> {
        for col in 0..self.lu.n() {
            let start = self.lu.column(col).0.start;
            let (values, rows) = self.lu.column_mut(col);
            for (k, (x, &r)) in values.iter_mut().zip(rows).enumerate() {
                let s = start + k;
                *x = if r < self.n_differential { c * self.f_y[s] + self.f_yp[s] } else { self.f_y[s] };
            }
        }
        self.lu.factor()
    }

    /// `out = [F_ẏ x; F_y x]`: `F_ẏ x` on the differential rows, `F_y x` on the algebraic rows (the
    /// right-hand side of the filtered error estimate, see `Bdf`).
    pub fn filter_rhs(&self, x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for c in 0..self.lu.n() {
            let (range, rows) = self.lu.column(c);
            for (s, &r) in range.zip(rows) {
                let entry = if r < self.n_differential { self.f_yp[s] } else { self.f_y[s] };
                out[r] += entry * x[c];
            }
        }
    }

    /// The stored `∂F/∂y` and `∂F/∂ẏ`, in the order of the sparse pattern (for a checkpoint).
    pub fn stored_parts(&self) -> (&[f64], &[f64]) {
        (&self.f_y, &self.f_yp)
    }

    /// Replaces the stored `∂F/∂y` and `∂F/∂ẏ` (from a checkpoint; their lengths checked by the caller).
    pub fn set_stored_parts(&mut self, f_y: &[f64], f_yp: &[f64]) {
        self.f_y.copy_from_slice(f_y);
        self.f_yp.copy_from_slice(f_yp);
    }

    /// Solves with the current factors in place.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        self.lu.solve_in_place(rhs)
    }
}

/// Finite-difference step for a column with value `x`.
#[inline]
fn perturbation(x: f64) -> f64 {
    let h = 1.5e-8 * x.abs().max(1.0);
    // Make the step exactly representable so that (x + h) − x == h.
    (x + h) - x
}

/// For each force element: the bodies it acts on and the bodies whose state it reads (through its
/// markers and the measures its expressions use): the coupling graph of the iteration matrices.
pub(crate) fn force_couplings(model: &Model) -> Vec<(Vec<usize>, Vec<usize>)> {
    use crate::force::ForceKind;
    use crate::measure::MeasureKind;
    let marker_body = |m: crate::model::MarkerId| model.markers[m.0].body.body().map(|b: BodyId| b.0);
    let joint_bodies = |j: crate::model::JointId| {
        let jt = &model.joints[j.0];
        [marker_body(jt.marker_i), marker_body(jt.marker_j)]
    };
    let measure_bodies = |m: crate::model::MeasureId| -> Vec<Option<usize>> {
        match model.measures[m.0].kind {
            MeasureKind::JointAngle(j)
            | MeasureKind::JointRate(j)
            | MeasureKind::JointDisplacement(j)
            | MeasureKind::JointVelocity(j) => joint_bodies(j).to_vec(),
            MeasureKind::Distance(a, b) | MeasureKind::DistanceRate(a, b) => vec![marker_body(a), marker_body(b)],
            MeasureKind::Position(a, _) | MeasureKind::Velocity(a, _) | MeasureKind::Speed(a) => vec![marker_body(a)],
            MeasureKind::Parameter(_) => Vec::new(),
        }
    };
    model
        .forces
        .iter()
        .map(|f| {
            let acted: Vec<Option<usize>> = match &f.kind {
                ForceKind::TranslationalSpringDamper { marker_i, marker_j, .. } => {
                    vec![marker_body(*marker_i), marker_body(*marker_j)]
                }
                ForceKind::RotationalSpringDamper { joint, .. } => joint_bodies(*joint).to_vec(),
                ForceKind::AppliedForce { marker, .. } | ForceKind::AppliedTorque { marker, .. } => {
                    vec![marker_body(*marker)]
                }
            };
            let mut read = acted.clone();
            for e in f.kind.expressions() {
                for m in e.measures() {
                    read.extend(measure_bodies(m));
                }
            }
            (acted.into_iter().flatten().collect(), read.into_iter().flatten().collect())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{assemble, velocity_analysis, AccelerationSolver, State};

    /// The coloured, pattern-restricted finite-difference Jacobian equals a dense one: no dependency is
    /// missing from the pattern and no two columns of one colour share a row.
    #[test]
    fn coloured_jacobian_matches_dense_finite_differences() {
        coloured_against_dense(crate::analysis::test_models::double_pendulum_with_spring());
        coloured_against_dense(crate::analysis::test_models::pendulum_with_stiff_slider());
    }

    fn coloured_against_dense(model: Model) {
        let mut data = Data::new(&model);
        let mut state = State::initial(&model);
        assemble(&model, &mut data, &mut state, Default::default()).unwrap();
        state.v.iter_mut().enumerate().for_each(|(k, v)| *v += 0.1 * (k as f64).sin());
        velocity_analysis(&model, &mut data, &mut state).unwrap();
        let acc = AccelerationSolver::new(&model).solve(&model, &mut data, 0.0, &state.q, &state.v, &state.active).unwrap().clone();
        let yl = YLayout::new(&model);
        let n = yl.len();
        let mut y = vec![0.0; n];
        y[yl.q.clone()].copy_from_slice(&state.q);
        y[yl.v.clone()].copy_from_slice(&state.v);
        y[yl.lambda.clone()].copy_from_slice(&acc.lambda);
        for k in yl.mu.clone() {
            y[k] = 1e-3 * (k as f64).cos();
        }
        let yp: Vec<f64> = (0..n).map(|k| 0.3 * (k as f64 * 0.7).sin()).collect();
        let mut jac = IterationMatrix::new(&model, &yl);
        jac.evaluate(&model, &mut data, &yl, &state.active, 0.1, &y, &yp);
        let mut f0 = vec![0.0; n];
        let mut f1 = vec![0.0; n];
        residual(&model, &mut data, &yl, &state.active, 0.1, &y, &yp, &mut f0);
        let mut worst = 0.0_f64;
        for c in 0..n {
            let mut yc = y.clone();
            let h = perturbation(y[c]);
            yc[c] += h;
            residual(&model, &mut data, &yl, &state.active, 0.1, &yc, &yp, &mut f1);
            for r in 0..n {
                let dense = (f1[r] - f0[r]) / h;
                let coloured = jac.lu.slot(r, c).map_or(0.0, |s| jac.f_y[s]);
                let err = (dense - coloured).abs() / (1.0 + dense.abs());
                assert!(err < 1e-6, "entry ({r}, {c}): dense {dense}, coloured {coloured}");
                worst = worst.max(err);
            }
        }
        assert!(worst < 1e-6);
    }
}
