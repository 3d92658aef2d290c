//! The linearized equations of motion in independent coordinates of the constrained system
//! (formulation.md §10): `M_z δz̈ + C_z δż + K_z δz = 0`, with the position perturbation
//! `δx = N δz` in the null space of the velocity-level Jacobian `B`.
//!
//! **The coordinates.** The independent coordinates are a subset of the velocity coordinates chosen by
//! coordinate partitioning, as DADS does (Wehage and Haug 1982): Gaussian elimination with complete
//! pivoting on `B` takes as dependent the columns of the largest pivots, and the rest are independent.
//! Rotations are measured about the *global* axes (`θ = A δπ̄`), not the body axes of the velocity
//! coordinates, so that a body spinning about a symmetry axis gives constant coefficients and
//! frequencies seen from the inertial frame (a spinning top's precession, a rotor's whirl). With the
//! global Jacobian `B_g = B G⁻¹` (`G` = `Aᵀ` on each rotation block, the identity elsewhere),
//! `N_g = P [−B_d⁻¹ B_i; I]` and `N = G N_g`: each column of `N` is the motion of the mechanism when one
//! independent coordinate moves by one unit and the others stay. Names: `<body>.R.x` (translation,
//! global axes), `<body>.theta.x` (rotation about the global x axis), `<body>.a.k` (modal coordinate).
//!
//! **About a steady motion.** `N` follows the reference motion; with `δv = d(δx)/dt + W δx`
//! (`W = ω̄̃₀` on each rotation block) the equations become (formulation.md §10)
//!
//! ```text
//! M_z = Nᵀ M N
//! C_z = Nᵀ [C N + M (2Ṅ + W N)]
//! K_z = Nᵀ [K N + C (Ṅ + W N) + M (N̈ + W Ṅ + Ẇ N)]
//! ```
//!
//! with `Ṅ`, `N̈` by central differences of `N` along the motion, `q(t₀ ± h) = q₀ ⊕ (±h v₀ + ½h² v̇₀)` with
//! the partition of `t₀` held. At rest `Ṅ = N̈ = W = 0` and the matrices are `NᵀMN`, `NᵀCN`, `NᵀKN`.

use faer::linalg::solvers::Solve;
use faer::Mat;

use super::Linearization;
use crate::analysis::{Accelerations, State};
use crate::data::Data;
use crate::math::{rotation_matrix, Mat3};
use crate::model::Model;
use crate::stage::{jacobian_entries, retract, run_kinematic_stages};

/// A pivot below this fraction of the largest entry of `B` ends the elimination: the remaining rows
/// depend on the others at this state.
const RANK_TOLERANCE: f64 = 1e-9;

/// The independent coordinates at an operating point: which velocity coordinates they are and the
/// null-space basis that maps them to the whole mechanism's motion.
#[derive(Clone, Debug)]
pub struct IndependentCoordinates {
    /// `N`, `nv × n`: the velocity-space displacement `δx` (translations, rotation vector in body axes,
    /// modal coordinates) of a unit change of each independent coordinate.
    pub basis: Mat<f64>,
    /// The velocity coordinate each independent coordinate is (an index into `0..nv`, rotations
    /// about the global axes).
    pub coordinates: Vec<usize>,
    /// A name for each: `<body>.R.x`, `<body>.theta.x` (global axes), `<body>.a.k`.
    pub names: Vec<String>,
}

/// The linear equations of motion in independent coordinates.
#[derive(Clone, Debug)]
pub struct ReducedLinearization {
    /// `M_z`, `n × n`, positive definite; symmetric but for the acceleration columns of a flexible
    /// body's geometric stiffening.
    pub mass: Mat<f64>,
    /// `C_z`, `n × n`: damping, gyroscopic and Coriolis terms.
    pub damping: Mat<f64>,
    /// `K_z`, `n × n`: elastic, gravity, and constraint-force (`(Φ_qᵀλ)_q`) stiffness.
    pub stiffness: Mat<f64>,
    /// The coordinates `δz` and the basis `N`.
    pub independent: IndependentCoordinates,
    /// `Ṅ + W N`, `nv × n`: the velocity a unit `δz` carries along the motion (`δv = N δż + (Ṅ + W N) δz`;
    /// zero at rest).
    pub basis_rate: Mat<f64>,
}

impl ReducedLinearization {
    /// Number of independent coordinates (degrees of freedom).
    pub fn degrees_of_freedom(&self) -> usize {
        self.mass.nrows()
    }
}

/// Which velocity coordinates are dependent: the pivot rows and columns of Gaussian elimination with
/// complete pivoting on the global Jacobian `B_g` (active rows only).
#[derive(Clone, Debug)]
struct Partition {
    rows: Vec<usize>,
    dependent: Vec<usize>,
    independent: Vec<usize>,
}

