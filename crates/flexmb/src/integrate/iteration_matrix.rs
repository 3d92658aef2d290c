//! The Newton iteration matrix `∂F/∂y + (1/c) ∂F/∂ẏ` of the DAE residual (rows with a derivative scaled by
//! `c`), on a sparse pattern derived once from the model's coupling graph.
//!
//! `∂F/∂y` of the multipliers' columns (`λ`, `μ`, the normalization's) is analytic: the residual is
//! linear in them, and its derivatives are the joints' constraint Jacobian `B` where they act
//! ([`multiplier_jacobian_entries`]). That of the positions and velocities comes from finite differences
//! of the residual with the columns grouped by a greedy colouring (Curtis, Powell and Reid 1974): columns
//! of bodies that share no equation are perturbed together, so the cost grows with the colour count, not
//! the model size. `∂F/∂ẏ` is exact: the identity on the
//! kinematic rows and the body mass matrices on the dynamic rows. Both are kept, so a change of step size
//! only refactors: `values = c·F_y + F_ẏ` on the differential rows.

use std::ops::Range;

use crate::data::Data;
use super::CheckpointError;
use crate::linalg::{greedy_colouring, perturbation, InvalidPivots, SingularMatrix, SparseLu};
use crate::model::{Coupling, Model};
use crate::stage::{inertia_jacobian_entries, multiplier_jacobian_entries, residual, StateJacobian, YLayout};

