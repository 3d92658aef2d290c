//! Assembly (position analysis): Newton–Raphson on `Φ̂(q) = [Φ(q, t); pᵀp − 1] = 0` from the approximate
//! configuration in the model file, each step the minimum-norm correction
//! `Δq = −Φ̂_qᵀ (Φ̂_q Φ̂_qᵀ)⁻¹ Φ̂` with backtracking. Redundant rows are found first and switched off.
//! What may move is chosen by [`ModalAssembly`]: the body frames, the frames and the modal coordinates,
//! or the modal coordinates alone in the static deformation of least strain energy.

use faer::prelude::*;

use super::massless_motions::check_massless_motions_held;
use super::memory::{analysis_bytes, format_bytes, MemoryLimit};
use super::redundancy::{dependency_of, find_redundant_rows, violated_rows, RedundantConstraint, ViolatedEquation};
use super::static_deformation::static_deformation_step;
use super::State;
use crate::data::Data;
use crate::linalg::{NormalEquations, SparseRows};
use crate::math::euler_parameters::g_matrix;
use crate::math::Vec4;
use crate::model::{Model, SizeCheck, SizeMismatch};
use crate::stage::{jacobian_entries, run_kinematic_stages};

/// Settings of the assembly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AssemblySettings {
    /// Largest absolute constraint residual accepted (m for point equations, dimensionless for dot-1).
    pub tolerance: f64,
    /// Most Newton iterations before giving up.
    pub max_iterations: usize,
    /// What the assembly may change in flexible bodies.
    pub modal: ModalAssembly,
    /// Memory the initial-condition analyses may use; a larger model is refused before anything is
    /// allocated.
    pub memory_limit: MemoryLimit,
}

impl Default for AssemblySettings {
    fn default() -> Self {
        Self { tolerance: 1e-10, max_iterations: 50, modal: ModalAssembly::Held, memory_limit: MemoryLimit::Available }
    }
}

/// How the assembly treats the modal coordinates of flexible bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ModalAssembly {
    /// They stay at their initial values; only the body frames move.
    #[default]
    Held,
    /// Frames and modal coordinates move together, each step the least change (Euclidean) in both.
    Free,
    /// The body frames stay where the model puts them; the modal coordinates take the deformation of
    /// least strain energy that closes the joints: the static deformation of a structure held by its
    /// frame and bent to fit its joints (see `static_deformation.rs`). Joints that the deformation
    /// cannot close (between frames alone) must already hold.
    Static,
}

/// What the assembly did.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct AssemblyReport {
    /// Newton iterations made.
    pub iterations: usize,
    /// Largest residual before the assembly.
    pub initial_residual: f64,
    /// Largest residual after it.
    pub residual: f64,
    /// The constraint rows found redundant and switched off.
    pub redundant: Vec<RedundantConstraint>,
    /// Degrees of freedom: velocity coordinates minus independent constraints.
    pub degrees_of_freedom: usize,
}

