//! Velocity analysis: consistent velocities `B v = ν` closest to the velocities given in the model.
//! Minimizes `½ (v − v₀)ᵀ W (v − v₀)` with weight 10⁶ on the components the user gave and 1 on the rest,
//! so given velocities are kept where the constraints allow and the others follow.

use super::{dependency_of, newly_dependent_rows, violated_rows, AssemblyError, State};
use crate::data::Data;
use crate::linalg::{solve_normal_equations, SparseRows};
use crate::model::Model;
use crate::stage::{jacobian_entries, run_kinematic_stages};

const GIVEN_WEIGHT: f64 = 1e6;

/// What the velocity analysis changed.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct VelocityReport {
    /// Given velocities the constraints did not allow, with what they became.
    pub adjusted: Vec<String>,
    /// Largest `|B v − ν|` after the analysis.
    pub residual: f64,
}

/// Relative size (of the largest velocity) above which a switched-off row's velocity residual means the
/// declared velocity equations cannot all hold.
const VELOCITY_CONSISTENCY: f64 = 1e-8;

/// Makes `state.v` consistent with the velocity constraints at `state.q` (already assembled). The rows
/// switched off as redundant must hold too: when one does not (a driver prescribes a rate the mechanism
/// cannot follow at a singular position), the analysis fails naming it.
pub fn velocity_analysis(model: &Model, data: &mut Data, state: &mut State) -> Result<VelocityReport, AssemblyError> {
    super::assembly::check_state(model, data, state)?;
    let l = &model.layout;
    let mut weight = vec![1.0; l.nv];
    for (b, body) in model.bodies.iter().enumerate() {
        let vo = l.v_offset[b];
        if body.initial.velocity.is_some() {
            weight[vo..vo + 3].fill(GIVEN_WEIGHT);
        }
        if body.initial.angular_velocity.is_some() {
            weight[vo + 3..vo + 6].fill(GIVEN_WEIGHT);
        }
        // Modal rates are always given (zero by default).
        let m = l.modes[b];
        weight[vo + 6..vo + 6 + m].fill(GIVEN_WEIGHT);
    }
    let v0 = state.v.clone();
    let residual = project_velocities(model, data, state, &weight)?;
    let mut report = VelocityReport { residual, ..Default::default() };
    for (bi, body) in model.bodies.iter().enumerate() {
        let vo = l.v_offset[bi];
        let changed = |range: std::ops::Range<usize>| {
            range.clone().any(|k| (state.v[k] - v0[k]).abs() > 1e-6 * v0[k].abs().max(1.0))
        };
        if body.initial.velocity.is_some() && changed(vo..vo + 3) {
            report.adjusted.push(format!(
                "body '{}': the given velocity {:?} became {:?} to satisfy the joints",
                body.name,
                &v0[vo..vo + 3],
                &state.v[vo..vo + 3]
            ));
        }
        if body.initial.angular_velocity.is_some() && changed(vo + 3..vo + 6) {
            report.adjusted.push(format!(
                "body '{}': the given angular velocity (body axes) {:?} became {:?} to satisfy the joints",
                body.name,
                &v0[vo + 3..vo + 6],
                &state.v[vo + 3..vo + 6]
            ));
        }
    }
    Ok(report)
}

/// Makes `state.v` consistent with the velocity constraints at `state.q` (already assembled), the
/// correction of least `½ Δvᵀ W Δv` for the diagonal weights `weight`; returns the largest `|B v − ν|`
/// after it. Fails when the constraint Jacobian is singular, or a row switched off as redundant cannot
/// hold.
pub(crate) fn project_velocities(model: &Model, data: &mut Data, state: &mut State, weight: &[f64]) -> Result<f64, AssemblyError> {
    let l = &model.layout;
    let v0 = state.v.clone();
    let rows: Vec<usize> = (0..l.nc).filter(|r| state.active[*r]).collect();
    let mut row_of = vec![usize::MAX; l.nc];
    rows.iter().enumerate().for_each(|(k, r)| row_of[*r] = k);
    run_kinematic_stages(model, data, state.t, &state.q, &state.v);
    super::assembly::check_finite(model, data, state.t)?;
    let mut entries = Vec::new();
    jacobian_entries(model, data, |r, c, x| {
        if row_of[r] != usize::MAX {
            entries.push((row_of[r], c, x));
        }
    });
    let b = SparseRows::from_entries(rows.len(), l.nv, entries);
    // r = ν − B v₀ = −(B v₀ + Φ_t); Δv = W⁻¹ Bᵀ z with (B W⁻¹ Bᵀ) z = r.
    let mut z: Vec<f64> = rows
        .iter()
        .map(|&r| {
            let (j, _) = l.equations[r];
            let joint = &model.joints[j.0];
            -data.equations[r].rate(&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0])
        })
        .collect();
    let mut dv = vec![0.0; l.nv];
    if solve_normal_equations(&b, Some(weight), &mut z).is_ok() {
        b.multiply_transposed(&z, &mut dv);
        dv.iter_mut().zip(weight).for_each(|(x, w)| *x /= w);
    } else {
        dv.fill(f64::NAN);
    }
    for k in 0..l.nv {
        state.v[k] += dv[k];
    }
    if !state.v.iter().all(|x| x.is_finite()) {
        state.v = v0;
        let dependent = newly_dependent_rows(model, data, state.t, &state.q, &state.active).map(|n| format!("; {n}")).unwrap_or_default();
        return Err(AssemblyError::Singular { what: "velocity analysis", dependent });
    }
    run_kinematic_stages(model, data, state.t, &state.q, &state.v);
    let residual = rows
        .iter()
        .map(|r| {
            let (j, _) = l.equations[*r];
            let joint = &model.joints[j.0];
            data.equations[*r].rate(&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0]).abs()
        })
        .fold(0.0, f64::max);
    let scale = state.v.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let violated = violated_rows(model, data, &state.active, true, VELOCITY_CONSISTENCY * scale);
    if !violated.is_empty() {
        let dependency = dependency_of(model, data, &state.active, &violated[0]);
        return Err(AssemblyError::SingularPosition { t: state.t, level: "velocity", violated, dependency });
    }
    Ok(residual)
}
