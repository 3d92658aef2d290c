//! The directions of a mode set that move no mass. A mode whose nodes only turn, at nodes without
//! rotary inertia (a beam twisted about its own axis, the static mode of a torque about it), has no
//! modal mass; so has a combination of modes that are massive alone (two static modes of tip
//! torques that bend the beam equally and twist it oppositely: their difference is a pure twist).
//! Such a direction has no acceleration in a mechanism (its equation is static, `K a = f`) and would
//! make the body's mass matrix singular; every mode set removes it here, before its modes are
//! orthonormalized.
//!
//! The null space of the modal mass `ΦᵀMΦ` is found by the eigen-decomposition of the modal mass
//! scaled scale-free: each mode by its largest nodal motion `|u|² + (L |θ|)²` (`L` the size of the
//! mesh), the mass by the body's; a direction whose mean squared translation of mass is below 10⁻¹²
//! of its motion is massless. For each massless direction `z` one mode is dropped, the one with the
//! largest share of `z` (column pivoting: the kept modes and the massless directions together span
//! the set); the kept modes keep their names, and each is made stiffness-orthogonal to the massless
//! directions, `φ ← φ − Z (ZᵀKZ)⁻¹ ZᵀKφ`: the massless directions are condensed statically on the kept
//! modes (with no load on them, their static equation sets them to `−(ZᵀKZ)⁻¹ZᵀK a`). The kept space is
//! then the one the finite modes of the pencil `(ΦᵀKΦ, ΦᵀMΦ)` span (for a massless `z` and a mode
//! `K x = λ M x`, `zᵀK x = λ zᵀM x = 0`), whatever the modes' scaling; a plain orthogonal complement would
//! depend on it. A single massless mode that the others do not couple by stiffness (the twist of a
//! tip torque against bending modes) is simply dropped. The kept modal mass is positive definite.

use faer::prelude::Solve;
use faer::{Mat, Side};

use crate::assembly::AssembledModel;
use crate::mesh::FeModel;
use crate::symmetric_product::{symmetric_projection, symmetrized};

/// Below this share of the body's mass per unit of nodal motion, a direction moves no mass.
const MASSLESS: f64 = 1e-12;
/// Below this nodal motion, a unit combination of modes each of unit largest nodal motion moves
/// nothing: the modes are dependent.
const DEPENDENT: f64 = 1e-6;

/// Removes the directions of `basis` (over the free dofs of `assembled`) that move no mass, as the
/// module says, each named in a warning by the modes' `names` (one per column). Returns the kept
/// basis' modal mass and the columns kept (each now with its massless part condensed).
pub(super) fn drop_massless_directions(
    model: &FeModel,
    assembled: &AssembledModel,
    basis: &mut Mat<f64>,
    names: &[String],
    warnings: &mut Vec<String>,
) -> (Mat<f64>, Vec<usize>) {
    let modal_mass = symmetrized(&symmetric_projection(&assembled.mass, basis.as_ref()));
    let m = basis.ncols();
    let all = (0..m).collect();
    if m == 0 {
        return (modal_mass, all);
    }
    let scale: Vec<f64> = motion_scales(model, assembled, basis).into_iter().map(|s| if s > 0.0 { s } else { 1.0 }).collect();
    let total_mass: f64 = assembled.mass_points.iter().map(|p| p.mass).sum::<f64>().max(f64::MIN_POSITIVE);
    let scaled = Mat::from_fn(m, m, |i, j| modal_mass[(i, j)] / (scale[i] * scale[j] * total_mass));
    let Ok(eigen) = scaled.self_adjoint_eigen(Side::Lower) else { return (modal_mass, all) };
    // NaN moves no mass. A direction that moves nothing at all is a dependence of the modes, not a
    // massless motion: it is left to the basis' independence test.
    let null: Vec<usize> = (0..m)
        .filter(|&k| eigen.S()[k].partial_cmp(&MASSLESS) != Some(std::cmp::Ordering::Greater))
        .filter(|&k| {
            let direction = Mat::from_fn(m, 1, |i, _| eigen.U()[(i, k)] / scale[i]);
            motion_scales(model, assembled, &(&*basis * &direction))[0] > DEPENDENT
        })
        .collect();
    if null.is_empty() {
        return (modal_mass, all);
    }
    // The massless directions in the modes' coefficients, and the mode each one replaces.
    let directions = Mat::from_fn(m, null.len(), |i, c| eigen.U()[(i, null[c])] / scale[i]);
    let pivots = pivot_columns(&Mat::from_fn(m, null.len(), |i, c| eigen.U()[(i, null[c])]));
    for (c, &p) in pivots.iter().enumerate() {
        warnings.push(massless_warning(names, &Mat::from_fn(m, 1, |i, _| eigen.U()[(i, null[c])]), p));
    }
    let kept: Vec<usize> = (0..m).filter(|j| !pivots.contains(j)).collect();
    let mut coefficients = Mat::from_fn(m, kept.len(), |i, k| if i == kept[k] { 1.0 } else { 0.0 });
    // Stiffness-orthogonal to the massless directions: X − Z (ZᵀKZ)⁻¹ ZᵀK X.
    let stiffness = symmetrized(&symmetric_projection(&assembled.stiffness, basis.as_ref()));
    let zk = directions.transpose() * &stiffness;
    let zkz = symmetrized(&(&zk * &directions));
    if let Ok(factor) = zkz.llt(Side::Lower) {
        let correction = factor.solve(&zk * &coefficients);
        coefficients -= &directions * &correction;
    }
    *basis = &*basis * &coefficients;
    (symmetrized(&(coefficients.transpose() * &modal_mass * &coefficients)), kept)
}

