//! The Newton iteration matrix of a generalized-α step, unknowns `x = [v̇, λ, μ̃]`, rows
//! `[dynamics (nv); velocity constraints / (γ'h) (nc); position constraints / (β'h²) (nc)]`:
//!
//! ```text
//! ┌ M + γ'h C + β'h² K J     Bᵀ    β'h² K J Bᵀ      ┐
//! │ B + (β'h/γ') K_B J       0     (β'h/γ') K_B J Bᵀ │    β' = β (1 − α_f)/(1 − α_m),  γ' = γ (1 − α_f)/(1 − α_m)
//! └ B J                      0     B J Bᵀ           ┘
//! ```
//! `M` (from `body_mass_entries`) and `B` (from `jacobian_entries`) are exact, evaluated afresh at the
//! predictor of every step attempt. `K = ∂g/∂q` and `C = ∂g/∂v` of `g = M v̇ + h(q, v) − Q + Bᵀλ`, and
//! `K_B = ∂(B v + Φ_t)/∂q`, come from finite differences (positions perturbed in velocity space, like the
//! step's own update) with the columns grouped by a greedy colouring of the bodies (Curtis, Powell and
//! Reid 1974); they are kept until a Newton iteration fails to converge with them, and since they are
//! stored apart from `h`, a new step size only refactors. `J` is block diagonal: in each body's rotation
//! columns the tangent `J_r(d_ω̄)` of the exponential map at the step increment `d` (Brüls and Cardona's
//! tangent operator; `q_n ∘ exp(d)` moves by `exp(J_r(d) δd)` when `d` moves by `δd`), the identity
//! elsewhere. The `μ̃` columns are the position columns times `Bᵀ`, since `μ` moves the positions by
//! `Bᵀμ`: the stabilizing multiplier is not small at a finite step (it absorbs the `O(h³)` mismatch of
//! the position and velocity constraints), and leaving its coupling to the dynamics out slowed the
//! Newton iteration to a linear rate of 0.2 to 0.8 on a pendulum. The constraint rows are scaled so that
//! every block stays of order one as `h → 0`, where the matrix tends to `[M Bᵀ 0; B 0 0; B 0 BBᵀ]`.

use std::ops::Range;

use faer::Mat;

use super::lie_group::{quaternion_product, right_jacobian, rotation_quaternion};
use super::Coefficients;
use crate::data::Data;
use crate::integrate::iteration_matrix::force_couplings;
use crate::linalg::{SingularMatrix, SparseLu};
use crate::math::{Mat3, Vec3, Vec4};
use crate::model::{BodyId, Model};
use crate::stage::{add_jacobian_transpose, body_mass_entries, forward, jacobian_entries};

/// The iteration matrix on its fixed sparse pattern, with the stored finite-difference parts.
pub(crate) struct IterationMatrix {
    lu: SparseLu,
    nv: usize,
    nc: usize,
    /// `K` (dynamic rows) and `K_B` (velocity-constraint rows) in LU slot order, columns `v̇`.
    stiffness: Vec<f64>,
    /// `C` (dynamic rows) in LU slot order, columns `v̇`.
    damping: Vec<f64>,
    /// `B` by rows: columns `b_col[b_ptr[i]..b_ptr[i + 1]]` (sorted) and its values.
    b_ptr: Vec<usize>,
    b_col: Vec<usize>,
    b_val: Vec<f64>,
    /// `B(q_n)` at the start of the step, same layout.
    b_start: Vec<f64>,
    /// `J_r(d_ω̄)` of each body at the step increment.
    tangents: Vec<Mat3>,
    /// The products of the `μ̃` columns, `P Bᵀ` with `P` the position part of the `v̇` columns: each
    /// `(target slot (r, μ̃_j), source slot (r, c), index of B(j, c) in b_val)`.
    products: Vec<(usize, usize, usize)>,
    /// The position part `P` of the `v̇` columns, in LU slot order.
    position_part: Vec<f64>,
    /// Velocity columns of the bodies, grouped by colour: bodies of one colour touch disjoint rows.
    colors: Vec<Vec<Range<usize>>>,
    g0: Vec<f64>,
    g1: Vec<f64>,
    q_work: Vec<f64>,
    v_work: Vec<f64>,
}

