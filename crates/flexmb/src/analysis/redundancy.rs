//! Redundant constraints: rows of `B` that are linear combinations of earlier rows, found by modified
//! Gram–Schmidt with reorthogonalization, in joint order, so that the later equation is the one named.

use crate::data::Data;
use crate::model::Model;
use crate::stage::{constraint_equations, jacobian_entries, kinematics};

/// Relative size below which a row's component orthogonal to the earlier rows counts as zero.
const REDUNDANCY_TOLERANCE: f64 = 1e-8;

/// A constraint row that repeats what earlier rows already impose.
#[derive(Clone, Debug, PartialEq)]
pub struct RedundantConstraint {
    pub row: usize,
    /// Joint, kind and equation, e.g. `joint 'rod_slider' (revolute), equation 5: dot-1(y_i, z_j)`.
    pub description: String,
}

/// Rows of the velocity Jacobian at `(q, t)` that are dependent on earlier rows; also returns the rank.
pub fn find_redundant_rows(model: &Model, data: &mut Data, t: f64, q: &[f64]) -> (Vec<RedundantConstraint>, usize) {
    let nv = model.layout.nv;
    let nc = model.layout.nc;
    let zero_v = vec![0.0; nv];
    kinematics(model, data, q, &zero_v);
    constraint_equations(model, data, t);
    let mut rows = vec![vec![0.0; nv]; nc];
    jacobian_entries(model, data, |r, c, x| rows[r][c] += x);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut redundant = Vec::new();
    for (r, mut row) in rows.into_iter().enumerate() {
        let norm0 = norm(&row);
        if norm0 > 0.0 {
            for _ in 0..2 {
                for e in &basis {
                    let proj = dot(&row, e);
                    row.iter_mut().zip(e).for_each(|(x, y)| *x -= proj * y);
                }
            }
        }
        let n = norm(&row);
        if norm0 == 0.0 || n <= REDUNDANCY_TOLERANCE * norm0 {
            redundant.push(RedundantConstraint { row: r, description: model.describe_constraint_row(r) });
        } else {
            row.iter_mut().for_each(|x| *x /= n);
            basis.push(row);
        }
    }
    (redundant, basis.len())
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// For a failure message: the rows in force (`active`) that have become dependent at `q`, i.e. the
/// mechanism locks or reaches a singular position there; `None` when there are none.
pub(crate) fn newly_dependent_rows(model: &Model, data: &mut Data, t: f64, q: &[f64], active: &[bool]) -> Option<String> {
    let (dependent, _) = find_redundant_rows(model, data, t, q);
    let newly: Vec<String> = dependent.iter().filter(|r| active[r.row]).map(|r| r.description.clone()).collect();
    (!newly.is_empty()).then(|| {
        format!(
            "the constraints have become dependent here (the mechanism locks or reaches a singular position): {}",
            newly.join("; ")
        )
    })
}
