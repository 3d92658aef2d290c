//! The interface sets: Craig–Bampton (`20N12C`) and free-interface, Herting-like (`20F12A`). Their
//! interface is the set of degrees of freedom the supports hold — where the joints act, typically the
//! six dofs of each interface node (a rigid or distributing coupling's reference node). The body is
//! reduced on the unsupported model, so that its interface nodes move with the modes:
//!
//! - **Craig–Bampton**: `N` the fixed-interface normal modes (the vibration modes of the supported
//!   model, as in the seed) and `C` the constraint modes, the static shape of a unit displacement of
//!   each held dof with the others held (`ψ_b = [−K_ii⁻¹ K_ib; e_b]`). Where the supports leave rigid
//!   motions (a hinge's free turn), each constraint mode is the one M-orthogonal to them (its load is
//!   balanced: the rigid motions vanish at the interface). Static correction modes (`S`) may be added.
//! - **Free interface**: `F` the free-free vibration modes and `A` the residual attachment modes, the
//!   static shapes of a unit load at each held dof, balanced by the rigid-body inertia forces
//!   (inertia relief), M-orthogonal to the rigid motions, less the part the kept free-free modes
//!   already carry (`x − Σ φ_k φ_kᵀ f / ω_k²`).
//!
//! The span of such a basis holds rigid motions of the free body (the constraint modes of a clamped
//! interface node are its six rigid motions), which the floating frame carries. The basis is
//! therefore made M-orthogonal to the six rigid motions of the unsupported model, the directions that
//! vanish (those rigid motions) are dropped, and the rest is orthonormalized by the reduced
//! eigenproblem: modes with a diagonal modal stiffness (no coupling of the static and the dynamic
//! modes through the stiffness), M-orthonormal and free of rigid motion, i.e. the body frame is the
//! mean axes (Tisserand's frame, linearized). Their frequencies are the free-free frequencies of the
//! reduced body.

use faer::{Mat, Side};

use crate::assembly::supported_dofs;
use crate::error::FemError;
use crate::mesh::{Dof, FeModel};
use crate::modes::rigid::pivot_dofs;
use crate::modes::shift_invert::ShiftInvert;
use crate::modes::{vibration_modes_and_operator, vibration_modes_of, EigenSettings, EigenSolver, PreparedModel, VibrationModes};
use crate::static_correction::{m_orthogonal_to, solve_with_extra_supports, static_correction_modes, static_responses, StaticModes};

use super::ModeSet;
use crate::symmetric_product::{symmetric_projection, symmetric_times, symmetrized};

/// Below this, a direction of the projected basis' scaled Gram matrix is a rigid motion (dropped).
const RIGID_DIRECTION: f64 = 1e-10;

/// The raw basis of an interface set, over the dofs of the unsupported model.
pub(super) struct InterfaceBasis {
    /// The model without its supports, assembled, with its rigid motions.
    pub free: PreparedModel,
    /// The raw modes (`n_free × set.len()`).
    pub basis: Mat<f64>,
    /// The FE vibration modes of the set: the free-free ones of a free-interface set, the
    /// fixed-interface ones otherwise.
    pub fe_modes: VibrationModes,
    /// The static correction modes (of the supported model), if the set has any.
    pub static_modes: Option<StaticModes>,
    /// How many rigid motions of the free body the raw basis spans.
    pub rigid_in_span: usize,
}

/// The interface dofs: `(node, dof)` of every held dof, node by node.
pub fn interface_dofs(model: &FeModel) -> Vec<(usize, Dof)> {
    supported_dofs(model).iter().enumerate().flat_map(|(node, set)| set.iter().map(move |dof| (node, dof))).collect()
}

