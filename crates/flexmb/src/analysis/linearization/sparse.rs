//! `K = ∂g/∂q`, `C = ∂g/∂v` and `K_B = ∂(B v + Φ_t)/∂q` of the equations of motion
//! ([`equations_of_motion`]) on a sparse pattern made once per model from its coupling graph, by
//! forward differences with the body columns grouped by a greedy colouring (Curtis, Powell and Reid
//! 1974): bodies of one colour touch disjoint rows and are perturbed together, so an evaluation costs
//! `1 + 2 · (widest body of each colour, summed over the colours)` evaluations of `g`, not `1 + 2 nv`.
//!
//! The positions are perturbed in velocity space, as the generalized-α step moves them and as
//! [`displaced_positions`](super::displaced_positions) does: translations and modal coordinates by
//! [`perturbation`] of their value, each body frame turned by `RELATIVE_STEP` rad about its own axes
//! (`p ∘ exp(δ e_i)`). The generalized-α iteration matrix evaluates its derivative parts here; an
//! eigen-analysis or an equilibrium solver takes `K`, `C` at an equilibrium (`v = 0`, `v̇ = 0`, its
//! multipliers) together with the exact `M` and `B`, sparse, from the same evaluation.

use std::ops::Range;

use faer::Mat;

use crate::data::Data;
use crate::stage::{quaternion_product, rotation_quaternion};
use crate::linalg::{greedy_colouring, perturbation, RELATIVE_STEP};
use crate::math::{Vec3, Vec4};
use crate::model::{Coupling, Layout, Model, SizeCheck, SizeMismatch};
use crate::stage::equations_of_motion;

use super::OperatingPoint;

/// `K`, `C` and `K_B` of a model on their sparse pattern, evaluated by coloured finite differences at
/// any state. Columns are the `nv` velocity coordinates; rows `0..nv` are the dynamic equations, rows
/// `nv..nv + nc` the velocity constraints. Allocates at construction only.
#[derive(Clone, Debug)]
pub struct SparseLinearization {
    nv: usize,
    nc: usize,
    /// The pattern by columns: the entries of column `c` are `col_ptr[c]..col_ptr[c + 1]`, their rows
    /// `row_idx[..]` (sorted).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// `K` on the dynamic rows and `K_B` on the velocity-constraint rows, in pattern order.
    stiffness: Vec<f64>,
    /// `C` on the dynamic rows (zero on the velocity-constraint rows), in pattern order.
    damping: Vec<f64>,
    /// The velocity columns of the bodies, grouped by colour.
    colours: Vec<Vec<Range<usize>>>,
    g0: Vec<f64>,
    g1: Vec<f64>,
    q_work: Vec<f64>,
    v_work: Vec<f64>,
}

#[derive(Clone, Copy)]
enum Pass {
    Positions,
    Velocities,
}

impl SparseLinearization {
    /// The pattern and colouring of `model`, made once.
    pub fn new(model: &Model) -> Self {
        Self::with_coupling(model, &Coupling::new(model))
    }

    /// The pattern and colouring from the coupling graph of `model`: column `c` of body `b` has the
    /// dynamic rows of the bodies that read `b` and the constraint rows of `b`'s joints.
    pub(crate) fn with_coupling(model: &Model, coupling: &Coupling) -> Self {
        let l = &model.layout;
        let (nb, nj, nv, nc) = (model.bodies.len(), model.joints.len(), l.nv, l.nc);
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for b in 0..nb {
            let mut rows: Vec<usize> = coupling.readers[b].iter().flat_map(|&r| l.v_span(r)).collect();
            rows.extend(coupling.joints_of[b].iter().flat_map(|&k| l.joint_rows[k].clone().map(|i| nv + i)));
            rows.sort_unstable();
            rows.dedup();
            for _ in l.v_span(b) {
                row_idx.extend_from_slice(&rows);
                col_ptr.push(row_idx.len());
            }
        }
        // Row blocks: the dynamic rows of each body (ids 0..nb), the velocity-constraint rows of each
        // joint (ids nb..nb + nj).
        let touched: Vec<Vec<usize>> = (0..nb)
            .map(|b| coupling.readers[b].iter().copied().chain(coupling.joints_of[b].iter().map(|&k| nb + k)).collect())
            .collect();
        let colours = greedy_colouring(&touched, nb + nj)
            .into_iter()
            .map(|bodies| bodies.into_iter().map(|b| l.v_span(b)).collect())
            .collect();
        let nnz = row_idx.len();
        Self {
            nv,
            nc,
            col_ptr,
            row_idx,
            stiffness: vec![0.0; nnz],
            damping: vec![0.0; nnz],
            colours,
            g0: vec![0.0; nv + nc],
            g1: vec![0.0; nv + nc],
            q_work: vec![0.0; l.nq],
            v_work: vec![0.0; nv],
        }
    }

