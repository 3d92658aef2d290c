//! Redundant constraints: rows of `B` that are linear combinations of rows kept before them, found by
//! modified Gram–Schmidt with reorthogonalization.
//!
//! Which of a dependent set is removed matters: the removed row is no longer enforced, so it must be one
//! that holds anyway. Rows are therefore taken in the order in which they are kept
//! ([`keep_order`]): first the rows that do not hold at the configuration (they must stay in force for
//! the assembly to close them), then the drivers (a prescribed motion is removed last), then the other
//! joints' rows in joint order, so that of two dependent joint rows the later one is named. After the
//! assembly and the velocity analysis every removed row is checked ([`violated_rows`]): when one does not
//! hold, the declared equations cannot all hold there and the mechanism is at a singular position.

use faer::linalg::matmul::matmul;
use faer::prelude::*;
use faer::{Accum, Par};

use crate::data::Data;
use crate::model::Model;
use crate::stage::{jacobian_entries, run_kinematic_stages};

/// Relative size below which a row's component orthogonal to the earlier rows counts as zero.
const REDUNDANCY_TOLERANCE: f64 = 1e-8;

/// A constraint row that repeats what earlier rows already impose.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RedundantConstraint {
    /// The row of `Φ`.
    pub row: usize,
    /// Joint, kind and equation, e.g. `joint 'rod_slider' (revolute), equation 5: dot-1(y_i, z_j)`.
    pub description: String,
}

/// Rows of the velocity Jacobian at `(q, t)` that depend on rows kept before them in `keep_order`
/// (rows with `|Φ| > satisfied_tolerance` first, then drivers, then joints); also returns the rank.
/// The result lists the rows in row order.
pub(crate) fn find_redundant_rows(
    model: &Model,
    data: &mut Data,
    t: f64,
    q: &[f64],
    satisfied_tolerance: f64,
) -> (Vec<RedundantConstraint>, usize) {
    let nv = model.layout.nv;
    let nc = model.layout.nc;
    let zero_v = vec![0.0; nv];
    run_kinematic_stages(model, data, t, q, &zero_v);
    let order = keep_order(model, data, satisfied_tolerance);
    let mut position = vec![0; nc];
    order.iter().enumerate().for_each(|(k, &r)| position[r] = k);
    // Bᵀ with its columns in keep order.
    let mut rows = Mat::<f64>::zeros(nv, nc);
    jacobian_entries(model, data, |r, c, x| rows[(c, position[r])] += x);
    let dependent = dependent_columns(&mut rows);
    let mut redundant: Vec<RedundantConstraint> = (0..nc)
        .filter(|&k| dependent[k])
        .map(|k| RedundantConstraint { row: order[k], description: model.describe_constraint_row(order[k]) })
        .collect();
    redundant.sort_by_key(|r| r.row);
    let rank = nc - redundant.len();
    (redundant, rank)
}

/// Columns of `a` that depend on the columns before them: Gram–Schmidt with reorthogonalization,
/// blocked so that the projections on the basis found so far are matrix products (classical
/// Gram–Schmidt, twice, against the earlier blocks; modified Gram–Schmidt, twice, within a block). A
/// column whose remainder is at most [`REDUNDANCY_TOLERANCE`] of its length is dependent. `a` is
/// overwritten.
fn dependent_columns(a: &mut Mat<f64>) -> Vec<bool> {
    const BLOCK: usize = 128;
    let (n, m) = (a.nrows(), a.ncols());
    let lengths: Vec<f64> = (0..m).map(|j| a.col(j).norm_l2()).collect();
    let mut basis = Mat::<f64>::zeros(n, m.min(n));
    let mut rank = 0;
    let mut dependent = vec![false; m];
    for start in (0..m).step_by(BLOCK) {
        let width = BLOCK.min(m - start);
        for _ in 0..2 {
            if rank > 0 {
                let q = basis.as_ref().subcols(0, rank);
                let c = q.transpose() * a.as_ref().subcols(start, width);
                matmul(a.as_mut().subcols_mut(start, width), Accum::Add, q, &c, -1.0, Par::Seq);
            }
        }
        let block_rank = rank;
        for j in start..start + width {
            for _ in 0..2 {
                for e in block_rank..rank {
                    let projection = basis.col(e).transpose() * a.col(j);
                    let (q, x) = (basis.col(e), a.col_mut(j));
                    x.iter_mut().zip(q.iter()).for_each(|(x, q)| *x -= projection * q);
                }
            }
            let remainder = a.col(j).norm_l2();
            if lengths[j] == 0.0 || remainder <= REDUNDANCY_TOLERANCE * lengths[j] || rank == n {
                dependent[j] = true;
            } else {
                let (x, q) = (a.col(j), basis.col_mut(rank));
                q.iter_mut().zip(x.iter()).for_each(|(q, x)| *q = x / remainder);
                rank += 1;
            }
        }
    }
    dependent
}