/// Why the assembly (or the velocity analysis after it) failed.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum AssemblyError {
    /// The Newton iteration did not bring the residuals below the tolerance.
    #[error(
        "assembly did not converge in {iterations} iterations: largest residual {residual:.3e} in {worst}; \
         check that the markers of that joint can be brought together from the given initial poses"
    )]
    NotConverged {
        /// Iterations made.
        iterations: usize,
        /// The largest residual left.
        residual: f64,
        /// The equation that has it.
        worst: String,
    },
    /// A linear system of the analysis is singular although the redundant rows were removed: rows in
    /// force have become dependent during the iteration (`dependent` names them when they are found).
    #[error("{what}: the constraint matrix is singular even after removing redundant rows{dependent}")]
    Singular {
        /// Which analysis.
        what: &'static str,
        /// The dependent rows, as a clause (may be empty).
        dependent: String,
    },
    /// Declared equations that depend on the others at the assembled configuration do not hold there
    /// (position or velocity level): the mechanism is at a singular position where they cannot all hold.
    #[error("{}", singular_position_message(*t, level, violated, dependency))]
    SingularPosition {
        /// Time (s).
        t: f64,
        /// `"position"` or `"velocity"`.
        level: &'static str,
        /// The removed equations that do not hold, largest residual first.
        violated: Vec<ViolatedEquation>,
        /// The equations in force that the first of them depends on.
        dependency: Vec<String>,
    },
    /// A constraint equation's value or time derivative is not finite (a driver's function evaluated
    /// outside its domain, or a non-finite position).
    #[error(
        "at t = {t} s {equation} is not finite (its {what} is {value}): check the driver's or distance's \
         function of time at this time (sqrt or ln of a negative number, a division by zero) and the \
         positions of its markers"
    )]
    NonFinite {
        /// Time (s).
        t: f64,
        /// The equation.
        equation: String,
        /// `value` or `time derivative`.
        what: &'static str,
        /// What it is.
        value: f64,
    },
    /// A motion of a flexible body carries no mass and neither a constraint in force nor the gauge of
    /// the frame's spin holds it: its acceleration is undetermined
    /// ([`ModalBody::massless_motions`](crate::body::ModalBody::massless_motions); the gauge: the module
    /// `analysis::massless_motions`).
    #[error(
        "flexible body '{body}': {motion} carries no mass (its nodes have no rotary inertia and lie on that axis, \
         as a straight beam's do) and no joint holds it, so its acceleration is undetermined: attach a joint that \
         holds that rotation, or give the body rotary inertia (rotary_inertia = true in its FE model, or a [[mass]] \
         with rotary_inertia at a node)"
    )]
    MasslessMotion {
        /// The body.
        body: String,
        /// The motion, in words (axis and point in the body frame).
        motion: String,
    },
    /// The workspace or the state is not of the model's sizes (made for another model).
    #[error(transparent)]
    SizeMismatch(#[from] SizeMismatch),
    /// The initial-condition analyses would need more memory than the machine has.
    #[error(
        "the model is too large for the initial-condition analyses: they need about {} for {nc} \
         constraint equations and {nv} velocity coordinates, and {} {}; use a smaller model (fewer bodies \
         or modes)",
        format_bytes(*needed),
        format_bytes(*available),
        if *machine { "is available on this machine" } else { "is the memory limit given" }
    )]
    TooLarge {
        /// Bytes needed.
        needed: u64,
        /// Bytes available.
        available: u64,
        /// Whether `available` is the machine's available memory (else a limit the caller gave).
        machine: bool,
        /// Constraint equations.
        nc: usize,
        /// Velocity coordinates.
        nv: usize,
    },
}

fn singular_position_message(t: f64, level: &str, violated: &[ViolatedEquation], dependency: &[String]) -> String {
    let first = &violated[0];
    let mut s = format!(
        "at t = {t} s the declared constraints cannot all hold: their equations are dependent at this \
         configuration (the mechanism is at a singular position, or joints repeat each other), and {} has a \
         {level} residual of {:.3e}",
        first.description, first.residual
    );
    if !dependency.is_empty() {
        s.push_str(&format!(" while it depends there on {}", dependency.join("; ")));
    }
    if violated.len() > 1 {
        let others: Vec<String> = violated[1..].iter().map(|v| format!("{} ({:.3e})", v.description, v.residual)).collect();
        s.push_str(&format!("; so do {}", others.join("; ")));
    }
    s.push_str(if level == "velocity" {
        ". A driver prescribes a motion the mechanism cannot make at this position (a dead centre, a locked \
         or singular configuration); start the model away from it, or drive another joint"
    } else {
        ". Joints that repeat each other must agree geometrically; a driver cannot prescribe a position the \
         mechanism cannot reach; and from initial poses at a singular position the assembly cannot tell which \
         way to move: give poses near the assembled configuration"
    });
    s
}

/// Largest attempts at the set of redundant rows: the set found at the initial configuration can
/// change at the assembled one (a row that did not hold is kept first, a dependency can vanish).
const MAX_REDUNDANCY_PASSES: usize = 4;

/// Assembles `state.q` at `state.t` in place; sets `state.active`.
///
/// Rows that depend on others are switched off, chosen among the rows that hold, drivers last (see
/// `redundancy.rs`); afterwards every declared equation, switched off or not, must hold to
/// `settings.tolerance`, else the mechanism is at a singular position and the assembly fails naming
/// the equations that cannot hold.
pub fn assemble(
    model: &Model,
    data: &mut Data,
    state: &mut State,
    settings: AssemblySettings,
) -> Result<AssemblyReport, AssemblyError> {
    check_state(model, data, state)?;
    check_memory(model, settings.memory_limit)?;
    let (mut redundant, mut rank) = find_redundant_rows(model, data, state.t, &state.q, settings.tolerance);
    check_finite(model, data, state.t)?;
    set_active(state, &redundant);
    let initial_residual = residual_norm(model, data, state);
    let mut iterations = newton(model, data, state, settings)?;
    // The rank can differ at the assembled configuration; if so, assemble again with the new set.
    for _ in 1..MAX_REDUNDANCY_PASSES {
        let (again, rank2) = find_redundant_rows(model, data, state.t, &state.q, settings.tolerance);
        if again == redundant {
            break;
        }
        redundant = again;
        rank = rank2;
        set_active(state, &redundant);
        iterations += newton(model, data, state, settings)?;
    }
    let residual = residual_norm(model, data, state);
    let violated = violated_rows(model, data, &state.active, false, settings.tolerance);
    if !violated.is_empty() {
        let dependency = dependency_of(model, data, &state.active, &violated[0]);
        return Err(AssemblyError::SingularPosition { t: state.t, level: "position", violated, dependency });
    }
    check_massless_motions_held(model, data, state)?;
    Ok(AssemblyReport {
        iterations,
        initial_residual,
        residual,
        redundant,
        degrees_of_freedom: model.layout.nv - rank,
    })
}

