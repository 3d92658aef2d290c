//! Static correction modes: the static response of the supported model to a unit load along each
//! deleted joint constraint (the seed's "static correction modes").
//!
//! With under-determined supports `K` is singular: the rigid motions `R` the supports leave carry no
//! strain. A load that does not excite them (`Rᵀ f = 0`, the usual case: a torque normal to the hinge
//! line) has a static solution, unique up to `R`; the one returned is M-orthogonal to `R`. A load that
//! does excite them is first balanced by the rigid-body inertia forces it would cause (inertia relief,
//! `f − M R (RᵀMR)⁻¹ Rᵀ f`), and the mode reports how much of the load was so balanced.
//!
//! The singular system is solved exactly by holding, in addition to the supports, as many free dofs
//! as there are rigid motions, chosen so that they fix those motions (a statically determinate extra
//! set, Nastran's SUPORT); for a balanced load their reactions vanish.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use crate::assembly::AssembledModel;
use crate::error::FemError;
use crate::mesh::{Dof, FeModel, StaticLoadKind};
use crate::modes::rigid::pivot_dofs;

/// The static correction modes of a model, over its free dofs.
#[derive(Clone, Debug)]
pub struct StaticModes {
    /// The names of the loads, in the order of the model's static loads.
    pub names: Vec<String>,
    /// The static displacements (`n_free × s`), in m per N or rad per N m of the unit load.
    pub shapes: Mat<f64>,
    /// For each load, the fraction `‖Rᵀf‖ / ‖f‖` that excited the rigid motions and was balanced by
    /// inertia relief (0 for a load the supports fully react).
    pub rigid_load_fractions: Vec<f64>,
    /// Largest relative residual `‖Kφ − f‖ / ‖f‖` of the solutions (balanced loads).
    pub max_residual: f64,
}

/// The unit load vectors of the model's static loads over the free dofs (`n_free × s`).
pub fn load_vectors(model: &FeModel, assembled: &AssembledModel) -> Result<Mat<f64>, FemError> {
    let dofs = &assembled.dofs;
    let mut loads = Mat::zeros(dofs.n_free(), model.static_loads.len());
    for (j, load) in model.static_loads.iter().enumerate() {
        let (direction, first) = match load.kind {
            StaticLoadKind::Force(d) => (d, 0),
            StaticLoadKind::Torque(d) => (d, 3),
        };
        let unit = direction / direction.norm();
        for k in 0..3 {
            if unit[k].abs() < 1e-14 {
                continue;
            }
            let dof = Dof::ALL[first + k];
            let global = 6 * load.node + dof.index();
            match dofs.equation(load.node, dof) {
                Some(e) => loads[(e, j)] = unit[k],
                None if dofs.is_dependent(global) => {
                    dofs.terms(global).into_iter().for_each(|(e, c)| loads[(e, j)] += c * unit[k]);
                }
                None if !dofs.is_present(global) => {
                    return Err(FemError::LoadOnAbsentDof {
                        name: load.name.clone(),
                        label: model.mesh.nodes[load.node].label,
                        dof: dof.name(),
                    })
                }
                None => {
                    return Err(FemError::LoadOnSupport {
                        name: load.name.clone(),
                        label: model.mesh.nodes[load.node].label,
                        dof: dof.name(),
                    })
                }
            }
        }
    }
    Ok(loads)
}

/// The static correction modes of `model`; `rigid` holds the free rigid motions (orthonormal
/// columns, from [`free_rigid_motions`](crate::modes::rigid::free_rigid_motions)).
pub fn static_correction_modes(
    model: &FeModel,
    assembled: &AssembledModel,
    rigid: &Mat<f64>,
) -> Result<StaticModes, FemError> {
    let names: Vec<String> = model.static_loads.iter().map(|l| l.name.clone()).collect();
    let loads = load_vectors(model, assembled)?;
    let (shapes, rigid_load_fractions, max_residual) = static_responses(assembled, rigid, loads)?;
    Ok(StaticModes { names, shapes, rigid_load_fractions, max_residual })
}