impl IterationMatrix {
    pub fn new(model: &Model) -> Self {
        let l = &model.layout;
        let (nb, nj, nv, nc) = (model.bodies.len(), model.joints.len(), l.nv, l.nc);
        let v_range = |b: usize| l.v_range(BodyId(b));
        let joint_bodies: Vec<Vec<usize>> =
            model.joints.iter().map(|j| model.joint_bodies(j).into_iter().flatten().map(|b| b.0).collect()).collect();
        let mut joints_of: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for (k, bodies) in joint_bodies.iter().enumerate() {
            for &b in bodies {
                joints_of[b].push(k);
            }
        }
        joints_of.iter_mut().for_each(|j| j.dedup());
        // readers[b]: the bodies whose dynamic rows depend on the state of body b.
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
        for list in &mut readers {
            list.sort_unstable();
            list.dedup();
        }

        let mut entries = Vec::new();
        for b in 0..nb {
            for &r in &readers[b] {
                for row in v_range(r) {
                    entries.extend(v_range(b).map(|col| (row, col)));
                }
            }
        }
        for (k, bodies) in joint_bodies.iter().enumerate() {
            for &b in bodies {
                for row in l.joint_rows[k].clone() {
                    for col in v_range(b) {
                        entries.extend([(nv + row, col), (nv + nc + row, col), (col, nv + row)]);
                    }
                }
            }
        }
        // μ̃_j moves the bodies of row j's joint: it reaches the rows that depend on their positions.
        let mut mu_rows: Vec<Vec<usize>> = vec![Vec::new(); nc];
        for (k, bodies) in joint_bodies.iter().enumerate() {
            let mut rows = Vec::new();
            for &b in bodies {
                for &r in &readers[b] {
                    rows.extend(v_range(r));
                }
                for &k2 in &joints_of[b] {
                    rows.extend(l.joint_rows[k2].clone().flat_map(|i| [nv + i, nv + nc + i]));
                }
            }
            rows.sort_unstable();
            rows.dedup();
            for j in l.joint_rows[k].clone() {
                entries.extend(rows.iter().map(|&r| (r, nv + nc + j)));
                mu_rows[j] = rows.clone();
            }
        }
        let lu = SparseLu::new(nv + 2 * nc, entries);
        let mut b_ptr = vec![0];
        let mut b_col = Vec::new();
        for row in 0..nc {
            let (joint, _) = l.equations[row];
            let mut cols: Vec<usize> = joint_bodies[joint.0].iter().flat_map(|&b| v_range(b)).collect();
            cols.sort_unstable();
            cols.dedup();
            b_col.extend(cols);
            b_ptr.push(b_col.len());
        }
        let mut products = Vec::new();
        for j in 0..nc {
            for &r in &mu_rows[j] {
                let target = lu.slot(r, nv + nc + j).expect("μ̃ column entry is in the pattern");
                for i in b_ptr[j]..b_ptr[j + 1] {
                    if let Some(source) = lu.slot(r, b_col[i]) {
                        products.push((target, source, i));
                    }
                }
            }
        }

        // Greedy colouring of the body column blocks by the row blocks they touch: dynamic rows of the
        // readers (ids 0..nb) and velocity-constraint rows of the body's joints (ids nb..nb + nj).
        let mut colors: Vec<Vec<Range<usize>>> = Vec::new();
        let mut used: Vec<Vec<bool>> = Vec::new();
        for b in 0..nb {
            let touched: Vec<usize> = readers[b].iter().copied().chain(joints_of[b].iter().map(|&k| nb + k)).collect();
            let slot = used.iter().position(|u| touched.iter().all(|&t| !u[t]));
            let c = slot.unwrap_or_else(|| {
                colors.push(Vec::new());
                used.push(vec![false; nb + nj]);
                colors.len() - 1
            });
            touched.iter().for_each(|&t| used[c][t] = true);
            colors[c].push(v_range(b));
        }

        // The rotation columns of a body share one row list (whole blocks are entered), which lets
        // `factor` combine them with `J_r` slot by slot.
        for b in 0..nb {
            let o = l.v_offset[b] + 3;
            for i in 1..3 {
                assert_eq!(lu.column(o).1, lu.column(o + i).1, "rotation columns of body {b} share their rows");
            }
        }
        let nnz = lu.values.len();
        let n_b = b_col.len();
        Self {
            lu,
            nv,
            nc,
            stiffness: vec![0.0; nnz],
            damping: vec![0.0; nnz],
            b_ptr,
            b_col,
            b_val: vec![0.0; n_b],
            b_start: vec![0.0; n_b],
            tangents: vec![Mat3::identity(); nb],
            products,
            position_part: vec![0.0; nnz],
            colors,
            g0: vec![0.0; nv + nc],
            g1: vec![0.0; nv + nc],
            q_work: vec![0.0; l.nq],
            v_work: vec![0.0; nv],
        }
    }