    /// Evaluations of `g` one [`evaluate`](Self::evaluate) costs.
    pub fn evaluations(&self) -> usize {
        1 + 2 * self.colours.iter().map(|c| c.iter().map(|r| r.len()).max().unwrap_or(0)).sum::<usize>()
    }

    /// Evaluates `K`, `C`, `K_B` at the operating point `at` (rows of the constraints switched off in
    /// `active` are zero). Returns the evaluations of `g` it used; leaves `data`'s stages evaluated at a
    /// perturbed state. An evaluator, `data` or vectors not of `model`'s sizes are an error.
    pub fn evaluate(
        &mut self,
        model: &Model,
        data: &mut Data,
        active: &[bool],
        at: &OperatingPoint,
    ) -> Result<usize, SizeMismatch> {
        SizeCheck::new(model)
            .velocities("the linearization's workspace (velocities)", &self.v_work)?
            .len("the linearization's workspace (equations)", self.g0.len(), model.layout.nv + model.layout.nc)?
            .len("the linearization's workspace (positions)", self.q_work.len(), model.layout.nq)?
            .data(data)?
            .rows("the rows in force (active)", active.len())?
            .positions(at.q)?
            .velocities("velocities v", at.v)?
            .velocities("accelerations v̇", at.vdot)?
            .rows("multipliers λ", at.lambda.len())?;
        Ok(self.evaluate_at(model, data, active, at))
    }

    /// [`evaluate`](Self::evaluate) on arguments of the model's sizes (the engine's own calls).
    pub(crate) fn evaluate_at(&mut self, model: &Model, data: &mut Data, active: &[bool], at: &OperatingPoint) -> usize {
        let l = &model.layout;
        let OperatingPoint { t, q, v, vdot, lambda } = *at;
        equations_of_motion(model, data, active, t, q, v, vdot, lambda, &mut self.g0);
        let mut evaluations = 1;
        self.q_work.copy_from_slice(q);
        self.v_work.copy_from_slice(v);
        self.stiffness.fill(0.0);
        self.damping.fill(0.0);
        for pass in [Pass::Positions, Pass::Velocities] {
            for colour in &self.colours {
                let width = colour.iter().map(|r| r.len()).max().unwrap_or(0);
                for local in 0..width {
                    // Perturb column `local` of every body of this colour.
                    for range in colour.iter().filter(|r| local < r.len()) {
                        let c = range.start + local;
                        let b = l.velocity_body(c);
                        match pass {
                            Pass::Positions => perturb_position(l, &mut self.q_work, b, local, q),
                            Pass::Velocities => self.v_work[c] = v[c] + perturbation(v[c]),
                        }
                    }
                    equations_of_motion(model, data, active, t, &self.q_work, &self.v_work, vdot, lambda, &mut self.g1);
                    evaluations += 1;
                    for range in colour.iter().filter(|r| local < r.len()) {
                        let c = range.start + local;
                        let b = l.velocity_body(c);
                        let delta = match pass {
                            Pass::Positions => {
                                let delta = position_perturbation(l, q, b, local);
                                let qr = l.q_span(b);
                                self.q_work[qr.clone()].copy_from_slice(&q[qr]);
                                delta
                            }
                            Pass::Velocities => {
                                let delta = self.v_work[c] - v[c];
                                self.v_work[c] = v[c];
                                delta
                            }
                        };
                        // K and K_B from the position pass; C from the velocity pass (the velocity
                        // constraints' derivative there is B, exact).
                        let (target, last_row) = match pass {
                            Pass::Positions => (&mut self.stiffness, self.nv + self.nc),
                            Pass::Velocities => (&mut self.damping, self.nv),
                        };
                        let range = self.col_ptr[c]..self.col_ptr[c + 1];
                        for (s, &r) in range.clone().zip(&self.row_idx[range]) {
                            if r < last_row {
                                target[s] = (self.g1[r] - self.g0[r]) / delta;
                            }
                        }
                    }
                }
            }
        }
        evaluations
    }

    /// The entries of column `c`: their range in [`stiffness`](Self::stiffness) and
    /// [`damping`](Self::damping), and their rows (sorted; `nv + i` for velocity constraint `i`).
    ///
    /// # Panics
    /// If `c` is not below `nv`.
    pub fn column(&self, c: usize) -> (Range<usize>, &[usize]) {
        let range = self.col_ptr[c]..self.col_ptr[c + 1];
        (range.clone(), &self.row_idx[range])
    }

    /// `K` (dynamic rows) and `K_B` (velocity-constraint rows) of the last evaluation, in pattern order.
    pub fn stiffness(&self) -> &[f64] {
        &self.stiffness
    }

    /// `C` (dynamic rows; zero on the velocity-constraint rows) of the last evaluation, in pattern order.
    pub fn damping(&self) -> &[f64] {
        &self.damping
    }