/// Moves `state.q` onto the constraints in force (the rows of `state.active`, which stay) by the
/// assembly's Newton iteration, the minimum-norm correction; returns its iterations. Fails as
/// [`assemble`] does when it does not converge or a row cannot hold.
pub(crate) fn project_positions(model: &Model, data: &mut Data, state: &mut State, settings: AssemblySettings) -> Result<usize, AssemblyError> {
    check_state(model, data, state)?;
    let iterations = newton(model, data, state, settings)?;
    let violated = violated_rows(model, data, &state.active, false, settings.tolerance);
    if !violated.is_empty() {
        let dependency = dependency_of(model, data, &state.active, &violated[0]);
        return Err(AssemblyError::SingularPosition { t: state.t, level: "position", violated, dependency });
    }
    Ok(iterations)
}

/// Fails on the first constraint equation whose value or time derivative is not finite (after
/// `constraint_equations` at `t`).
pub(crate) fn check_finite(model: &Model, data: &Data, t: f64) -> Result<(), AssemblyError> {
    for (row, terms) in data.equations.iter().enumerate() {
        for (what, value) in [("value", terms.phi), ("time derivative", terms.phi_t)] {
            if !value.is_finite() {
                return Err(AssemblyError::NonFinite { t, equation: model.describe_constraint_row(row), what, value });
            }
        }
    }
    Ok(())
}

/// Refuses a model whose initial-condition analyses would need more memory than `limit` allows.
fn check_memory(model: &Model, limit: MemoryLimit) -> Result<(), AssemblyError> {
    let l = &model.layout;
    let needed = analysis_bytes(model);
    match limit.bytes() {
        Some(available) if needed > available => {
            let machine = limit == MemoryLimit::Available;
            Err(AssemblyError::TooLarge { needed, available, machine, nc: l.nc, nv: l.nv })
        }
        _ => Ok(()),
    }
}

/// The rows in force that have become dependent at `state.q`, for a singular-matrix message.
fn dependent_note(model: &Model, data: &mut Data, state: &State) -> String {
    super::newly_dependent_rows(model, data, state.t, &state.q, &state.active).map(|n| format!("; {n}")).unwrap_or_default()
}

fn set_active(state: &mut State, redundant: &[RedundantConstraint]) {
    state.active.fill(true);
    for r in redundant {
        state.active[r.row] = false;
    }
}

/// Evaluates `Φ̂` (active rows, then one normalization row per body) at `state.q`.
fn constraint_values(model: &Model, data: &mut Data, state: &State, out: &mut Vec<f64>) {
    let zero_v = vec![0.0; model.layout.nv];
    run_kinematic_stages(model, data, state.t, &state.q, &zero_v);
    out.clear();
    out.extend(data.equations.iter().zip(&state.active).filter(|(_, a)| **a).map(|(e, _)| e.phi));
    for b in 0..model.bodies.len() {
        let qo = model.layout.q_offset[b];
        out.push((3..7).map(|k| state.q[qo + k].powi(2)).sum::<f64>() - 1.0);
    }
}