/// Iteration matrix with stored derivative parts and reusable LU factors.
pub(crate) struct IterationMatrix {
    lu: SparseLu,
    f_y: Vec<f64>,
    f_yp: Vec<f64>,
    n_differential: usize,
    /// The analytic positions' and velocities' columns (of the bodies that allow them).
    state_jacobian: StateJacobian,
    /// Column blocks (of one body or joint) grouped by colour: the positions' and velocities' columns
    /// that are not analytic.
    colors: Vec<Vec<Range<usize>>>,
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
            let r = l.q_span(b);
            yl.q.start + r.start..yl.q.start + r.end
        };
        let fv = |b: usize| {
            let r = l.v_span(b);
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

        let Coupling { joint_bodies, joints_of, readers, joint_neighbours } = Coupling::new(model);

        // Column blocks and the row blocks each one touches.
        let mut columns: Vec<(Range<usize>, Vec<usize>)> = Vec::new();
        for b in 0..nb {
            let mut touched: Vec<usize> = joint_neighbours[b].iter().map(|&n| id_fq(n)).collect();
            touched.extend(readers[b].iter().map(|&c| id_fv(c)));
            touched.extend(joints_of[b].iter().flat_map(|&k| [id_lam(k), id_mu(k)]));
            touched.push(id_norm(b));
            columns.push((fq(b), touched));
            let mut touched: Vec<usize> = vec![id_fq(b)];
            touched.extend(readers[b].iter().map(|&c| id_fv(c)));
            touched.extend(joints_of[b].iter().map(|&k| id_lam(k)));
            columns.push((fv(b), touched));
            columns.push((norm(b), vec![id_fq(b)]));
        }
        for (k, bodies) in joint_bodies.iter().enumerate() {
            if l.joint_rows[k].is_empty() {
                continue;
            }
            let mut touched: Vec<usize> = bodies.iter().map(|&b| id_fv(b)).collect();
            touched.push(id_lam(k));
            columns.push((lam(k), touched));
            let mut touched: Vec<usize> = bodies.iter().map(|&b| id_fq(b)).collect();
            touched.push(id_mu(k));
            columns.push((mu(k), touched));
        }

        // The analytic bodies' positions' and velocities' columns hold the entries their formulas give
        // (`StateJacobian::entries`, `F_ẏ`'s identity and mass matrix) and no others: far fewer than the
        // dense blocks of the coupling graph (on a chain of rods 24 of 52 rows in an Euler parameter's
        // column, 3 in a position's), and the factors' fill and arithmetic follow the pattern.
        let state_jacobian = StateJacobian::new(model);
        let analytic_block = |k: usize| k < 3 * nb && k % 3 != 2 && state_jacobian.is_analytic(k / 3);
        let mut entries = analytic_state_entries(model, yl, &state_jacobian);
        for (k, (block, touched)) in columns.iter().enumerate() {
            if analytic_block(k) {
                continue;
            }
            for &rb in touched {
                for r in row_ranges[rb].clone() {
                    for c in block.clone() {
                        entries.push((r, c));
                    }
                }
            }
        }
        let n = yl.len();
        let lu = SparseLu::with_kept_pivots(n, entries);

        // Blocks of one colour touch disjoint row blocks. Only the positions' and velocities' columns of
        // the bodies without analytic ones are differenced; the multipliers' (from λ on) are analytic.
        // The first 3 nb column blocks are the bodies' (positions, velocities, normalization).
        let differenced: Vec<usize> =
            (0..columns.len()).filter(|&k| columns[k].0.start < yl.lambda.start && !analytic_block(k)).collect();
        let touched: Vec<Vec<usize>> = differenced.iter().map(|&k| columns[k].1.clone()).collect();
        let colors = greedy_colouring(&touched, n_row_blocks)
            .into_iter()
            .map(|blocks| blocks.into_iter().map(|i| columns[differenced[i]].0.clone()).collect())
            .collect();
        let nnz = lu.values.len();
        Self {
            lu,
            f_y: vec![0.0; nnz],
            f_yp: vec![0.0; nnz],
            n_differential: yl.n_differential(),
            state_jacobian,
            colors,
            f0: vec![0.0; n],
            f1: vec![0.0; n],
            y_work: vec![0.0; n],
        }
    }

    /// The entries of `F_y` on the sparse pattern that are analytic (those of the multipliers' columns
    /// and of the analytic bodies' positions and velocities), and all of them.
    #[cfg(test)]
    pub fn analytic_entries(&self) -> (usize, usize) {
        let differenced: usize = self.colors.iter().flatten().flat_map(|b| b.clone()).map(|c| self.lu.column(c).1.len()).sum();
        (self.f_y.len() - differenced, self.f_y.len())
    }

    /// Number of residual evaluations one Jacobian costs (besides the base point).
    pub fn evaluations_per_jacobian(&self) -> usize {
        self.colors.iter().map(|c| c.iter().map(|b| b.len()).max().unwrap_or(0)).sum()
    }

    /// Re-evaluates `F_y` (analytic in the multipliers' columns, finite differences in the others) and
    /// `F_ẏ` at `(t, y, ẏ)`. Returns the residual evaluations used.
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
            for k in model.layout.q_span(b) {
                let s = self.lu.slot(yl.q.start + k, yl.q.start + k).expect("diagonal is in the pattern");
                self.f_yp[s] = 1.0;
            }
            let v0 = yl.v.start + model.layout.v_offset[b];
            let (lu, f_yp) = (&self.lu, &mut self.f_yp);
            inertia_jacobian_entries(model, data, b, |r, c, m| match lu.slot(v0 + r, v0 + c) {
                Some(s) => f_yp[s] += m,
                None => debug_assert!(m == 0.0, "mass entry ({r}, {c}) = {m} outside the pattern"),
            });
        }
        self.f_y.fill(0.0);
        let (lu, f_y) = (&self.lu, &mut self.f_y);
        multiplier_jacobian_entries(model, data, yl, &y[yl.q.clone()], active, |r, c, x| {
            if let Some(s) = lu.slot(r, c) {
                f_y[s] += x;
            }
        });
        self.state_jacobian.entries(model, data, yl, y, yp, active, |r, c, x| match lu.slot(r, c) {
            Some(s) => f_y[s] += x,
            None => debug_assert!(x == 0.0, "analytic entry ({r}, {c}) = {x} outside the pattern"),
        });
        self.y_work.copy_from_slice(y);
        for color in &self.colors {
            let width = color.iter().map(|b| b.len()).max().unwrap_or(0);
            for local in 0..width {
                for block in color.iter().filter(|b| local < b.len()) {
                    let c = block.start + local;
                    self.y_work[c] = y[c] + perturbation(y[c]);
                }
                residual(model, data, yl, active, t, &self.y_work, yp, &mut self.f1);
                evaluations += 1;
                for block in color.iter().filter(|b| local < b.len()) {
                    let c = block.start + local;
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

    /// `out = |A| |y|`, `A` the matrix last formed by [`factor`](Self::factor): the row sums of the
    /// magnitudes whose rounding the residual at `y` carries (see `rounding_level`).
    pub fn absolute_product(&self, y: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for c in 0..self.lu.n() {
            let (range, rows) = self.lu.column(c);
            let yc = y[c].abs();
            for (x, &r) in self.lu.values[range].iter().zip(rows) {
                out[r] += x.abs() * yc;
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

/// The entries `(row, column)` of the analytic bodies' positions' and velocities' columns of the
/// iteration matrix: those `StateJacobian::entries` gives with every constraint row in force, the
/// positions' diagonal and the mass matrix (`F_ẏ`), less those that the model's constants make zero
/// whatever the state (a rod's first moment about its centre of mass: its translation's rows then read
/// neither its rotation nor its angular velocity; a joint marker at a body's origin). An entry that is
/// zero at a generic state, here two states of pseudo-random numbers (Euler parameters off the unit
/// sphere, velocities, accelerations, multipliers), is such a zero: the entries are polynomials and
/// quotients of the state that vanish on a set of measure zero unless they vanish everywhere.
fn analytic_state_entries(model: &Model, yl: &YLayout, state_jacobian: &StateJacobian) -> Vec<(usize, usize)> {
    let l = &model.layout;
    let mut data = Data::new(model);
    let active = vec![true; l.nc];
    let (mut y, mut yp, mut f) = (vec![0.0; yl.len()], vec![0.0; yl.len()], vec![0.0; yl.len()]);
    let mut entries = Vec::new();
    // A 64-bit linear congruential generator (Knuth's MMIX constants), numbers in [0.5, 1.5).
    let mut seed: u64 = 0x5eed;
    let mut generic = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        0.5 + (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..2 {
        y.iter_mut().chain(yp.iter_mut()).for_each(|x| *x = generic());
        residual(model, &mut data, yl, &active, 0.0, &y, &yp, &mut f);
        state_jacobian.entries(model, &data, yl, &y, &yp, &active, |r, c, x| {
            if x != 0.0 {
                entries.push((r, c));
            }
        });
        for b in (0..model.bodies.len()).filter(|&b| state_jacobian.is_analytic(b)) {
            entries.extend(l.q_span(b).map(|k| (yl.q.start + k, yl.q.start + k)));
            let v0 = yl.v.start + l.v_offset[b];
            inertia_jacobian_entries(model, &data, b, |r, c, m| {
                if m != 0.0 {
                    entries.push((v0 + r, v0 + c));
                }
            });
        }
    }
    entries
}

/// Keeps the pivot sequence of a checkpoint (or none) in an iteration matrix's LU, BDF's or generalized-α's;
/// a sequence that does not fit the matrix is the checkpoint's error.
pub(crate) fn keep_checkpoint_pivots(lu: &mut SparseLu, row_positions: Option<&[usize]>) -> Result<(), CheckpointError> {
    lu.keep_pivots(row_positions).map_err(|InvalidPivots| {
        CheckpointError::Unsupported(format!(
            "the checkpoint's kept pivots do not fit the iteration matrix ({} unknowns): not a permutation of its rows, or a zero pivot on its pattern",
            lu.n()
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::test_models;

    /// The coloured, pattern-restricted Jacobian equals a dense finite-difference one: no dependency is
    /// missing from the pattern, no two columns of one colour share a row, and the analytic columns of the
    /// multipliers are right. The residual is linear in the multipliers, so their dense columns are
    /// differenced with a step of 1, exact to round-off (with the positions' step, about 1e-8, round-off
    /// in residuals of order 100 leaves 1e-6 in the difference quotient).
    #[test]
    fn coloured_jacobian_matches_dense_finite_differences() {
        coloured_against_dense(crate::analysis::test_models::double_pendulum_with_spring());
        coloured_against_dense(crate::analysis::test_models::pendulum_with_stiff_slider());
    }

    /// With the multipliers' columns analytic, a Jacobian of the double pendulum costs at most the
    /// positions' and velocities' columns of its two bodies, 2 × (7 + 6) = 26 residuals, whatever its
    /// joints; the analytic entries are the multipliers' columns, 253 of the 1119 entries of `F_y`.
    #[test]
    fn the_multipliers_columns_are_analytic() {
        let model = crate::analysis::test_models::double_pendulum_with_spring();
        let yl = YLayout::new(&model);
        let jac = IterationMatrix::new(&model, &yl);
        assert!(jac.evaluations_per_jacobian() <= 26, "{} evaluations", jac.evaluations_per_jacobian());
        assert_eq!(jac.analytic_entries(), (253, 1119));
    }

    /// On bodies that only gravity and spherical, revolute and universal joints act on, the positions'
    /// and velocities' columns are analytic too (`stage/state_jacobian.rs`), and equal dense finite
    /// differences to the same tolerance, with the Euler parameters off the unit sphere as inside a
    /// Newton iteration: the chain of rods, independent spherical pendulums, and a triple pendulum of
    /// tilted links with offset centres of mass on a spherical, a revolute and a universal joint.
    #[test]
    fn analytic_state_columns_match_dense_finite_differences() {
        coloured_against_dense(test_models::spherical_chain(4));
        coloured_against_dense(test_models::spherical_pendulums(3));
        let triple = test_models::spatial_triple_pendulum();
        let yl = YLayout::new(&triple);
        assert_eq!(IterationMatrix::new(&triple, &yl).evaluations_per_jacobian(), 0, "every column analytic");
        coloured_against_dense(triple);
    }

    /// On the chain of 32 rods every entry of `F_y` is analytic and a Jacobian costs no residual besides
    /// the base point; so on one spherical pendulum, the heavy top's structure. The pattern holds the
    /// entries the formulas give (`stage/state_jacobian.rs`, the mass matrix, the positions' `F_ẏ`) that
    /// the model does not make zero. Per rod on `j` spherical joints: the 3 position columns hold the
    /// diagonal and one point row per joint, `3 (1 + j)`; the 4 Euler parameters' the 4 kinematic rows,
    /// the 2 transverse rotational dynamic rows (no first moment; the axial row's `s̄ × …` vanishes along
    /// the rod), the normalization's and 6 constraint rows per joint, `4 (7 + 6 j)`; the 3 translational
    /// velocities' one kinematic row, the mass `m` and one velocity row per joint, `3 (2 + j)`; the 3
    /// angular velocities' 12 kinematic entries, 7 dynamic (the axial row holds `J̄`'s diagonal alone,
    /// `J̄ = diag(a, b, b)`) and 3 velocity rows per joint but in the axial column, `19 + 6 j`:
    /// `56 + 36 j` in all. The chain of 32 rods has 63 joint ends (the first
    /// joint's other end is ground): 56 × 32 + 36 × 63 = 4,060, with the multipliers' columns' 3,289
    /// entries 7,349 (the coupling graph's dense blocks were 20,575); the pendulum 56 + 36 + 65 = 157
    /// (301).
    #[test]
    fn the_chain_s_jacobian_is_analytic() {
        for (model, entries, multipliers) in
            [(test_models::spherical_chain(32), 7_349, 3_289), (test_models::spherical_pendulums(1), 157, 65)]
        {
            let yl = YLayout::new(&model);
            let jac = IterationMatrix::new(&model, &yl);
            assert_eq!(jac.evaluations_per_jacobian(), 0);
            assert_eq!(jac.analytic_entries(), (entries, entries));
            let in_multiplier_columns: usize = (yl.lambda.start..yl.len()).map(|c| jac.lu.column(c).1.len()).sum();
            assert_eq!(in_multiplier_columns, multipliers);
        }
    }

    /// The factors of a chain's iteration matrix on kept pivots grow linearly with its rods: from 8
    /// to 64 rods, the entries of `L` and `U` and the multiply–adds of a refactorization grow by at
    /// most 2.5 per doubling (2 for a pattern that repeats per rod, plus the fill-reducing ordering's
    /// variations; measured: entries ×2.16, ×2.08, ×2.04, multiply–adds ×2.33, ×2.16, ×2.07).
    #[test]
    fn the_factors_of_a_chain_grow_linearly_with_its_rods() {
        let mut counts = Vec::new();
        for rods in [8, 16, 32, 64] {
            let model = test_models::spherical_chain(rods);
            let (mut data, state, acc) = test_models::moving_state(&model);
            let yl = YLayout::new(&model);
            let mut y = vec![0.0; yl.len()];
            y[yl.q.clone()].copy_from_slice(&state.q);
            y[yl.v.clone()].copy_from_slice(&state.v);
            y[yl.lambda.clone()].copy_from_slice(&acc.lambda);
            let mut jac = IterationMatrix::new(&model, &yl);
            jac.evaluate(&model, &mut data, &yl, &state.active, 0.1, &y, &vec![0.0; yl.len()]);
            jac.factor(1e-3).unwrap();
            let factors = jac.lu.kept_factors().expect("kept pivots above the dense limit");
            counts.push((rods, factors.factor_entries(), factors.refactor_operations()));
        }
        for w in counts.windows(2) {
            let (a, b) = (w[0], w[1]);
            assert!(b.1 as f64 <= 2.5 * a.1 as f64 && b.2 as f64 <= 2.5 * a.2 as f64, "{counts:?}");
        }
    }

    fn coloured_against_dense(model: Model) {
        let (mut data, state, acc) = test_models::moving_state(&model);
        let yl = YLayout::new(&model);
        let n = yl.len();
        let mut y = vec![0.0; n];
        y[yl.q.clone()].copy_from_slice(&state.q);
        y[yl.v.clone()].copy_from_slice(&state.v);
        y[yl.lambda.clone()].copy_from_slice(&acc.lambda);
        for k in yl.mu.clone() {
            y[k] = 1e-3 * (k as f64).cos();
        }
        // Euler parameters off the unit sphere by 1e-3, as inside a Newton iteration.
        for b in 0..model.bodies.len() {
            let o = yl.q.start + model.layout.q_offset[b] + 3;
            for k in o..o + 4 {
                y[k] *= 1.0 + 1e-3 * (1.0 + b as f64).sin();
            }
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
            let h = if c >= yl.lambda.start { 1.0 } else { perturbation(y[c]) };
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
