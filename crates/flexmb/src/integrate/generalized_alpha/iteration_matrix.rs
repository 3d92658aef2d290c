//! The Newton iteration matrix of a generalized-α step, unknowns `x = [v̇, λ, μ̃]`, rows
//! `[dynamics (nv); velocity constraints / (γ'h) (nc); position constraints / (β'h²) (nc)]`:
//!
//! ```text
//! ┌ M + γ'h C + β'h² K J     Bᵀ    β'h² K J Bᵀ      ┐
//! │ B + (β'h/γ') K_B J       0     (β'h/γ') K_B J Bᵀ │    β' = β (1 − α_f)/(1 − α_m),  γ' = γ (1 − α_f)/(1 − α_m)
//! └ B J                      0     B J Bᵀ           ┘
//! ```
//! `M` (from `inertia_jacobian_entries`: the mass matrix and the geometric stiffening's acceleration columns) and `B` (from `jacobian_entries`) are exact, evaluated afresh at the
//! predictor of every step attempt. `K = ∂g/∂q` and `C = ∂g/∂v` of `g = M v̇ + h(q, v) − Q + Bᵀλ`, and
//! `K_B = ∂(B v + Φ_t)/∂q`, are the linearization's
//! ([`SparseLinearization`](crate::analysis::SparseLinearization): coloured finite differences, positions perturbed in velocity space like the step's own update); they are
//! kept until a Newton iteration fails to converge with them, and since they are stored apart from `h`, a new
//! step size only refactors. `J` is block diagonal: in each body's rotation columns the tangent `J_r(d_ω̄)`
//! of the exponential map at the step increment `d` (Brüls and Cardona's tangent operator; `q_n ∘ exp(d)`
//! moves by `exp(J_r(d) δd)` when `d` moves by `δd`), the identity elsewhere. The `μ̃` columns are the
//! position columns times `Bᵀ`, since `μ` moves the positions by `Bᵀμ`: the stabilizing multiplier is not
//! small at a finite step (it absorbs the `O(h³)` mismatch of the position and velocity constraints), and
//! leaving its coupling to the dynamics out slowed the Newton iteration to a linear rate of 0.2 to 0.8 on a
//! pendulum. The constraint rows are scaled so that every block stays of order one as `h → 0`, where the
//! matrix tends to `[M Bᵀ 0; B 0 0; B 0 BBᵀ]`.

use crate::stage::right_jacobian;
use super::Coefficients;
use crate::analysis::SparseLinearization;
use crate::data::Data;
use crate::integrate::CheckpointError;
use crate::integrate::iteration_matrix::keep_checkpoint_pivots;
use crate::linalg::{SingularMatrix, SparseLu};
use crate::math::{Mat3, Vec3};
use crate::model::{Coupling, Model};
use crate::stage::geometric_stiffening::interface_reaction_entries;
use crate::stage::{inertia_jacobian_entries, jacobian_entries};

/// The iteration matrix on its fixed sparse pattern, with the stored finite-difference parts.
pub(crate) struct IterationMatrix {
    lu: SparseLu,
    nv: usize,
    nc: usize,
    /// `K`, `C` (dynamic rows) and `K_B` (velocity-constraint rows), columns `v̇`, evaluated by the
    /// integrator when it refreshes them: column `c` of their pattern is the part of LU column `c` above
    /// the position-constraint rows.
    pub(super) derivatives: SparseLinearization,
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
}

impl IterationMatrix {
    pub fn new(model: &Model) -> Self {
        let l = &model.layout;
        let (nb, nv, nc) = (model.bodies.len(), l.nv, l.nc);
        let v_range = |b: usize| l.v_span(b);
        let coupling = Coupling::new(model);
        let Coupling { joint_bodies, joints_of, readers, .. } = &coupling;
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
        let lu = SparseLu::with_kept_pivots(nv + 2 * nc, entries);
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

        // The rotation columns of a body share one row list (whole blocks are entered), which lets
        // `factor` combine them with `J_r` slot by slot.
        for b in 0..nb {
            let o = l.v_offset[b] + 3;
            for i in 1..3 {
                assert_eq!(lu.column(o).1, lu.column(o + i).1, "rotation columns of body {b} share their rows");
            }
        }
        let derivatives = SparseLinearization::with_coupling(model, &coupling);
        for c in 0..nv {
            let rows = derivatives.column(c).1;
            assert_eq!(rows, &lu.column(c).1[..rows.len()], "the linearization's column {c} heads the LU column");
        }
        let nnz = lu.values.len();
        let n_b = b_col.len();
        Self {
            lu,
            nv,
            nc,
            derivatives,
            b_ptr,
            b_col,
            b_val: vec![0.0; n_b],
            b_start: vec![0.0; n_b],
            tangents: vec![Mat3::identity(); nb],
            products,
            position_part: vec![0.0; nnz],
        }
    }