/// The raw basis of the interface set `set` of `model`, whose supported model is `supported` and
/// unsupported one `free`.
pub(super) fn interface_basis(
    model: &FeModel,
    supported: &PreparedModel,
    free: PreparedModel,
    set: &ModeSet,
    eigen: &EigenSettings,
) -> Result<InterfaceBasis, FemError> {
    let mode_set_error = |message: String| FemError::ModeSet { text: set.to_string(), message };
    let dofs = &free.assembled.dofs;
    let interface: Vec<usize> = interface_dofs(model)
        .into_iter()
        .filter_map(|(node, dof)| dofs.equation(node, dof))
        .collect();
    for (letter, count) in [('C', set.constraint()), ('A', set.attachment())] {
        if count > 0 && count != interface.len() {
            return Err(mode_set_error(format!(
                "asks for {count} {letter} modes but the supports hold {} degrees of freedom (the interface): write {}{letter}",
                interface.len(),
                interface.len()
            )));
        }
    }
    if set.free_vibration() > 0 && interface.is_empty() {
        return Err(mode_set_error("a free-interface set needs an interface: the supports' held dofs".into()));
    }
    // The supported model's equations among the free model's. The free model holds a dof of each of
    // its rigid motions that move no mass (a straight beam's spin about its axis without rotary
    // inertia; `prepare`): the supported model's modes lose their component there, a massless turn.
    let n = dofs.n_free();
    let supported_dofs = &supported.assembled.dofs;
    let mut to_free = vec![None; supported_dofs.n_free()];
    let mut to_supported = vec![None; n];
    for global in 0..6 * model.mesh.nodes.len() {
        if let Some(e) = supported_dofs.equation_of(global) {
            if free.held_massless.contains(&(global / 6, Dof::ALL[global % 6])) {
                continue;
            }
            let f = dofs.equation_of(global).ok_or_else(|| {
                mode_set_error("a support on a node of a distributing coupling changes which dofs the coupling eliminates: support its reference node instead".into())
            })?;
            to_free[e] = Some(f);
            to_supported[f] = Some(e);
        }
    }
    let lift = |m: &Mat<f64>| {
        let mut lifted = Mat::zeros(n, m.ncols());
        for (e, f) in to_free.iter().enumerate() {
            let Some(f) = *f else { continue };
            for j in 0..m.ncols() {
                lifted[(f, j)] = m[(e, j)];
            }
        }
        lifted
    };
    let mut columns: Vec<Mat<f64>> = Vec::new();
    let mut fe_modes = None;
    let mut fixed_interface_operator = None;
    let mut static_modes = None;
    let mut rigid_in_span = 0;
    for group in &set.groups {
        match group.letter() {
            'N' => {
                let (modes, operator) = vibration_modes_and_operator(&supported.assembled, &supported.rigid, group.count(), eigen)?;
                columns.push(lift(&modes.shapes));
                fe_modes = Some(modes);
                fixed_interface_operator = Some(operator);
            }
            'S' => {
                let statics = static_correction_modes(&supported.model, &supported.assembled, &supported.rigid)?;
                columns.push(lift(&statics.shapes.subcols(0, group.count()).to_owned()));
                static_modes = Some(statics);
            }
            'C' => {
                let operator = fixed_interface_operator.as_ref();
                columns.push(constraint_modes(&free, supported, operator, &interface, &to_supported, &lift)?);
                rigid_in_span = free.rigid.ncols().saturating_sub(supported.rigid.ncols());
            }
            'F' => {
                let modes = vibration_modes_of(&free.assembled, &free.rigid, group.count(), eigen)?;
                columns.push(modes.shapes.clone());
                fe_modes = Some(modes);
            }
            _ => {
                let free_modes = fe_modes.as_ref();
                columns.push(residual_attachment_modes(&free, &interface, free_modes)?);
            }
        }
    }
    let width: usize = columns.iter().map(|c| c.ncols()).sum();
    let mut basis = Mat::zeros(n, width);
    let mut at = 0;
    for c in &columns {
        basis.as_mut().subcols_mut(at, c.ncols()).copy_from(c);
        at += c.ncols();
    }
    let fe_modes = fe_modes.unwrap_or_else(|| VibrationModes {
        eigenvalues: Vec::new(),
        frequencies_hz: Vec::new(),
        shapes: Mat::zeros(supported_dofs.n_free(), 0),
        rigid_modes: supported.rigid.ncols(),
        solver: EigenSolver::Auto,
        max_residual: 0.0,
        max_orthogonality_error: 0.0,
    });
    Ok(InterfaceBasis { free, basis, fe_modes, static_modes, rigid_in_span })
}

/// The Craig–Bampton constraint modes over the free model's dofs: for each interface dof `b`, the
/// interior's static response to `b` displaced by 1 with the other interface dofs held. The
/// fixed-interface modes' factor of `K_ii` (`operator`, when it is unshifted) is reused.
fn constraint_modes(
    free: &PreparedModel,
    supported: &PreparedModel,
    operator: Option<&ShiftInvert>,
    interface: &[usize],
    to_supported: &[Option<usize>],
    lift: &dyn Fn(&Mat<f64>) -> Mat<f64>,
) -> Result<Mat<f64>, FemError> {
    let k = &free.assembled.stiffness;
    let mut loads = Mat::zeros(supported.assembled.dofs.n_free(), interface.len());
    for (j, &b) in interface.iter().enumerate() {
        for (i, v) in k.row_idx_of_col(b).zip(k.val_of_col(b)) {
            if let Some(r) = to_supported[i] {
                loads[(r, j)] -= *v;
            }
        }
    }
    let rigid = &supported.rigid;
    let interior = match operator {
        Some(operator) if operator.shift == 0.0 && rigid.ncols() == 0 => {
            let mut x = loads;
            operator.solve_in_place(x.as_mut());
            x
        }
        _ => solve_with_extra_supports(&supported.assembled, &pivot_dofs(rigid), &loads, rigid.ncols())?,
    };
    let interior = if rigid.ncols() > 0 { m_orthogonal_to(&supported.assembled, rigid, &interior)? } else { interior };
    let mut modes = lift(&interior);
    for (j, &b) in interface.iter().enumerate() {
        modes[(b, j)] = 1.0;
    }
    Ok(modes)
}

