//! Vibration modes of a supported FE model: the lowest eigenpairs of `K φ = ω² M φ`, mass-normalized
//! and sorted, with the rigid mechanisms of under-determined supports set aside.
//!
//! Both solvers work on the shift-invert operator of [`shift_invert`]: the dense one forms it
//! completely and calls a symmetric eigensolver (small models), the other runs a thick-restart Lanczos
//! iteration on it with one sparse Cholesky factorization (large models). Every mode's
//! residual `‖K φ − ω² M φ‖` and the M-orthogonality of the set are checked before the modes are
//! returned.

mod dense;
mod lanczos;
mod nested_dissection;
pub mod rigid;
pub mod shift_invert;

use faer::Mat;

use crate::assembly::{assemble, AssembledModel};
use crate::error::FemError;
use crate::memory::{dense_eigensolver_bytes, mode_analysis_bytes};
use crate::mesh::{Dof, DofSet, FeModel, Support};
use crate::symmetric_product::symmetric_times;
use shift_invert::ShiftInvert;

/// Which eigensolver to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EigenSolver {
    /// Dense up to [`EigenSettings::dense_limit`] free dofs, Lanczos above.
    #[default]
    Auto,
    /// The dense symmetric eigensolver on the whole shifted operator.
    Dense,
    /// Lanczos, except for a problem no larger than its Krylov space (64 vectors, or four times the
    /// modes asked for and a few more), which is solved densely.
    Lanczos,
}

/// Settings of the vibration-mode analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EigenSettings {
    /// Default [`EigenSolver::Auto`].
    pub solver: EigenSolver,
    /// Largest model (free dofs) solved densely by `Auto`. Default 300: above it the Lanczos path is
    /// faster (1270 dofs: 0.03 s against 0.3 s) and as accurate.
    pub dense_limit: usize,
    /// Convergence tolerance of the Lanczos iteration on its Ritz residuals: relative to the operator's
    /// largest eigenvalue `1/ω²` where that exceeds 1 s², absolute below. Default 1e-12.
    pub lanczos_tolerance: f64,
    /// Largest accepted relative residual `‖Kφ − ω²Mφ‖ / ‖Kφ‖` of a mode. Default 1e-6.
    pub residual_tolerance: f64,
    /// The memory (bytes) the analysis may use: a mesh whose [`mode_analysis_bytes`] exceed it is
    /// refused before it is assembled. Default `None`: no limit.
    pub memory_limit: Option<u64>,
}

impl Default for EigenSettings {
    fn default() -> Self {
        Self {
            solver: EigenSolver::Auto,
            dense_limit: 300,
            lanczos_tolerance: 1e-12,
            residual_tolerance: 1e-6,
            memory_limit: None,
        }
    }
}

/// The lowest elastic vibration modes of a supported model.
#[derive(Clone, Debug)]
pub struct VibrationModes {
    /// Eigenvalues ω² (rad²/s²), ascending.
    pub eigenvalues: Vec<f64>,
    /// Natural frequencies f = ω / 2π (Hz).
    pub frequencies_hz: Vec<f64>,
    /// Mode shapes over the free dofs (`n_free × count`), `φᵀ M φ = 1`.
    pub shapes: Mat<f64>,
    /// Number of zero-frequency rigid motions the supports leave (excluded from the modes).
    pub rigid_modes: usize,
    /// The solver that ran.
    pub solver: EigenSolver,
    /// Largest relative residual `‖Kφ − ω²Mφ‖ / ‖Kφ‖` among the modes.
    pub max_residual: f64,
    /// Largest `|ΦᵀMΦ − I|` entry.
    pub max_orthogonality_error: f64,
}

/// The lowest `count` elastic vibration modes of `model`.
pub fn vibration_modes(model: &FeModel, count: usize, settings: &EigenSettings) -> Result<VibrationModes, FemError> {
    check_memory(model, settings)?;
    let prepared = prepare(model)?;
    let mut modes = vibration_modes_of(&prepared.assembled, &prepared.rigid, count, settings)?;
    modes.rigid_modes += prepared.held_massless.len();
    Ok(modes)
}

/// Refuses a mesh whose mode analysis needs more memory than `settings` allow.
pub fn check_memory(model: &FeModel, settings: &EigenSettings) -> Result<(), FemError> {
    let Some(limit) = settings.memory_limit else {
        return Ok(());
    };
    let needed = mode_analysis_bytes(&model.mesh);
    if needed > limit {
        let (elements, nodes) = (model.mesh.elements.len(), model.mesh.nodes.len());
        return Err(FemError::TooLarge { elements, nodes, needed, limit });
    }
    Ok(())
}