fn residual_norm(model: &Model, data: &mut Data, state: &State) -> f64 {
    let mut phi = Vec::new();
    constraint_values(model, data, state, &mut phi);
    phi.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

fn newton(model: &Model, data: &mut Data, state: &mut State, settings: AssemblySettings) -> Result<usize, AssemblyError> {
    let l = &model.layout;
    let active_rows: Vec<usize> = (0..l.nc).filter(|r| state.active[*r]).collect();
    let mut phi = Vec::new();
    // The pattern of Φ̂_q stays over the iterations: its normal matrix is analysed once.
    let mut normal = NormalEquations::default();
    for it in 0..=settings.max_iterations {
        constraint_values(model, data, state, &mut phi);
        let norm = phi.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        if norm <= settings.tolerance && phi.iter().all(|x| x.is_finite()) {
            return Ok(it);
        }
        if it == settings.max_iterations {
            break;
        }
        let modal = settings.modal != ModalAssembly::Held;
        let gq = position_jacobian(model, data, state, &active_rows, modal);
        let mut dq = vec![0.0; l.nq];
        let solved = match settings.modal {
            ModalAssembly::Static => static_deformation_step(model, &state.q, &dense(&gq), &phi).map(|step| {
                dq.iter_mut().enumerate().for_each(|(k, x)| *x = step[(k, 0)]);
            }),
            _ => {
                // Δq = −Φ̂_qᵀ z with (Φ̂_q Φ̂_qᵀ) z = Φ̂.
                let mut z = phi.clone();
                normal.solve(&gq, None, &mut z).ok().map(|()| {
                    gq.multiply_transposed(&z, &mut dq);
                    dq.iter_mut().for_each(|x| *x = -*x);
                })
            }
        };
        if solved.is_none() || !dq.iter().all(|x| x.is_finite()) {
            let dependent = dependent_note(model, data, state);
            let what = if settings.modal == ModalAssembly::Static { "static deformation" } else { "assembly" };
            return Err(AssemblyError::Singular { what, dependent });
        }
        // Backtracking on the largest residual.
        let q0 = state.q.clone();
        let mut alpha = 1.0;
        loop {
            for k in 0..l.nq {
                state.q[k] = q0[k] + alpha * dq[k];
            }
            if residual_norm(model, data, state) < norm || alpha < 1e-3 {
                break;
            }
            alpha *= 0.5;
        }
    }
    constraint_values(model, data, state, &mut phi);
    let (worst_k, residual) =
        phi.iter().enumerate().fold((0, 0.0_f64), |(bk, bv), (k, x)| if x.abs() > bv { (k, x.abs()) } else { (bk, bv) });
    let worst = if worst_k < active_rows.len() {
        model.describe_constraint_row(active_rows[worst_k])
    } else {
        format!("the normalization of body '{}'", model.bodies[worst_k - active_rows.len()].name)
    };
    Err(AssemblyError::NotConverged { iterations: settings.max_iterations, residual, worst })
}

/// Sparse `Φ̂_q` in positions: `Φ_R = B_Ṙ`, `Φ_p = B_ω̄ 2G(p)`, `(pᵀp)_p = 2pᵀ`, and `Φ_a = B_ȧ` when
/// the modal coordinates may move (else no entries, which holds them) (after `constraint_values`). Rows:
/// the rows in force, then one normalization row per body.
pub(crate) fn position_jacobian(model: &Model, data: &Data, state: &State, active_rows: &[usize], modal: bool) -> SparseRows {
    let l = &model.layout;
    let nb = model.bodies.len();
    let m = active_rows.len() + nb;
    let mut row_of = vec![usize::MAX; l.nc];
    for (k, r) in active_rows.iter().enumerate() {
        row_of[*r] = k;
    }
    let mut body_of_v = vec![0; l.nv];
    let mut g2 = Vec::with_capacity(nb);
    for b in 0..nb {
        body_of_v[l.v_span(b)].fill(b);
        let qo = l.q_offset[b];
        let p = Vec4::new(state.q[qo + 3], state.q[qo + 4], state.q[qo + 5], state.q[qo + 6]);
        g2.push(2.0 * g_matrix(&p));
    }
    let mut entries = Vec::new();
    jacobian_entries(model, data, |r, c, x| {
        let r = row_of[r];
        if r == usize::MAX {
            return;
        }
        let b = body_of_v[c];
        let (qo, k) = (l.q_offset[b], c - l.v_offset[b]);
        match k {
            0..=2 => entries.push((r, qo + k, x)),
            3..=5 => entries.extend((0..4).map(|c| (r, qo + 3 + c, x * g2[b][(k - 3, c)]))),
            _ if modal => entries.push((r, qo + 7 + (k - 6), x)),
            _ => {}
        }
    });
    for b in 0..nb {
        let qo = l.q_offset[b];
        entries.extend((0..4).map(|c| (active_rows.len() + b, qo + 3 + c, 2.0 * state.q[qo + 3 + c])));
    }
    SparseRows::from_entries(m, l.nq, entries)
}

/// The dense matrix of `a` (for the static deformation, whose flexible bodies have few rows).
fn dense(a: &SparseRows) -> Mat<f64> {
    let mut d = Mat::<f64>::zeros(a.nrows(), a.ncols());
    for r in 0..a.nrows() {
        let (cols, values) = a.row(r);
        cols.iter().zip(values).for_each(|(c, x)| d[(r, *c)] = *x);
    }
    d
}

/// `data` and `state` (positions, velocities, rows in force) of `model`'s sizes.
pub(crate) fn check_state(model: &Model, data: &Data, state: &State) -> Result<(), SizeMismatch> {
    SizeCheck::new(model).data(data)?.state(state)?;
    Ok(())
}