/// The order in which rows are kept when some are dependent (after `constraint_equations`): rows that
/// do not hold (`|Φ| > satisfied_tolerance`), then drivers, then the other rows, each group in row order.
fn keep_order(model: &Model, data: &Data, satisfied_tolerance: f64) -> Vec<usize> {
    let rank = |r: usize| {
        let (joint, _) = model.layout.equations[r];
        if data.equations[r].phi.abs() > satisfied_tolerance {
            0
        } else if model.joints[joint.0].kind.is_driver() {
            1
        } else {
            2
        }
    };
    let mut order: Vec<usize> = (0..model.layout.nc).collect();
    order.sort_by_key(|&r| rank(r));
    order
}

/// A declared equation that does not hold, with its residual.
#[derive(Clone, Debug, PartialEq)]
pub struct ViolatedEquation {
    /// The row of `Φ`.
    pub row: usize,
    /// Joint, kind and equation, as in [`RedundantConstraint::description`].
    pub description: String,
    /// `|Φ|` (position level) or `|Φ̇|` (velocity level).
    pub residual: f64,
}

/// The rows switched off (`!active`) whose residual exceeds `tolerance`, largest first: `|Φ|` when
/// `velocity` is false, else `|B v + Φ_t|` (after `kinematics` and `constraint_equations` at the state).
pub(crate) fn violated_rows(model: &Model, data: &Data, active: &[bool], velocity: bool, tolerance: f64) -> Vec<ViolatedEquation> {
    let mut violated: Vec<ViolatedEquation> = (0..model.layout.nc)
        .filter(|&r| !active[r])
        .filter_map(|r| {
            let terms = &data.equations[r];
            let residual = if velocity {
                let joint = &model.joints[model.layout.equations[r].0 .0];
                terms.rate(&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]).abs()
            } else {
                terms.phi.abs()
            };
            (residual > tolerance || residual.is_nan())
                .then(|| ViolatedEquation { row: r, description: model.describe_constraint_row(r), residual })
        })
        .collect();
    violated.sort_by(|a, b| b.residual.total_cmp(&a.residual));
    violated
}

/// The equations in force that `violated` depends on (its row of `B` as a combination of theirs, by
/// least squares), grouped by joint, e.g. `joint 'slide' (translational), equations 1, 3`; after
/// `constraint_equations` at the state.
pub(crate) fn dependency_of(model: &Model, data: &Data, active: &[bool], violated: &ViolatedEquation) -> Vec<String> {
    let l = &model.layout;
    let rows: Vec<usize> = (0..l.nc).filter(|&r| active[r]).collect();
    let mut row_of = vec![usize::MAX; l.nc];
    rows.iter().enumerate().for_each(|(k, &r)| row_of[r] = k);
    let mut b = Mat::<f64>::zeros(rows.len(), l.nv);
    let mut target = Mat::<f64>::zeros(l.nv, 1);
    jacobian_entries(model, data, |r, c, x| {
        if row_of[r] != usize::MAX {
            b[(row_of[r], c)] += x;
        } else if r == violated.row {
            target[(c, 0)] += x;
        }
    });
    // B Bᵀ c = B b_r: the coefficients of b_r on the rows in force.
    let mut c = &b * &target;
    (&b * b.transpose()).partial_piv_lu().solve_in_place(c.as_mut());
    let largest = (0..rows.len()).map(|k| c[(k, 0)].abs()).fold(0.0, f64::max);
    let involved: Vec<usize> = (0..rows.len()).filter(|&k| c[(k, 0)].abs() > 1e-6 * largest).map(|k| rows[k]).collect();
    group_by_joint(model, &involved)
}

/// `joint 'slide' (translational), equations 1, 3` for each joint of `rows` (in row order).
fn group_by_joint(model: &Model, rows: &[usize]) -> Vec<String> {
    let l = &model.layout;
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for &r in rows {
        let joint = l.equations[r].0 .0;
        let k = r - l.joint_rows[joint].start + 1;
        match groups.last_mut() {
            Some((j, ks)) if *j == joint => ks.push(k),
            _ => groups.push((joint, vec![k])),
        }
    }
    groups
        .into_iter()
        .map(|(j, ks)| {
            let joint = &model.joints[j];
            let ks: Vec<String> = ks.iter().map(|k| k.to_string()).collect();
            let noun = if joint.kind.is_driver() { "driver" } else { "joint" };
            let eq = if ks.len() == 1 { "equation" } else { "equations" };
            format!("{noun} '{}' ({}), {eq} {}", joint.name, joint.kind.keyword(), ks.join(", "))
        })
        .collect()
}

/// For a failure message: the rows in force (`active`) that have become dependent at `q`, i.e. the
/// mechanism locks or reaches a singular position there; `None` when there are none.
pub(crate) fn newly_dependent_rows(model: &Model, data: &mut Data, t: f64, q: &[f64], active: &[bool]) -> Option<String> {
    let (dependent, _) = find_redundant_rows(model, data, t, q, f64::INFINITY);
    let newly: Vec<String> = dependent.iter().filter(|r| active[r.row]).map(|r| r.description.clone()).collect();
    (!newly.is_empty()).then(|| {
        format!(
            "the constraints have become dependent here (the mechanism locks or reaches a singular position): {}",
            newly.join("; ")
        )
    })
}
