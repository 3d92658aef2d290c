//! What the isoparametric solid elements share: the map from natural to body coordinates, its
//! Jacobian and the check that it is positive, the Cartesian gradients of the shape functions, the
//! stiffness `∫ Bᵀ D B dV` of an isotropic material and the mass points `∫ ρ Nᵀ N dV` of the
//! consistent mass, both by quadrature.
//!
//! Body coordinates `x(ξ) = Σₐ Nₐ(ξ) xₐ`; the Jacobian `J = ∂x/∂ξ` (columns: the natural directions);
//! Cartesian gradients `∇Nₐ = J⁻ᵀ ∂Nₐ/∂ξ`; the volume element `dV = det J dξ`.

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};

use super::quadrature::IntegrationPoint;
use crate::element::{ElementError, MassPoint};

/// Values and natural derivatives `∂N/∂ξ, ∂N/∂η, ∂N/∂ζ` of an element's shape functions at a point.
#[derive(Clone, Debug)]
pub(super) struct ShapeFunctions {
    /// `Nₐ`, one per node.
    pub values: Vec<f64>,
    /// `∂Nₐ/∂(ξ, η, ζ)`, one per node.
    pub derivatives: Vec<Vector3<f64>>,
}

/// The shape functions of an element family at natural coordinates `ξ η ζ`.
pub(super) type ShapeFunctionsAt = fn([f64; 3]) -> ShapeFunctions;

/// The Jacobian `J = ∂x/∂ξ = Σₐ xₐ (∂Nₐ/∂ξ)ᵀ` at the point where `shape` was evaluated.
pub(super) fn jacobian(points: &[Vector3<f64>], shape: &ShapeFunctions) -> Matrix3<f64> {
    points.iter().zip(&shape.derivatives).map(|(x, d)| x * d.transpose()).sum()
}

/// The size of an element: the largest extent of its nodes along the body axes.
fn size(points: &[Vector3<f64>]) -> f64 {
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (hi - lo).max()
}

/// `det J` at `natural`, checked: an element whose Jacobian determinant is not positive there (nodes
/// out of order: an inverted element; or collapsed nodes) is refused. `reference_volume` is the
/// volume of the reference shape (8 for the brick); the determinant is compared with 1e-10 of
/// `size³ / reference_volume`.
pub(super) fn checked_determinant(
    points: &[Vector3<f64>],
    shape: &ShapeFunctions,
    natural: [f64; 3],
    reference_volume: f64,
) -> Result<(Matrix3<f64>, f64), ElementError> {
    let j = jacobian(points, shape);
    let det = j.determinant();
    let scale = size(points).powi(3) / reference_volume;
    if det.is_nan() || det <= 1e-10 * scale {
        return Err(ElementError::InvertedSolid { determinant: det, relative: det / scale, at: natural });
    }
    Ok((j, det))
}

/// The Cartesian gradients `J⁻ᵀ ∂Nₐ/∂ξ` of natural derivatives `derivatives`.
pub(super) fn cartesian_gradients(j: &Matrix3<f64>, derivatives: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let inverse_transpose = j.try_inverse().unwrap_or_else(Matrix3::zeros).transpose();
    derivatives.iter().map(|d| inverse_transpose * d).collect()
}

/// Lamé's constants `λ = E ν / ((1 + ν)(1 − 2ν))` and `μ = G = E / (2 (1 + ν))`.
pub(super) fn lame(youngs_modulus: f64, poisson_ratio: f64) -> (f64, f64) {
    let mu = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
    let lambda = youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
    (lambda, mu)
}

/// Adds `weight · Bᵀ D B` of an isotropic material for Cartesian gradients `gradients` (one per
/// displacement field: the nodes, and for the incompatible-mode brick its bubble modes) to `k`
/// (`3 m × 3 m`, translations of field a at rows `3a..3a+3`). With `Bₐ` the strain of field a
/// (εxx εyy εzz γxy γyz γzx) and D isotropic, the 3 × 3 block is
/// `K_ab,ij = λ ∂ᵢNₐ ∂ⱼN_b + μ (∂ⱼNₐ ∂ᵢN_b + δᵢⱼ ∇Nₐ·∇N_b)`.
pub(super) fn add_stiffness(k: &mut DMatrix<f64>, gradients: &[Vector3<f64>], lambda: f64, mu: f64, weight: f64) {
    for (a, ga) in gradients.iter().enumerate() {
        for (b, gb) in gradients.iter().enumerate() {
            let dot = ga.dot(gb);
            for i in 0..3 {
                for j in 0..3 {
                    let mut value = lambda * ga[i] * gb[j] + mu * ga[j] * gb[i];
                    if i == j {
                        value += mu * dot;
                    }
                    k[(3 * a + i, 3 * b + j)] += weight * value;
                }
            }
        }
    }
}

/// The stiffness `∫ Bᵀ D B dV` (3n × 3n, translations node by node) of an element whose nodes are at
/// `points`, by the quadrature `rule`.
pub(super) fn stiffness(
    points: &[Vector3<f64>],
    shape_at: ShapeFunctionsAt,
    rule: &[IntegrationPoint],
    reference_volume: f64,
    (lambda, mu): (f64, f64),
) -> Result<DMatrix<f64>, ElementError> {
    let n = points.len();
    let mut k = DMatrix::zeros(3 * n, 3 * n);
    for point in rule {
        let shape = shape_at(point.natural);
        let (j, det) = checked_determinant(points, &shape, point.natural, reference_volume)?;
        add_stiffness(&mut k, &cartesian_gradients(&j, &shape.derivatives), lambda, mu, point.weight * det);
    }
    Ok(k)
}

/// The mass points of the consistent mass: at each point of `rule`, the mass `ρ w det J` moving with
/// the displacement interpolated by the shape functions there (`Nₐ I` on node a's translations,
/// nothing on its rotations). `Σ_g m_g N_gᵀ N_g` is then `∫ ρ Nᵀ N dV` by that rule.
pub(super) fn mass_points(
    points: &[Vector3<f64>],
    shape_at: ShapeFunctionsAt,
    rule: &[IntegrationPoint],
    reference_volume: f64,
    density: f64,
) -> Result<Vec<MassPoint>, ElementError> {
    rule.iter()
        .map(|point| {
            let shape = shape_at(point.natural);
            let (_, det) = checked_determinant(points, &shape, point.natural, reference_volume)?;
            let interpolation = shape
                .values
                .iter()
                .enumerate()
                .map(|(a, &value)| {
                    let mut block = Matrix6::zeros();
                    block.fixed_view_mut::<3, 3>(0, 0).copy_from(&(Matrix3::identity() * value));
                    (a, block)
                })
                .collect();
            Ok(MassPoint {
                position: points.iter().zip(&shape.values).map(|(x, n)| *n * x).sum(),
                mass: density * point.weight * det,
                rotary_inertia: Matrix3::zeros(),
                interpolation,
            })
        })
        .collect()
}