/// Each mode's largest nodal motion `√(|u|² + (L |θ|)²)` (0 for one that moves nothing or is not finite).
fn motion_scales(model: &FeModel, assembled: &AssembledModel, basis: &Mat<f64>) -> Vec<f64> {
    let size = model.mesh.size();
    (0..basis.ncols())
        .map(|j| {
            let nodal = assembled.dofs.expand(&(0..basis.nrows()).map(|i| basis[(i, j)]).collect::<Vec<_>>());
            let motion = nodal
                .chunks(6)
                .map(|d| d[..3].iter().map(|x| x * x).sum::<f64>() + size * size * d[3..].iter().map(|x| x * x).sum::<f64>())
                .fold(0.0_f64, f64::max)
                .sqrt();
            if motion.is_finite() {
                motion
            } else {
                0.0
            }
        })
        .collect()
}

/// One row per column of `directions` (`m × k`, independent): the pivots of Gaussian elimination with
/// complete pivoting on its columns, a mode for each direction such that the other modes and the
/// directions span the set.
fn pivot_columns(directions: &Mat<f64>) -> Vec<usize> {
    let mut work = directions.clone();
    let (m, k) = (work.nrows(), work.ncols());
    let mut pivots = Vec::with_capacity(k);
    let mut done = vec![false; k];
    for _ in 0..k {
        let mut best = (0.0_f64, 0, 0);
        for c in (0..k).filter(|&c| !done[c]) {
            for i in (0..m).filter(|i| !pivots.contains(i)) {
                if work[(i, c)].abs() > best.0 {
                    best = (work[(i, c)].abs(), i, c);
                }
            }
        }
        let (_, row, column) = best;
        pivots.push(row);
        done[column] = true;
        for c in (0..k).filter(|&c| !done[c]) {
            let factor = work[(row, c)] / work[(row, column)];
            for i in 0..m {
                work[(i, c)] -= factor * work[(i, column)];
            }
        }
    }
    pivots
}

/// The warning for the massless direction `direction` (`m × 1`, unit) that replaces mode `pivot`.
fn massless_warning(names: &[String], direction: &Mat<f64>, pivot: usize) -> String {
    let name = |j: usize| names.get(j).cloned().unwrap_or_else(|| format!("{}", j + 1));
    let largest = (0..direction.nrows()).map(|i| direction[(i, 0)].abs()).fold(0.0, f64::max);
    let involved: Vec<usize> = (0..direction.nrows()).filter(|&i| direction[(i, 0)].abs() > 1e-3 * largest).collect();
    if involved.len() == 1 {
        return format!(
            "mode {} moves no mass (it only turns nodes without rotary inertia): dropped from the basis, the body is \
             rigid against it; set rotary_inertia = true to keep it",
            name(pivot)
        );
    }
    // The coefficients are in units of each mode's largest nodal motion.
    let combination: Vec<String> = involved.iter().map(|&i| format!("{:+.3} {}", direction[(i, 0)], name(i))).collect();
    format!(
        "the combination {} of modes (each in units of its largest nodal motion) moves no mass (it only turns nodes without rotary inertia): mode {} dropped from \
         the basis and the others made stiffness-orthogonal to it (condensed statically), the body is rigid against \
         it; set rotary_inertia = true to keep it",
        combination.join(" "),
        name(pivot)
    )
}