/// `G(q)`: the body-axes rotation vector of a global one, `δπ̄ = Aᵀ θ`, body by body.
fn body_rotations(model: &Model, q: &[f64]) -> Vec<Mat3> {
    let l = &model.layout;
    (0..model.bodies.len())
        .map(|b| {
            let qo = l.q_offset[b];
            rotation_matrix(&nalgebra::Vector4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6])).transpose()
        })
        .collect()
}

/// `B_g = B G⁻¹` at `q` (rows of switched-off constraints zero).
fn global_jacobian(model: &Model, data: &mut Data, t: f64, q: &[f64], active: &[bool]) -> Mat<f64> {
    let l = &model.layout;
    let v = vec![0.0; l.nv];
    run_kinematic_stages(model, data, t, q, &v);
    let mut jac = Mat::zeros(l.nc, l.nv);
    jacobian_entries(model, data, |row, col, x| {
        if active[row] {
            jac[(row, col)] += x;
        }
    });
    for (b, g) in body_rotations(model, q).iter().enumerate() {
        let c = l.v_offset[b] + 3;
        for row in 0..l.nc {
            let old = [jac[(row, c)], jac[(row, c + 1)], jac[(row, c + 2)]];
            for k in 0..3 {
                jac[(row, c + k)] = (0..3).map(|i| old[i] * g[(i, k)]).sum();
            }
        }
    }
    jac
}

/// Complete pivoting on a copy of `jac`: the pivot rows and (dependent) columns, in elimination order.
fn partition(jac: &Mat<f64>) -> Partition {
    let (nr, nc) = (jac.nrows(), jac.ncols());
    let mut a = jac.clone();
    let scale = (0..nr).flat_map(|i| (0..nc).map(move |j| (i, j))).map(|(i, j)| a[(i, j)].abs()).fold(0.0, f64::max);
    let (mut row_free, mut col_free) = (vec![true; nr], vec![true; nc]);
    let (mut rows, mut dependent) = (Vec::new(), Vec::new());
    loop {
        let mut best = (0.0, 0, 0);
        for i in (0..nr).filter(|&i| row_free[i]) {
            for j in (0..nc).filter(|&j| col_free[j]) {
                if a[(i, j)].abs() > best.0 {
                    best = (a[(i, j)].abs(), i, j);
                }
            }
        }
        let (pivot, pr, pc) = best;
        if pivot <= RANK_TOLERANCE * scale || pivot == 0.0 {
            break;
        }
        row_free[pr] = false;
        col_free[pc] = false;
        rows.push(pr);
        dependent.push(pc);
        for i in (0..nr).filter(|&i| row_free[i]) {
            let f = a[(i, pc)] / a[(pr, pc)];
            if f != 0.0 {
                for j in 0..nc {
                    a[(i, j)] -= f * a[(pr, j)];
                }
            }
        }
    }
    let independent = (0..nc).filter(|&j| col_free[j]).collect();
    Partition { rows, dependent, independent }
}

/// `[N_g | P_g]` at `q` with the partition held (rotations about global axes): the null-space basis,
/// then for each constraint row of `driven` the particular solution `B_g δx_p = e_row` with the
/// independent coordinates held (zero there). Every row of `driven` must be a pivot row of `p`.
fn global_basis_at(model: &Model, data: &mut Data, t: f64, q: &[f64], active: &[bool], p: &Partition, driven: &[usize]) -> Mat<f64> {
    let jac = global_jacobian(model, data, t, q, active);
    let nv = model.layout.nv;
    let (r, n) = (p.dependent.len(), p.independent.len());
    let mut ng = Mat::zeros(nv, n + driven.len());
    for (k, &c) in p.independent.iter().enumerate() {
        ng[(c, k)] = 1.0;
    }
    if r > 0 {
        let bd = Mat::from_fn(r, r, |i, j| jac[(p.rows[i], p.dependent[j])]);
        let rhs = Mat::from_fn(r, n + driven.len(), |i, j| match j.checked_sub(n) {
            None => -jac[(p.rows[i], p.independent[j])],
            Some(d) => f64::from(u8::from(p.rows[i] == driven[d])),
        });
        let x = bd.partial_piv_lu().solve(&rhs);
        for (i, &c) in p.dependent.iter().enumerate() {
            for k in 0..n + driven.len() {
                ng[(c, k)] = x[(i, k)];
            }
        }
    }
    ng
}