    /// Replaces the values (from an integrator's checkpoint; lengths checked by the caller).
    pub(crate) fn set_values(&mut self, stiffness: &[f64], damping: &[f64]) {
        self.stiffness.copy_from_slice(stiffness);
        self.damping.copy_from_slice(damping);
    }

    /// `(K, C, K_B)` of the last evaluation as dense matrices (`nv × nv`, `nv × nv`, `nc × nv`).
    pub fn to_dense(&self) -> (Mat<f64>, Mat<f64>, Mat<f64>) {
        let (nv, nc) = (self.nv, self.nc);
        let (mut k, mut c, mut k_b) = (Mat::zeros(nv, nv), Mat::zeros(nv, nv), Mat::zeros(nc, nv));
        for col in 0..nv {
            let (range, rows) = self.column(col);
            for (s, &r) in range.zip(rows) {
                if r < nv {
                    k[(r, col)] = self.stiffness[s];
                    c[(r, col)] = self.damping[s];
                } else {
                    k_b[(r - nv, col)] = self.stiffness[s];
                }
            }
        }
        (k, c, k_b)
    }
}

/// The step along velocity direction `local` of body `b`'s positions: translations and modal
/// coordinates by their own size, rotations by `RELATIVE_STEP` rad.
fn position_perturbation(l: &Layout, q: &[f64], b: usize, local: usize) -> f64 {
    let qo = l.q_offset[b];
    match local {
        0..=2 => perturbation(q[qo + local]),
        3..=5 => RELATIVE_STEP,
        _ => perturbation(q[qo + 7 + local - 6]),
    }
}

/// Moves body `b`'s positions in `q_work` (a copy of `q`) by the step of velocity direction `local`.
fn perturb_position(l: &Layout, q_work: &mut [f64], b: usize, local: usize, q: &[f64]) {
    let qo = l.q_offset[b];
    let delta = position_perturbation(l, q, b, local);
    match local {
        0..=2 => q_work[qo + local] = q[qo + local] + delta,
        3..=5 => {
            let mut axis = Vec3::zeros();
            axis[local - 3] = delta;
            let p = Vec4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]);
            let turned = quaternion_product(&p, &rotation_quaternion(&axis));
            q_work[qo + 3..qo + 7].copy_from_slice(turned.as_slice());
        }
        _ => q_work[qo + 7 + local - 6] = q[qo + 7 + local - 6] + delta,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::test_models;

    /// The coloured evaluation on the sparse pattern equals forward differences of `g` taken one column
    /// at a time over all rows: the coupling graph misses no dependency, and the bodies of one colour
    /// touch disjoint rows.
    #[test]
    fn coloured_derivatives_match_one_column_at_a_time() {
        coloured_against_dense(test_models::double_pendulum_with_spring());
        coloured_against_dense(test_models::pendulum_with_stiff_slider());
    }

    fn coloured_against_dense(model: Model) {
        let l = &model.layout;
        let (nv, nc) = (l.nv, l.nc);
        let (mut data, state, acc) = test_models::moving_state(&model);
        let (t, q, v, active) = (0.1, &state.q, &state.v, &state.active);
        let mut sparse = SparseLinearization::new(&model);
        sparse.evaluate(&model, &mut data, active, &OperatingPoint { t, q, v, vdot: &acc.vdot, lambda: &acc.lambda }).unwrap();
        let (k, c, k_b) = sparse.to_dense();
        let mut g0 = vec![0.0; nv + nc];
        let mut g1 = vec![0.0; nv + nc];
        equations_of_motion(&model, &mut data, active, t, q, v, &acc.vdot, &acc.lambda, &mut g0);
        let close = |dense: f64, coloured: f64| (dense - coloured).abs() / (1.0 + dense.abs()) < 1e-6;
        for col in 0..nv {
            let b = l.velocity_body(col);
            let local = col - l.v_offset[b];
            let mut q_moved = q.clone();
            perturb_position(l, &mut q_moved, b, local, q);
            let delta = position_perturbation(l, q, b, local);
            equations_of_motion(&model, &mut data, active, t, &q_moved, v, &acc.vdot, &acc.lambda, &mut g1);
            for r in 0..nv + nc {
                let dense = (g1[r] - g0[r]) / delta;
                let coloured = if r < nv { k[(r, col)] } else { k_b[(r - nv, col)] };
                assert!(close(dense, coloured), "∂g_{r}/∂q_{col}: dense {dense}, coloured {coloured}");
            }
            let mut v_moved = v.clone();
            v_moved[col] += perturbation(v[col]);
            let delta = v_moved[col] - v[col];
            equations_of_motion(&model, &mut data, active, t, q, &v_moved, &acc.vdot, &acc.lambda, &mut g1);
            for r in 0..nv {
                let dense = (g1[r] - g0[r]) / delta;
                assert!(close(dense, c[(r, col)]), "∂g_{r}/∂v_{col}: dense {dense}, coloured {}", c[(r, col)]);
            }
        }
    }
}
