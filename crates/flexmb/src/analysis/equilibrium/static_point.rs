//! The static equations at one configuration: the generalized forces `f = h(q, 0) − Q(q, 0, t)` (no
//! inertia, `v = 0`, `v̇ = 0`), the constraint Jacobian `B` of the rows in force, the basis `N` of its
//! null space (the motions the constraints allow), the multipliers that balance `f` best,
//! `λ = argmin ‖f + Bᵀλ‖` (with the joints' interface stiffening `W λ` added to `f`), and the residual
//! `f + Bᵀλ + W λ` that is left: zero at a static equilibrium.

use faer::Mat;

use crate::analysis::State;
use crate::data::Data;
use crate::model::Model;
use crate::stage::geometric_stiffening::add_interface_reactions;
use crate::stage::{jacobian_entries, run_force_stages, run_kinematic_stages};

/// Singular values of `B` below this fraction of the largest are taken as zero (the rows in force are
/// independent after the assembly; this only guards the least-squares multipliers).
const RANK_TOLERANCE: f64 = 1e-10;

/// Passes of the multipliers' fixed-point iteration with the joints' interface stiffening.
const INTERFACE_PASSES: usize = 4;

/// The static equations at one configuration.
pub(super) struct StaticPoint {
    /// `f = h − Q` at `v = 0`, `v̇ = 0` (length `nv`).
    pub force: Vec<f64>,
    /// `N`: orthonormal basis of the null space of `B`, `nv × dof`.
    pub null_space: Mat<f64>,
    /// `B⁺ = V_r Σ_r⁻¹ U_rᵀ` in factors (rows in force): the least change of the positions that closes
    /// a constraint residual ([`least_change`](Self::least_change)).
    pseudo_inverse: PseudoInverse,
    /// `Φ` of the rows in force.
    pub phi: Vec<f64>,
    /// Multipliers, one per constraint row (zero for the rows switched off).
    pub lambda: Vec<f64>,
    /// `f + Bᵀλ + W λ` (length `nv`).
    pub residual: Vec<f64>,
}

impl StaticPoint {
    /// The static equations at `state.q`, `state.t` with the rows in force of `state.active`; leaves
    /// the stages evaluated there (at `v = 0`) in `data`.
    pub fn evaluate(model: &Model, data: &mut Data, state: &State) -> Self {
        let l = &model.layout;
        let zero = vec![0.0; l.nv];
        run_kinematic_stages(model, data, state.t, &state.q, &zero);
        let rows: Vec<usize> = (0..l.nc).filter(|&r| state.active[r]).collect();
        let mut index = vec![usize::MAX; l.nc];
        rows.iter().enumerate().for_each(|(k, &r)| index[r] = k);
        let mut jacobian = Mat::<f64>::zeros(rows.len(), l.nv);
        jacobian_entries(model, data, |r, c, x| {
            if index[r] != usize::MAX {
                jacobian[(index[r], c)] += x;
            }
        });
        let phi: Vec<f64> = rows.iter().map(|&r| data.equations[r].phi).collect();
        run_force_stages(model, data, state.t, &zero);
        let force: Vec<f64> = (0..l.nv).map(|k| data.inertia[k] - data.applied[k]).collect();
        let (null_space, pseudo_inverse) = null_space_and_pseudo_inverse(&jacobian);
        // λ = −(B⁺)ᵀ f minimizes ‖f + Bᵀλ‖. The joints' loads at interface nodes stiffen their
        // bodies by `W λ` (linear in λ, of the order of the deflection): λ = −(B⁺)ᵀ (f + W λ) by a
        // fixed-point iteration, which `W`'s smallness makes converge at once (without interface
        // nodes `W = 0` and the first pass is the answer).
        let mut lambda = vec![0.0; l.nc];
        let mut loaded = force.clone();
        for _ in 0..INTERFACE_PASSES {
            for (k, x) in pseudo_inverse.transpose_apply(&loaded).into_iter().enumerate() {
                lambda[rows[k]] = -x;
            }
            let mut reactions = vec![0.0; l.nv];
            add_interface_reactions(model, data, &lambda, &mut reactions);
            if reactions.iter().all(|&x| x == 0.0) {
                break;
            }
            loaded.iter_mut().zip(force.iter().zip(&reactions)).for_each(|(y, (f, w))| *y = f + w);
        }
        let mut residual = force.clone();
        add_interface_reactions(model, data, &lambda, &mut residual);
        for (k, &r) in rows.iter().enumerate() {
            for c in 0..l.nv {
                residual[c] += jacobian[(k, c)] * lambda[r];
            }
        }
        Self { force, null_space, pseudo_inverse, phi, lambda, residual }
    }