    /// Evaluations of `g` one evaluation of the derivative parts costs.
    pub fn evaluations_per_jacobian(&self) -> usize {
        self.derivatives.evaluations()
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
            inertia_jacobian_entries(model, data, b, |r, col, m| lu.add(vo + r, vo + col, m));
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
                let b = l.velocity_body(col);
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
        // The joints' interface stiffening, linear in λ: beside Bᵀ in the dynamic rows.
        {
            let lu = &mut self.lu;
            interface_reaction_entries(model, data, |row, col, x| {
                if active[row] {
                    lu.add(col, nv + row, x);
                }
            });
        }
        // β'h² K J on the dynamic rows, (β'h/γ') K_B J on the velocity-constraint rows; γ'h C.
        let (cb, cg) = (c.beta_prime() * h * h, c.gamma_prime() * h);
        let stored = self.derivatives.stiffness();
        for b in 0..model.bodies.len() {
            let vo = l.v_offset[b];
            let rotation_starts = [0, 1, 2].map(|i| self.derivatives.column(vo + 3 + i).0.start);
            for col in l.v_span(b) {
                let local = col - vo;
                let start = self.derivatives.column(col).0.start;
                let (range, rows) = self.lu.column(col);
                for (k, (s, &r)) in range.zip(rows).enumerate() {
                    if r >= nv + nc || (r >= nv && !active[r - nv]) {
                        continue;
                    }
                    let stiffness = if (3..6).contains(&local) {
                        (0..3).map(|i| stored[rotation_starts[i] + k] * self.tangents[b][(i, local - 3)]).sum()
                    } else {
                        stored[start + k]
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
        for col in 0..self.lu.n() {
            let damping: &[f64] = if col < nv { &self.derivatives.damping()[self.derivatives.column(col).0] } else { &[] };
            let start = self.lu.column(col).0.start;
            let (values, _) = self.lu.column_mut(col);
            for (k, x) in values.iter_mut().enumerate() {
                *x += self.position_part[start + k] + cg * damping.get(k).copied().unwrap_or(0.0);
            }
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
        (self.derivatives.stiffness(), self.derivatives.damping(), &self.b_start)
    }

    /// Replaces the stored parts (from a checkpoint; their lengths checked by the caller).
    pub fn set_stored_parts(&mut self, stiffness: &[f64], damping: &[f64], b_start: &[f64]) {
        self.derivatives.set_values(stiffness, damping);
        self.b_start.copy_from_slice(b_start);
    }

    /// The matrix the current factors were made of, in the order of its sparse pattern (for a checkpoint).
    pub fn factored_values(&self) -> &[f64] {
        &self.lu.values
    }

    /// Factors `values`, the matrix of a checkpoint (its length checked by the caller).
    pub fn factor_values(&mut self, values: &[f64]) -> Result<(), SingularMatrix> {
        self.lu.values.copy_from_slice(values);
        self.lu.factor()
    }

    /// The pivot sequence its factorizations keep (for a checkpoint; `None` when none is kept).
    pub fn kept_pivots(&self) -> Option<&[usize]> {
        self.lu.kept_pivots()
    }

    /// Keeps the pivot sequence of a checkpoint (or none) for the next factorizations.
    pub fn keep_pivots(&mut self, row_positions: Option<&[usize]>) -> Result<(), CheckpointError> {
        keep_checkpoint_pivots(&mut self.lu, row_positions)
    }

    /// Solves with the current factors in place.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        self.lu.solve_in_place(rhs)
    }
}