/// The static responses to the columns of `loads` (over the free dofs), each balanced by inertia
/// relief where it excites the rigid motions `rigid` and made M-orthogonal to them; with each
/// load's fraction `‖Rᵀf‖ / ‖f‖` so balanced and the largest relative residual.
pub(crate) fn static_responses(
    assembled: &AssembledModel,
    rigid: &Mat<f64>,
    mut loads: Mat<f64>,
) -> Result<(Mat<f64>, Vec<f64>, f64), FemError> {
    let s = loads.ncols();
    let mut rigid_load_fractions = vec![0.0; s];
    if rigid.ncols() > 0 {
        for j in 0..s {
            let excitation = rigid.transpose() * loads.col(j);
            rigid_load_fractions[j] = excitation.norm_l2() / loads.col(j).norm_l2();
        }
        loads = inertia_relief(assembled, rigid, &loads)?;
    }
    let held = pivot_dofs(rigid);
    let solution = solve_with_extra_supports(assembled, &held, &loads, rigid.ncols())?;
    let shapes = if rigid.ncols() > 0 { m_orthogonal_to(assembled, rigid, &solution)? } else { solution };
    let residual = &assembled.stiffness * &shapes - &loads;
    let mut max_residual = 0.0_f64;
    for j in 0..s {
        max_residual = max_residual.max(residual.col(j).norm_l2() / loads.col(j).norm_l2().max(f64::MIN_POSITIVE));
    }
    Ok((shapes, rigid_load_fractions, max_residual))
}

/// `f − M R (RᵀMR)⁻¹ Rᵀ f`: the load balanced by the rigid-body inertia forces it causes.
fn inertia_relief(assembled: &AssembledModel, rigid: &Mat<f64>, loads: &Mat<f64>) -> Result<Mat<f64>, FemError> {
    let m_r = &assembled.mass * rigid;
    let rigid_mass = rigid.transpose() * &m_r;
    let mut coefficients = rigid.transpose() * loads;
    rigid_mass.partial_piv_lu().solve_in_place(coefficients.as_mut());
    Ok(loads - &m_r * &coefficients)
}

/// `x − R (RᵀMR)⁻¹ RᵀM x`: the part of `x` M-orthogonal to the rigid motions.
pub(crate) fn m_orthogonal_to(assembled: &AssembledModel, rigid: &Mat<f64>, x: &Mat<f64>) -> Result<Mat<f64>, FemError> {
    let m_r = &assembled.mass * rigid;
    let rigid_mass = rigid.transpose() * &m_r;
    let mut coefficients = m_r.transpose() * x;
    rigid_mass.partial_piv_lu().solve_in_place(coefficients.as_mut());
    Ok(x - rigid * &coefficients)
}

/// Solves `K x = f` with the dofs `held` also held at zero (their rows dropped).
pub(crate) fn solve_with_extra_supports(
    assembled: &AssembledModel,
    held: &[usize],
    loads: &Mat<f64>,
    rigid: usize,
) -> Result<Mat<f64>, FemError> {
    let n = assembled.dofs.n_free();
    let mut reduced_index = vec![None; n];
    let mut count = 0;
    for (i, slot) in reduced_index.iter_mut().enumerate() {
        if !held.contains(&i) {
            *slot = Some(count);
            count += 1;
        }
    }
    let k = &assembled.stiffness;
    let mut triplets = Vec::with_capacity(k.compute_nnz());
    for j in 0..n {
        let Some(c) = reduced_index[j] else { continue };
        for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
            if let Some(r) = reduced_index[i] {
                triplets.push(Triplet::new(r, c, *v));
            }
        }
    }
    let reduced = SparseColMat::try_new_from_triplets(count, count, &triplets)
        .map_err(|e| FemError::LinearAlgebra(format!("static stiffness: {e:?}")))?;
    let factor = reduced.sp_cholesky(Side::Lower).map_err(|_| FemError::Mechanism { rigid })?;
    let mut rhs = Mat::from_fn(count, loads.ncols(), |_, _| 0.0);
    for (i, slot) in reduced_index.iter().enumerate() {
        if let Some(r) = slot {
            for j in 0..loads.ncols() {
                rhs[(*r, j)] = loads[(i, j)];
            }
        }
    }
    factor.solve_in_place(rhs.as_mut());
    Ok(Mat::from_fn(n, loads.ncols(), |i, j| reduced_index[i].map_or(0.0, |r| rhs[(r, j)])))
}