/// A model ready for the mode analysis: assembled, with its rigid motions, and with the rigid
/// motions that carry no mass held by extra supports.
#[derive(Clone, Debug)]
pub struct PreparedModel {
    /// The model with the extra supports added.
    pub model: FeModel,
    /// That model assembled.
    pub assembled: AssembledModel,
    /// The rigid motions the supports leave, all with mass (orthonormal columns over the free dofs).
    pub rigid: Mat<f64>,
    /// The dofs held because a rigid motion through them has no mass, as (node, dof).
    pub held_massless: Vec<(usize, Dof)>,
}

/// Assembles `model` and finds its rigid motions. A rigid motion without mass (a straight line of
/// beams without rotary inertia spinning about its axis) has neither a frequency nor a mass to move
/// it; one dof per such motion is held, which leaves every vibration mode unchanged (the modes can be
/// chosen zero there) and makes the shifted stiffness positive definite.
pub fn prepare(model: &FeModel) -> Result<PreparedModel, FemError> {
    prepare_assembled(model, assemble(model)?)
}

/// [`prepare`] of `model` given `free`, the preparation of the same model without supports (or with
/// fewer): where it holds no massless motion and the supports only remove equations, the supported
/// model's matrices are the free model's less the held rows and columns, and the model is not
/// assembled again (a Craig–Bampton reduction needs both).
pub fn prepare_supported(model: &FeModel, free: &PreparedModel) -> Result<PreparedModel, FemError> {
    if free.held_massless.is_empty() {
        if let Some(assembled) = free.assembled.with_supports(model)? {
            return prepare_assembled(model, assembled);
        }
    }
    prepare(model)
}

/// [`prepare`] of `model` assembled as `assembled`.
fn prepare_assembled(model: &FeModel, assembled: AssembledModel) -> Result<PreparedModel, FemError> {
    let rigid = rigid::free_rigid_motions(&model.mesh, &assembled.dofs);
    let massless = rigid::massless_rigid_motions(&assembled.mass, &rigid);
    if massless.ncols() == 0 {
        return Ok(PreparedModel { model: model.clone(), assembled, rigid, held_massless: Vec::new() });
    }
    let held_massless: Vec<(usize, Dof)> =
        rigid::pivot_dofs(&massless).into_iter().filter_map(|e| assembled.dofs.node_dof(e)).collect();
    let mut model = model.clone();
    for &(node, dof) in &held_massless {
        model.supports.push(Support { node, dofs: DofSet::EMPTY.with(dof) });
    }
    let assembled = assemble(&model)?;
    let rigid = rigid::free_rigid_motions(&model.mesh, &assembled.dofs);
    Ok(PreparedModel { model, assembled, rigid, held_massless })
}

/// The lowest `count` elastic vibration modes of an assembled model whose free rigid motions are
/// `rigid` (from [`rigid::free_rigid_motions`]).
pub fn vibration_modes_of(
    assembled: &AssembledModel,
    rigid: &Mat<f64>,
    count: usize,
    settings: &EigenSettings,
) -> Result<VibrationModes, FemError> {
    vibration_modes_and_operator(assembled, rigid, count, settings).map(|(modes, _)| modes)
}

