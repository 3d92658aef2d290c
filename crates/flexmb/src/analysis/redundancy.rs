//! Redundant constraints: rows of `B` that are linear combinations of rows kept before them, found by a
//! rank-revealing sparse QR that takes the rows one at a time (Givens rotations, George and Heath; see
//! `linalg/givens_qr.rs`): a row whose part left after the rotations is at most
//! [`REDUNDANCY_TOLERANCE`] of its length depends on the rows before it. Its work and memory grow with
//! the entries of `B` and the fill of `R`, i.e. with the bodies for chains and trees.
//!
//! Which of a dependent set is removed matters: the removed row is no longer enforced, so it must be one
//! that holds anyway. Rows are therefore taken in the order in which they are kept
//! ([`keep_order`]): first the rows that do not hold at the configuration (they must stay in force for
//! the assembly to close them), then the drivers (a prescribed motion is removed last), then the other
//! joints' rows in joint order, so that of two dependent joint rows the later one is named. After the
//! assembly and the velocity analysis every removed row is checked ([`violated_rows`]): when one does not
//! hold, the declared equations cannot all hold there and the mechanism is at a singular position.

use crate::data::Data;
use crate::linalg::{dependent_rows, solve_normal_equations, SparseRows};
use crate::model::Model;
use crate::stage::{jacobian_entries, run_kinematic_stages};

/// Relative size below which a row's component orthogonal to the earlier rows counts as zero.
pub(crate) const REDUNDANCY_TOLERANCE: f64 = 1e-8;

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
    let nc = model.layout.nc;
    let b = jacobian_in_keep_order(model, data, t, q, satisfied_tolerance);
    let dependent = dependent_rows(&b.rows, REDUNDANCY_TOLERANCE);
    let mut redundant: Vec<RedundantConstraint> = (0..nc)
        .filter(|&k| dependent[k])
        .map(|k| RedundantConstraint { row: b.order[k], description: model.describe_constraint_row(b.order[k]) })
        .collect();
    redundant.sort_by_key(|r| r.row);
    let rank = nc - redundant.len();
    (redundant, rank)
}

/// The rows of `B` at `(q, t)` that depend on rows kept before them, as the assembly finds them (in row
/// order); for the tests that hold it against [`gram_schmidt_redundant_rows`](super::gram_schmidt_redundant_rows).
#[doc(hidden)]
pub fn redundant_rows(model: &Model, data: &mut Data, t: f64, q: &[f64], satisfied_tolerance: f64) -> Vec<usize> {
    find_redundant_rows(model, data, t, q, satisfied_tolerance).0.iter().map(|r| r.row).collect()
}

/// The velocity Jacobian `B` with its rows in keep order, and that order.
pub(crate) struct KeepOrderJacobian {
    /// `B`'s rows, the `k`-th being row `order[k]` of `B`.
    pub(crate) rows: SparseRows,
    /// The rows of `B` in the order they are kept.
    pub(crate) order: Vec<usize>,
}

/// `B` at `(q, t)` (after the kinematic stages there, with zero velocities) with its rows in
/// [`keep_order`].
pub(crate) fn jacobian_in_keep_order(
    model: &Model,
    data: &mut Data,
    t: f64,
    q: &[f64],
    satisfied_tolerance: f64,
) -> KeepOrderJacobian {
    let (nv, nc) = (model.layout.nv, model.layout.nc);
    let zero_v = vec![0.0; nv];
    run_kinematic_stages(model, data, t, q, &zero_v);
    let order = keep_order(model, data, satisfied_tolerance);
    let mut position = vec![0; nc];
    order.iter().enumerate().for_each(|(k, &r)| position[r] = k);
    let mut entries = Vec::new();
    jacobian_entries(model, data, |r, c, x| entries.push((position[r], c, x)));
    KeepOrderJacobian { rows: SparseRows::from_entries(nc, nv, entries), order }
}

/// The order in which rows are kept when some are dependent (after `constraint_equations`): rows that
/// do not hold (`|Φ| > satisfied_tolerance`), then drivers, then the other rows, each group in row order.
pub(crate) fn keep_order(model: &Model, data: &Data, satisfied_tolerance: f64) -> Vec<usize> {
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
    let mut entries = Vec::new();
    let mut target = vec![0.0; l.nv];
    jacobian_entries(model, data, |r, c, x| {
        if row_of[r] != usize::MAX {
            entries.push((row_of[r], c, x));
        } else if r == violated.row {
            target[c] += x;
        }
    });
    let b = SparseRows::from_entries(rows.len(), l.nv, entries);
    // B Bᵀ c = B b_r: the coefficients of b_r on the rows in force.
    let mut c = vec![0.0; rows.len()];
    b.multiply(&target, &mut c);
    if solve_normal_equations(&b, None, &mut c).is_err() {
        return Vec::new();
    }
    let largest = c.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let involved: Vec<usize> = (0..rows.len()).filter(|&k| c[k].abs() > 1e-6 * largest).map(|k| rows[k]).collect();
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