    /// Evaluations of `g` one [`evaluate_derivatives`](Self::evaluate_derivatives) costs.
    pub fn evaluations_per_jacobian(&self) -> usize {
        1 + 2 * self.colors.iter().map(|c| c.iter().map(|r| r.len()).max().unwrap_or(0)).sum::<usize>()
    }

    /// Re-evaluates `K`, `C`, `K_B` by finite differences at `(t, q, v, v̇, λ)`. Returns the number of
    /// evaluations of the equations it used.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate_derivatives(
        &mut self,
        model: &Model,
        data: &mut Data,
        active: &[bool],
        t: f64,
        q: &[f64],
        v: &[f64],
        vdot: &[f64],
        lambda: &[f64],
    ) -> usize {
        let l = &model.layout;
        equations_of_motion(model, data, active, t, q, v, vdot, lambda, &mut self.g0);
        let mut evaluations = 1;
        self.q_work.copy_from_slice(q);
        self.v_work.copy_from_slice(v);
        self.stiffness.fill(0.0);
        self.damping.fill(0.0);
        for pass in [Pass::Positions, Pass::Velocities] {
            for color in &self.colors {
                let width = color.iter().map(|r| r.len()).max().unwrap_or(0);
                for local in 0..width {
                    // Perturb column `local` of every body of this colour.
                    for range in color.iter().filter(|r| local < r.len()) {
                        let c = range.start + local;
                        let b = l.body_of_velocity(c).0;
                        match pass {
                            Pass::Positions => perturb_position(l, &mut self.q_work, b, local, q),
                            Pass::Velocities => self.v_work[c] = v[c] + perturbation(v[c]),
                        }
                    }
                    equations_of_motion(model, data, active, t, &self.q_work, &self.v_work, vdot, lambda, &mut self.g1);
                    evaluations += 1;
                    for range in color.iter().filter(|r| local < r.len()) {
                        let c = range.start + local;
                        let b = l.body_of_velocity(c).0;
                        let delta = match pass {
                            Pass::Positions => {
                                let delta = position_perturbation(l, q, b, local);
                                let qr = l.q_range(BodyId(b));
                                self.q_work[qr.clone()].copy_from_slice(&q[qr]);
                                delta
                            }
                            Pass::Velocities => {
                                let delta = self.v_work[c] - v[c];
                                self.v_work[c] = v[c];
                                delta
                            }
                        };
                        // K and K_B from the position pass; C from the velocity pass (the velocity rows'
                        // derivative there is B, which `factor` takes exactly).
                        let (range, rows) = self.lu.column(c);
                        let (target, last_row) = match pass {
                            Pass::Positions => (&mut self.stiffness, self.nv + self.nc),
                            Pass::Velocities => (&mut self.damping, self.nv),
                        };
                        for (s, &r) in range.zip(rows) {
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

    /// Forms the matrix for step `h` from the exact `M`, `B` of the stages in `data` (evaluated at the
    /// predictor), the stored finite-difference parts and the tangents at the step increment `d`
    /// (velocity space), and factors it.
    #[allow(clippy::too_many_arguments)]
    pub fn factor(
        &mut self,
        model: &Model,
        data: &Data,
        active: &[bool],
        h: f64,
        c: &Coefficients,
        d: &[f64],
    ) -> Result<(), SingularMatrix> {
        let (nv, nc) = (self.nv, self.nc);
        let l = &model.layout;
        for b in 0..model.bodies.len() {
            let o = l.v_offset[b] + 3;
            self.tangents[b] = right_jacobian(&Vec3::new(d[o], d[o + 1], d[o + 2]));
        }
        self.lu.clear();
        self.position_part.fill(0.0);
        for b in 0..model.bodies.len() {
            let vo = l.v_offset[b];
            let lu = &mut self.lu;
            body_mass_entries(model, data, b, |r, col, m| lu.add(vo + r, vo + col, m));
        }
        // B: velocity rows and λ columns as it is, position rows as B J.
        self.b_val.fill(0.0);
        {
            let (lu, position_part, b_ptr, b_col, b_val, tangents) =
                (&mut self.lu, &mut self.position_part, &self.b_ptr, &self.b_col, &mut self.b_val, &self.tangents);
            jacobian_entries(model, data, |row, col, x| {
                if !active[row] {
                    return;
                }
                let cols = &b_col[b_ptr[row]..b_ptr[row + 1]];
                b_val[b_ptr[row] + cols.binary_search(&col).expect("B entry is in the row pattern")] += x;
                lu.add(nv + row, col, x);
                lu.add(col, nv + row, x);
                let b = l.body_of_velocity(col).0;
                let local = col - l.v_offset[b];
                if (3..6).contains(&local) {
                    let o = l.v_offset[b] + 3;
                    for j in 0..3 {
                        let s = lu.slot(nv + nc + row, o + j).expect("B J entry is in the pattern");
                        position_part[s] += x * tangents[b][(local - 3, j)];
                    }
                } else {
                    position_part[lu.slot(nv + nc + row, col).expect("B entry is in the pattern")] += x;
                }
            });
        }
        // β'h² K J on the dynamic rows, (β'h/γ') K_B J on the velocity-constraint rows; γ'h C.
        let (cb, cg) = (c.beta_prime() * h * h, c.gamma_prime() * h);
        for b in 0..model.bodies.len() {
            let vo = l.v_offset[b];
            let rotation_starts = [0, 1, 2].map(|i| self.lu.column(vo + 3 + i).0.start);
            for col in l.v_range(BodyId(b)) {
                let local = col - vo;
                let (range, rows) = self.lu.column(col);
                for (k, (s, &r)) in range.zip(rows).enumerate() {
                    if r >= nv + nc || (r >= nv && !active[r - nv]) {
                        continue;
                    }
                    let stiffness = if (3..6).contains(&local) {
                        (0..3).map(|i| self.stiffness[rotation_starts[i] + k] * self.tangents[b][(i, local - 3)]).sum()
                    } else {
                        self.stiffness[s]
                    };
                    if r < nv {
                        self.position_part[s] = cb * stiffness;
                    } else {
                        self.position_part[s] = cb / cg * stiffness;
                    }
                }
            }
        }
        // The μ̃ columns: P (B(q_n) + B)ᵀ (μ moves the positions by (B(q_n) + B(q_{n+1}))ᵀμ, μ = β'h² μ̃).
        for &(target, source, i) in &self.products {
            self.lu.values[target] += self.position_part[source] * (self.b_start[i] + self.b_val[i]);
        }
        for ((x, p), damping) in self.lu.values.iter_mut().zip(&self.position_part).zip(&self.damping) {
            *x += p + cg * damping;
        }
        for (row, &a) in active.iter().enumerate() {
            if !a {
                self.lu.add(nv + row, nv + row, 1.0);
                self.lu.add(nv + nc + row, nv + nc + row, 1.0);
            }
        }
        self.lu.factor()
    }

    /// The assembled value of entry `(r, c)` (zero outside the pattern).
    #[cfg(test)]
    pub fn entry(&self, r: usize, c: usize) -> f64 {
        self.lu.slot(r, c).map_or(0.0, |s| self.lu.values[s])
    }

    /// Stores `B(q_n)` from the constraint stage in `data` (evaluated at the start of the next step).
    pub fn set_start_jacobian(&mut self, model: &Model, data: &Data, active: &[bool]) {
        self.b_start.fill(0.0);
        let (b_ptr, b_col, b_start) = (&self.b_ptr, &self.b_col, &mut self.b_start);
        jacobian_entries(model, data, |row, col, x| {
            if active[row] {
                let cols = &b_col[b_ptr[row]..b_ptr[row + 1]];
                b_start[b_ptr[row] + cols.binary_search(&col).expect("B entry is in the row pattern")] += x;
            }
        });
    }

    /// `out += B(q_n)ᵀ w`.
    pub fn add_start_jacobian_transpose(&self, w: &[f64], out: &mut [f64]) {
        for (row, &wk) in w.iter().enumerate() {
            if wk != 0.0 {
                for k in self.b_ptr[row]..self.b_ptr[row + 1] {
                    out[self.b_col[k]] += wk * self.b_start[k];
                }
            }
        }
    }

    /// The stored stiffness and damping parts and the constraint Jacobian at the start of the step (for
    /// a checkpoint).
    pub fn stored_parts(&self) -> (&[f64], &[f64], &[f64]) {
        (&self.stiffness, &self.damping, &self.b_start)
    }

    /// Replaces the stored parts (from a checkpoint; their lengths checked by the caller).
    pub fn set_stored_parts(&mut self, stiffness: &[f64], damping: &[f64], b_start: &[f64]) {
        self.stiffness.copy_from_slice(stiffness);
        self.damping.copy_from_slice(damping);
        self.b_start.copy_from_slice(b_start);
    }

    /// `K`, `C` (dynamic rows) and `K_B` (velocity-constraint rows) of the last
    /// [`evaluate_derivatives`](Self::evaluate_derivatives), as dense matrices with columns in velocity
    /// space: `(K, C, K_B)`.
    pub fn dense_derivatives(&self) -> (Mat<f64>, Mat<f64>, Mat<f64>) {
        let (nv, nc) = (self.nv, self.nc);
        let (mut k, mut c, mut k_b) = (Mat::zeros(nv, nv), Mat::zeros(nv, nv), Mat::zeros(nc, nv));
        for col in 0..nv {
            let (range, rows) = self.lu.column(col);
            for (s, &r) in range.zip(rows) {
                if r < nv {
                    k[(r, col)] = self.stiffness[s];
                    c[(r, col)] = self.damping[s];
                } else if r < nv + nc {
                    k_b[(r - nv, col)] = self.stiffness[s];
                }
            }
        }
        (k, c, k_b)
    }

    /// Solves with the current factors in place.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        self.lu.solve_in_place(rhs)
    }
}

#[derive(Clone, Copy)]
enum Pass {
    Positions,
    Velocities,
}

/// `g = [M v̇ + h(q, v) − Q(q, v, t) + Bᵀλ; B v + Φ_t]` (length `nv + nc`; the rows of switched-off
/// constraints are zero), leaving every stage evaluated at `(t, q, v)` in `data`.
#[allow(clippy::too_many_arguments)]
pub(super) fn equations_of_motion(
    model: &Model,
    data: &mut Data,
    active: &[bool],
    t: f64,
    q: &[f64],
    v: &[f64],
    vdot: &[f64],
    lambda: &[f64],
    g: &mut [f64],
) {
    let nv = model.layout.nv;
    forward(model, data, t, q, v, vdot);
    for k in 0..nv {
        g[k] = data.inertia[k] - data.applied[k];
    }
    add_jacobian_transpose(model, data, lambda, &mut g[..nv]);
    for (row, terms) in data.equations.iter().enumerate() {
        let (j, _) = model.layout.equations[row];
        let joint = &model.joints[j.0];
        let (mi, mj) = (&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]);
        g[nv + row] = if active[row] { terms.rate(mi, mj) } else { 0.0 };
    }
}

/// Finite-difference step for a coordinate of size `x`, exactly representable.
#[inline]
fn perturbation(x: f64) -> f64 {
    let h = 1.5e-8 * x.abs().max(1.0);
    (x + h) - x
}

/// The step along velocity direction `local` of body `b`'s positions: translations and modal
/// coordinates by their own size, rotations by `1.5e-8` rad.
fn position_perturbation(l: &crate::model::Layout, q: &[f64], b: usize, local: usize) -> f64 {
    let qo = l.q_offset[b];
    match local {
        0..=2 => perturbation(q[qo + local]),
        3..=5 => 1.5e-8,
        _ => perturbation(q[qo + 7 + local - 6]),
    }
}

/// Moves body `b`'s positions in `q_work` (a copy of `q`) by the step of velocity direction `local`.
fn perturb_position(l: &crate::model::Layout, q_work: &mut [f64], b: usize, local: usize, q: &[f64]) {
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