/// [`vibration_modes_of`], and the factored operator it used: `K + σM` with `σ = 0` when the supports
/// leave no rigid motion and `K` is regular, so that static solutions can reuse the factor.
pub fn vibration_modes_and_operator(
    assembled: &AssembledModel,
    rigid: &Mat<f64>,
    count: usize,
    settings: &EigenSettings,
) -> Result<(VibrationModes, ShiftInvert), FemError> {
    let n = assembled.dofs.n_free();
    let available = massive_dofs(assembled).saturating_sub(rigid.ncols());
    if count > available {
        return Err(FemError::TooManyModes { asked: count, available });
    }
    let operator = factor_shifted(assembled, rigid)?;
    let solver = match settings.solver {
        EigenSolver::Auto if n <= settings.dense_limit => EigenSolver::Dense,
        // A problem no larger than the Lanczos method's Krylov space is solved densely, whichever
        // solver was asked for. Its size is the operator's rank, the massive dofs less the rigid
        // motions, which may be less than its dimension (the mass points' motions).
        EigenSolver::Auto | EigenSolver::Lanczos if !lanczos::applies(count, available.min(operator.dim())) => {
            EigenSolver::Dense
        }
        EigenSolver::Auto => EigenSolver::Lanczos,
        chosen => chosen,
    };
    if let (EigenSolver::Dense, Some(limit)) = (solver, settings.memory_limit) {
        let (dimension, needed) = (operator.dim(), dense_eigensolver_bytes(operator.dim()));
        if needed > limit {
            return Err(FemError::DenseTooLarge { dimension, needed, limit });
        }
    }
    let z = match solver {
        EigenSolver::Dense => dense::largest_eigenvectors(&operator, count)?,
        _ => lanczos::largest_eigenvectors(&operator, count, settings.lanczos_tolerance)?,
    };
    let mut shapes = operator.mode_shapes(z.as_ref());
    // K φ and M φ once, for the Rayleigh quotients, the residuals and the M-orthogonality check.
    let mut k_phi = symmetric_times(&assembled.stiffness, shapes.as_ref());
    let mut m_phi = symmetric_times(&assembled.mass, shapes.as_ref());
    let mut eigenvalues = Vec::with_capacity(count);
    for j in 0..shapes.ncols() {
        let k_norm: f64 = (0..n).map(|i| shapes[(i, j)] * k_phi[(i, j)]).sum();
        let m_norm: f64 = (0..n).map(|i| shapes[(i, j)] * m_phi[(i, j)]).sum();
        let scale = 1.0 / m_norm.sqrt();
        for matrix in [&mut shapes, &mut k_phi, &mut m_phi] {
            matrix.col_mut(j).iter_mut().for_each(|x| *x *= scale);
        }
        eigenvalues.push(k_norm / m_norm);
    }
    sort_modes(&mut eigenvalues, [&mut shapes, &mut k_phi, &mut m_phi]);
    check_mechanisms(assembled, &eigenvalues, rigid.ncols())?;
    let max_residual = max_residual(assembled, &eigenvalues, &shapes, (&k_phi, &m_phi));
    if max_residual.1 > settings.residual_tolerance {
        return Err(FemError::EigenResidual { mode: max_residual.0 + 1, residual: max_residual.1, tolerance: settings.residual_tolerance });
    }
    let gram = shapes.transpose() * &m_phi;
    let mut max_orthogonality_error = 0.0_f64;
    for i in 0..count {
        for j in 0..count {
            let target = if i == j { 1.0 } else { 0.0 };
            max_orthogonality_error = max_orthogonality_error.max((gram[(i, j)] - target).abs());
        }
    }
    let frequencies_hz = eigenvalues.iter().map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)).collect();
    let modes = VibrationModes {
        eigenvalues,
        frequencies_hz,
        shapes,
        rigid_modes: rigid.ncols(),
        solver,
        max_residual: max_residual.1,
        max_orthogonality_error,
    };
    Ok((modes, operator))
}

/// Factors `K` (no rigid motions) or `K + σM` with a small shift (rigid motions present, or `K`
/// found singular). A failed factorization with the shift means a mechanism the geometry does not
/// explain.
fn factor_shifted(assembled: &AssembledModel, rigid: &Mat<f64>) -> Result<ShiftInvert, FemError> {
    if rigid.ncols() == 0 {
        if let Ok(op) = ShiftInvert::new(assembled, rigid, 0.0) {
            return Ok(op);
        }
    }
    // The shift only has to make K + σM positive definite in the rigid directions, where σM is the
    // whole matrix; 1e-9 of the stiffness-to-mass scale keeps its pivots far above round-off.
    let shift = 1e-9 * stiffness_to_mass_scale(assembled);
    ShiftInvert::new(assembled, rigid, shift).map_err(|_| FemError::Mechanism { rigid: rigid.ncols() })
}

/// `Σ K_ii / Σ M_ii` over the dofs with mass: the scale of ω² of the mesh's shortest waves.
pub(crate) fn stiffness_to_mass_scale(assembled: &AssembledModel) -> f64 {
    let (mut k, mut m) = (0.0, 0.0);
    for (kd, md) in diagonal(&assembled.stiffness).into_iter().zip(diagonal(&assembled.mass)) {
        if md > 0.0 {
            k += kd;
            m += md;
        }
    }
    if m > 0.0 { k / m } else { 1.0 }
}

fn diagonal(a: &faer::sparse::SparseColMat<usize, f64>) -> Vec<f64> {
    let mut d = vec![0.0; a.ncols()];
    for j in 0..a.ncols() {
        for (i, v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            if i == j {
                d[j] += *v;
            }
        }
    }
    d
}