/// The residual attachment modes: the inertia-relieved static responses to a unit load at each
/// interface dof, less what the free-free modes `kept` carry of them.
fn residual_attachment_modes(free: &PreparedModel, interface: &[usize], kept: Option<&VibrationModes>) -> Result<Mat<f64>, FemError> {
    let n = free.assembled.dofs.n_free();
    let mut loads = Mat::zeros(n, interface.len());
    for (j, &b) in interface.iter().enumerate() {
        loads[(b, j)] = 1.0;
    }
    let (mut modes, _, _) = static_responses(&free.assembled, &free.rigid, loads)?;
    if let Some(kept) = kept {
        for (k, lambda) in kept.eigenvalues.iter().enumerate() {
            for (j, &b) in interface.iter().enumerate() {
                let c = kept.shapes[(b, k)] / lambda;
                for i in 0..n {
                    modes[(i, j)] -= c * kept.shapes[(i, k)];
                }
            }
        }
    }
    Ok(modes)
}

/// The orthonormalized elastic span of `basis`: made M-orthogonal to the rigid motions `rigid`, its
/// vanishing directions (exactly `rigid_in_span` of them, else an error) dropped, and the rest
/// diagonalized by the reduced eigenproblem. Returns the eigenvalues ω² (ascending), the modes, and
/// the smallest scaled Gram eigenvalue kept (the basis' independence).
pub(super) fn orthonormal_elastic_span(
    free: &PreparedModel,
    basis: &Mat<f64>,
    rigid_in_span: usize,
    set: &ModeSet,
) -> Result<(Vec<f64>, Mat<f64>, f64), FemError> {
    let (assembled, rigid) = (&free.assembled, &free.rigid);
    let m = basis.ncols();
    let mass_basis = symmetric_times(&assembled.mass, basis.as_ref());
    // Each column's own M-norm, before the projection: the scale against which a projected
    // direction counts as vanished.
    let mut scaled = if rigid.ncols() > 0 { m_orthogonal_to(assembled, rigid, basis)? } else { basis.clone() };
    for j in 0..m {
        let norm: f64 = (0..basis.nrows()).map(|i| basis[(i, j)] * mass_basis[(i, j)]).sum::<f64>().sqrt();
        if norm.is_nan() || norm <= 0.0 {
            return Err(FemError::SingularBasis { message: format!("mode {} of {set} moves no mass", j + 1) });
        }
        for i in 0..basis.nrows() {
            scaled[(i, j)] /= norm;
        }
    }
    let gram = symmetric_projection(&assembled.mass, scaled.as_ref());
    let gram = symmetrized(&gram);
    let eigen = gram.self_adjoint_eigen(Side::Lower).map_err(|e| FemError::LinearAlgebra(format!("interface basis Gram matrix: {e:?}")))?;
    let kept: Vec<usize> = (0..m).filter(|&k| eigen.S()[k] > RIGID_DIRECTION).collect();
    let dropped = m - kept.len();
    if dropped != rigid_in_span {
        return Err(FemError::SingularBasis {
            message: format!(
                "the modes of {set} span {dropped} dependent direction(s) once the rigid motions are removed, where {rigid_in_span} were rigid motions; use fewer modes"
            ),
        });
    }
    let independence = kept.first().map_or(1.0, |&k| eigen.S()[k]);
    // W = B V Λ^{-1/2}: M-orthonormal, no rigid motion.
    let w_coefficients = Mat::from_fn(m, kept.len(), |i, c| eigen.U()[(i, kept[c])] / eigen.S()[kept[c]].sqrt());
    let w = &scaled * &w_coefficients;
    let reduced = symmetric_projection(&assembled.stiffness, w.as_ref());
    let r = kept.len();
    let reduced = symmetrized(&reduced);
    let eigen = reduced.self_adjoint_eigen(Side::Lower).map_err(|e| FemError::LinearAlgebra(format!("interface reduced eigenproblem: {e:?}")))?;
    let values: Vec<f64> = (0..r).map(|k| eigen.S()[k]).collect();
    Ok((values, &w * eigen.U(), independence))
}