/// `G x`: the global rotation vectors of `x` turned into body axes, body by body, at `q`.
fn to_body_axes(model: &Model, q: &[f64], x: &Mat<f64>) -> Mat<f64> {
    let l = &model.layout;
    let mut out = x.clone();
    for (b, g) in body_rotations(model, q).iter().enumerate() {
        let c = l.v_offset[b] + 3;
        for k in 0..x.ncols() {
            let theta = [x[(c, k)], x[(c + 1, k)], x[(c + 2, k)]];
            for i in 0..3 {
                out[(c + i, k)] = (0..3).map(|j| g[(i, j)] * theta[j]).sum();
            }
        }
    }
    out
}

/// `x` with the entries at or below `floor` (the rounding of a difference quotient) set to zero, so
/// that a basis that does not change along the motion has exactly zero rates.
fn without_rounding(mut x: Mat<f64>, floor: f64) -> Mat<f64> {
    for j in 0..x.ncols() {
        for i in 0..x.nrows() {
            if x[(i, j)].abs() <= floor {
                x[(i, j)] = 0.0;
            }
        }
    }
    x
}

/// The names of the velocity coordinates as independent coordinates (rotations about global axes).
fn coordinate_names(model: &Model) -> Vec<String> {
    let mut names = Vec::with_capacity(model.layout.nv);
    for (b, body) in model.bodies.iter().enumerate() {
        names.extend(["R.x", "R.y", "R.z", "theta.x", "theta.y", "theta.z"].iter().map(|c| format!("{}.{c}", body.name)));
        names.extend((1..=model.layout.modes[b]).map(|k| format!("{}.a.{k}", body.name)));
    }
    names
}

/// `W δx`: the angular-velocity cross product on each rotation block (`δω̄ = δπ̄̇ + ω̄₀ × δπ̄`).
fn apply_spin(model: &Model, omega_source: &[f64], x: &Mat<f64>) -> Mat<f64> {
    let l = &model.layout;
    let mut out = Mat::zeros(x.nrows(), x.ncols());
    for b in 0..model.bodies.len() {
        let c = l.v_offset[b] + 3;
        let w = [omega_source[c], omega_source[c + 1], omega_source[c + 2]];
        for k in 0..x.ncols() {
            let d = [x[(c, k)], x[(c + 1, k)], x[(c + 2, k)]];
            out[(c, k)] = w[1] * d[2] - w[2] * d[1];
            out[(c + 1, k)] = w[2] * d[0] - w[0] * d[2];
            out[(c + 2, k)] = w[0] * d[1] - w[1] * d[0];
        }
    }
    out
}

/// The time step of the central differences of `N` along the motion: a rotation of about 10⁻³ rad, a
/// translation of 10⁻³ times the largest velocity's unit (none when the mechanism is at rest).
fn motion_step(state: &State, acc: &Accelerations) -> Option<f64> {
    let speed = state.v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let accel = acc.vdot.iter().fold(0.0_f64, |m, x| m.max(x.abs())).sqrt();
    let rate = speed.max(accel);
    (rate > 0.0).then(|| 1e-3 / rate)
}

/// Reduces `lin` (taken at `state` with `acc`) to independent coordinates. `data` is used to evaluate
/// the constraint Jacobian along the motion and is left evaluated at some nearby state.
///
/// With `N = G N_g` and `Ġ = −W G` (the body axes turn with `ω̄₀`) the rates of `N` in the equations
/// are those of the global basis alone, `Ṅ + W N = G Ṅ_g` and `N̈ + W Ṅ + Ẇ N = G N̈_g − W G Ṅ_g`, so
/// that a spin about a symmetry axis, which leaves `N_g` unchanged, adds no differencing error.
pub fn reduce_to_independent(model: &Model, data: &mut Data, state: &State, acc: &Accelerations, lin: &Linearization) -> ReducedLinearization {
    match reduce_with_particular(model, data, state, acc, lin, &[]) {
        Ok((reduced, _)) => reduced,
        Err(_) => unreachable!("no driven rows to find among the pivots"),
    }
}