fn massive_dofs(assembled: &AssembledModel) -> usize {
    diagonal(&assembled.mass).iter().filter(|&&m| m > 0.0).count()
}

/// Sorts the eigenvalues ascending and the columns of `shapes` (and of the matrices whose columns
/// go with them) in the same order.
fn sort_modes<const N: usize>(eigenvalues: &mut [f64], shapes: [&mut Mat<f64>; N]) {
    let mut order: Vec<usize> = (0..eigenvalues.len()).collect();
    order.sort_by(|&a, &b| eigenvalues[a].total_cmp(&eigenvalues[b]));
    let sorted_values: Vec<f64> = order.iter().map(|&k| eigenvalues[k]).collect();
    eigenvalues.copy_from_slice(&sorted_values);
    for matrix in shapes {
        *matrix = Mat::from_fn(matrix.nrows(), matrix.ncols(), |i, j| matrix[(i, order[j])]);
    }
}

/// A zero eigenvalue among the elastic modes is a mechanism the supports and the geometry do not
/// explain (a disconnected part, a hinge in the mesh).
fn check_mechanisms(assembled: &AssembledModel, eigenvalues: &[f64], rigid: usize) -> Result<(), FemError> {
    let scale = stiffness_to_mass_scale(assembled);
    if eigenvalues.first().is_some_and(|&l| l < 1e-12 * scale) {
        return Err(FemError::Mechanism { rigid });
    }
    Ok(())
}

/// (mode index, largest relative residual `‖Kφ − λMφ‖ / ‖Kφ‖`).
/// The mode with the largest relative residual `‖K φ − λ M φ‖ / ‖K φ‖`, and that residual, less what
/// rounding explains: computing `K φ − λ M φ` in floating point leaves about `ε ‖|K| |φ|‖ + ε |λ|
/// ‖|M| |φ|‖` by itself, which exceeds the tolerance for a mode much softer than the stiffest
/// element (a shell's drilling rotation, a near-mechanism), however exact the mode.
/// `K φ` and `M φ` are given (`products`).
fn max_residual(assembled: &AssembledModel, eigenvalues: &[f64], shapes: &Mat<f64>, (k_phi, m_phi): (&Mat<f64>, &Mat<f64>)) -> (usize, f64) {
    let (k_rounding, m_rounding) = (absolute_product_norms(&assembled.stiffness, shapes), absolute_product_norms(&assembled.mass, shapes));
    let mut worst = (0, 0.0_f64);
    for (j, lambda) in eigenvalues.iter().enumerate() {
        let mut residual = 0.0_f64;
        let mut norm = 0.0_f64;
        for i in 0..shapes.nrows() {
            residual += (k_phi[(i, j)] - lambda * m_phi[(i, j)]).powi(2);
            norm += k_phi[(i, j)].powi(2);
        }
        let rounding = ROUNDING_FACTOR
            * f64::EPSILON
            * (k_rounding[j] + lambda.abs() * m_rounding[j]);
        let relative = (residual.sqrt() - rounding).max(0.0) / norm.sqrt().max(f64::MIN_POSITIVE);
        if relative > worst.1 {
            worst = (j, relative);
        }
    }
    worst
}

/// How many unit roundoffs of `‖|A| |φ|‖` a residual may hold from rounding alone: a margin over the
/// few terms per row of an FE matrix and the rounding of `φ` itself.
const ROUNDING_FACTOR: f64 = 16.0;

/// `‖|A| |φ_j|‖` of every column `j`, the size of the terms that the product `A φ_j` sums (one pass
/// over `A` for all the columns).
fn absolute_product_norms(a: &faer::sparse::SparseColMat<usize, f64>, shapes: &Mat<f64>) -> Vec<f64> {
    let (col_ptr, row_idx, values) = (a.col_ptr(), a.row_idx(), a.val());
    let count = shapes.ncols();
    let mut sum = vec![0.0; a.nrows() * count];
    let mut x = vec![0.0; count];
    for col in 0..a.ncols() {
        x.iter_mut().enumerate().for_each(|(j, x)| *x = shapes[(col, j)].abs());
        for k in col_ptr[col]..col_ptr[col + 1] {
            let (row, v) = (row_idx[k], values[k].abs());
            sum[row * count..(row + 1) * count].iter_mut().zip(&x).for_each(|(s, x)| *s += v * x);
        }
    }
    (0..count).map(|j| (0..a.nrows()).map(|row| sum[row * count + j].powi(2)).sum::<f64>().sqrt()).collect()
}