    /// `B⁺ φ`: the least change of the positions (velocity space) that changes the constraints of the
    /// rows in force by `φ` (one entry per row in force).
    pub fn least_change(&self, phi: &[f64]) -> Vec<f64> {
        self.pseudo_inverse.apply(phi)
    }

    /// Largest `|f + Bᵀλ|`.
    pub fn force_residual(&self) -> f64 {
        self.residual.iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    /// Largest `|Φ|` of the rows in force.
    pub fn constraint_residual(&self) -> f64 {
        self.phi.iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    /// `‖f + Bᵀλ‖₂`, the merit function of the line search.
    pub fn merit(&self) -> f64 {
        self.residual.iter().map(|x| x * x).sum::<f64>().sqrt()
    }
}

/// `B⁺ = V_r Σ_r⁻¹ U_rᵀ` kept as its factors: applying it costs `(nv + rows) rank`, where forming it
/// cost `nv rows rank` per configuration.
struct PseudoInverse {
    /// `U_r`, rows × rank.
    left: Mat<f64>,
    /// `1/σ_k`.
    inverse_singular: Vec<f64>,
    /// `V_r`, `nv` × rank.
    right: Mat<f64>,
}

impl PseudoInverse {
    /// `B⁺ x` (`x` over the rows).
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let x = Mat::from_fn(x.len(), 1, |i, _| x[i]);
        let mut y = self.left.transpose() * &x;
        self.inverse_singular.iter().enumerate().for_each(|(k, s)| y[(k, 0)] *= s);
        let out = &self.right * &y;
        (0..out.nrows()).map(|i| out[(i, 0)]).collect()
    }

    /// `(B⁺)ᵀ x` (`x` over the velocity coordinates).
    fn transpose_apply(&self, x: &[f64]) -> Vec<f64> {
        let x = Mat::from_fn(x.len(), 1, |i, _| x[i]);
        let mut y = self.right.transpose() * &x;
        self.inverse_singular.iter().enumerate().for_each(|(k, s)| y[(k, 0)] *= s);
        let out = &self.left * &y;
        (0..out.nrows()).map(|i| out[(i, 0)]).collect()
    }
}

/// `N` (orthonormal null-space basis of `b`) and `B⁺`, from the full singular value decomposition.
fn null_space_and_pseudo_inverse(b: &Mat<f64>) -> (Mat<f64>, PseudoInverse) {
    let (m, n) = (b.nrows(), b.ncols());
    let none = |rows: usize| PseudoInverse { left: Mat::zeros(rows, 0), inverse_singular: Vec::new(), right: Mat::zeros(n, 0) };
    if m == 0 {
        return (Mat::identity(n, n), none(0));
    }
    let Ok(svd) = b.svd() else {
        // Never seen for a finite matrix; leave every motion free and no multipliers.
        return (Mat::identity(n, n), none(m));
    };
    let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
    let largest = (0..m.min(n)).map(|k| s[k]).fold(0.0, f64::max);
    let rank = (0..m.min(n)).filter(|&k| s[k] > RANK_TOLERANCE * largest).count();
    let null_space = Mat::from_fn(n, n - rank, |i, k| v[(i, rank + k)]);
    let pseudo_inverse = PseudoInverse {
        left: Mat::from_fn(m, rank, |i, k| u[(i, k)]),
        inverse_singular: (0..rank).map(|k| 1.0 / s[k]).collect(),
        right: Mat::from_fn(n, rank, |i, k| v[(i, k)]),
    };
    (null_space, pseudo_inverse)
}