/// The reduced equations and, for the constraint rows `driven`, the particular motions `P` (`B δx_p =
/// e_row`, the independent coordinates held) with their terms in the reduced equations,
/// `Nᵀ [M, C, K]`-products of `P` built as those of `N` are:
///
/// ```text
/// M_zu = Nᵀ M P,   C_zu = Nᵀ [C P + M (2Ṗ + W P)],   K_zu = Nᵀ [K P + C (Ṗ + W P) + M (P̈ + W Ṗ + Ẇ P)]
/// ```
///
/// A row of `driven` that the partition found dependent on the others is an error naming it.
pub(super) fn reduce_with_particular(
    model: &Model,
    data: &mut Data,
    state: &State,
    acc: &Accelerations,
    lin: &Linearization,
    driven: &[usize],
) -> Result<(ReducedLinearization, ParticularMotion), usize> {
    let jac = global_jacobian(model, data, state.t, &state.q, &state.active);
    let p = partition(&jac);
    if let Some(&row) = driven.iter().find(|row| !p.rows.contains(row)) {
        return Err(row);
    }
    let ng = global_basis_at(model, data, state.t, &state.q, &state.active, &p, driven);
    let nv = model.layout.nv;
    let (mut ng_dot, mut ng_ddot) = (Mat::<f64>::zeros(nv, ng.ncols()), Mat::<f64>::zeros(nv, ng.ncols()));
    if let Some(h) = motion_step(state, acc) {
        let along = |sign: f64| -> Vec<f64> {
            let d: Vec<f64> = state.v.iter().zip(&acc.vdot).map(|(v, a)| sign * h * v + 0.5 * h * h * a).collect();
            let mut q = vec![0.0; state.q.len()];
            retract(&model.layout, &state.q, &d, &mut q);
            q
        };
        let (q_plus, q_minus) = (along(1.0), along(-1.0));
        let plus = global_basis_at(model, data, state.t + h, &q_plus, &state.active, &p, driven);
        let minus = global_basis_at(model, data, state.t - h, &q_minus, &state.active, &p, driven);
        let size = (0..nv).flat_map(|i| (0..ng.ncols()).map(move |j| (i, j))).map(|(i, j)| ng[(i, j)].abs()).fold(0.0, f64::max);
        let eps = 64.0 * f64::EPSILON * size;
        ng_dot = without_rounding((&plus - &minus) * (0.5 / h), eps / h);
        ng_ddot = without_rounding((&plus - &ng * 2.0 + &minus) * (1.0 / (h * h)), 4.0 * eps / (h * h));
    }
    let n_free = p.independent.len();
    let e = to_body_axes(model, &state.q, &ng);
    let g_e_dot = to_body_axes(model, &state.q, &ng_dot);
    let g_e_ddot = to_body_axes(model, &state.q, &ng_ddot);
    let we = apply_spin(model, &state.v, &e);
    let n = e.as_ref().subcols(0, n_free).to_owned();
    let nt = n.transpose();
    let (m, c, k) = (&lin.mass, &lin.damping, &lin.stiffness);
    // 2Ṅ + W N = 2 G Ṅ_g − W N;  Ṅ + W N = G Ṅ_g;  N̈ + W Ṅ + Ẇ N = G N̈_g − W G Ṅ_g (and alike for P).
    let mass = nt * m * &e;
    let damping = nt * (c * &e + m * (&g_e_dot * 2.0 - &we));
    let stiffness = nt * (k * &e + c * &g_e_dot + m * (&g_e_ddot - apply_spin(model, &state.v, &g_e_dot)));
    let (first, rest) = (|x: &Mat<f64>| x.as_ref().subcols(0, n_free).to_owned(), |x: &Mat<f64>| x.as_ref().subcols(n_free, driven.len()).to_owned());
    let names = coordinate_names(model);
    let independent = IndependentCoordinates {
        names: p.independent.iter().map(|&i| names[i].clone()).collect(),
        coordinates: p.independent,
        basis: n,
    };
    let reduced = ReducedLinearization { mass: first(&mass), damping: first(&damping), stiffness: first(&stiffness), independent, basis_rate: first(&g_e_dot) };
    let particular = ParticularMotion { mass: rest(&mass), damping: rest(&damping), stiffness: rest(&stiffness), motion: rest(&e), motion_rate: rest(&g_e_dot) };
    Ok((reduced, particular))
}

/// The particular motions of prescribed constraint values and their terms in the reduced equations
/// (see [`reduce_with_particular`]).
#[derive(Clone, Debug)]
pub(super) struct ParticularMotion {
    pub(super) mass: Mat<f64>,
    pub(super) damping: Mat<f64>,
    pub(super) stiffness: Mat<f64>,
    pub(super) motion: Mat<f64>,
    pub(super) motion_rate: Mat<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Complete pivoting on a Jacobian with a dependent row: the rank, and `B N = 0`.
    #[test]
    fn the_partition_spans_the_null_space_of_a_rank_deficient_jacobian() {
        let jac = Mat::from_fn(3, 5, |i, j| match i {
            0 => [1.0, 2.0, 0.0, 0.5, 0.0][j],
            1 => [0.0, 1.0, 3.0, 0.0, 1.0][j],
            _ => [1.0, 3.0, 3.0, 0.5, 1.0][j],
        });
        let p = partition(&jac);
        assert_eq!((p.dependent.len(), p.independent.len()), (2, 3));
    }
}
