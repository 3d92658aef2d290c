//! The membrane (in-plane) stiffness of the flat shell, in the local degrees of freedom `u v` of
//! each node.
//!
//! - **Triangle:** the constant-strain triangle (Turner, Clough, Martin & Topp 1956).
//! - **Quadrilateral:** the bilinear isoparametric element with Taylor's incompatible modes, QM6
//!   (Taylor, Beresford & Wilson, "A non-conforming element for stress analysis", IJNME 10, 1976,
//!   1211–1219): the displacement gets the bubble modes (1 − ξ²) and (1 − η²) in u and in v, whose
//!   strains are formed with the Jacobian at the centre and scaled by det J₀ / det J, so that they
//!   integrate to zero over any element and the patch test is passed; the four extra parameters
//!   are condensed out. On rectangles QM6 represents pure in-plane bending exactly, where the plain
//!   bilinear element locks in shear.
//!
//! Both use the plane-stress elasticity of an isotropic material.

use nalgebra::{Matrix3, SMatrix, Vector2};

use super::bilinear;
use crate::element::ElementError;

/// `scale` · E / (1 − ν²) [1 ν 0; ν 1 0; 0 0 (1 − ν)/2], the plane-stress elasticity times `scale`
/// (t for membrane forces, t³/12 for bending moments).
pub(super) fn plane_stress(youngs_modulus: f64, poisson_ratio: f64, scale: f64) -> Matrix3<f64> {
    let nu = poisson_ratio;
    let c = scale * youngs_modulus / (1.0 - nu * nu);
    Matrix3::new(
        c,
        c * nu,
        0.0,
        c * nu,
        c,
        0.0,
        0.0,
        0.0,
        c * 0.5 * (1.0 - nu),
    )
}

/// The constant-strain triangle, `(u₁ v₁ u₂ v₂ u₃ v₃)`, for membrane elasticity `d` (forces per
/// unit strain, i.e. t times the plane-stress matrix).
pub(super) fn constant_strain_triangle(
    xy: &[Vector2<f64>],
    d: &Matrix3<f64>,
) -> SMatrix<f64, 6, 6> {
    let (gradients, area) = triangle_gradients(xy);
    let mut b = SMatrix::<f64, 3, 6>::zeros();
    for (i, g) in gradients.iter().enumerate() {
        b[(0, 2 * i)] = g.x;
        b[(1, 2 * i + 1)] = g.y;
        b[(2, 2 * i)] = g.y;
        b[(2, 2 * i + 1)] = g.x;
    }
    b.transpose() * d * b * area
}

/// The (constant) gradients of the linear shape functions of a triangle and its area.
pub(super) fn triangle_gradients(xy: &[Vector2<f64>]) -> ([Vector2<f64>; 3], f64) {
    let twice_area = (xy[1] - xy[0]).perp(&(xy[2] - xy[0]));
    // ∂Nᵢ/∂x = (y_j − y_k) / 2A, ∂Nᵢ/∂y = (x_k − x_j) / 2A for (i, j, k) cyclic.
    let gradient = |i: usize| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        Vector2::new(xy[j].y - xy[k].y, xy[k].x - xy[j].x) / twice_area
    };
    ([gradient(0), gradient(1), gradient(2)], 0.5 * twice_area)
}

/// Taylor's QM6 quadrilateral, `(u₁ v₁ … u₄ v₄)`, for membrane elasticity `d`.
pub(super) fn qm6(
    xy: &[Vector2<f64>],
    d: &Matrix3<f64>,
) -> Result<SMatrix<f64, 8, 8>, ElementError> {
    let j0 = bilinear::jacobian(xy, 0.0, 0.0);
    let det0 = j0.determinant();
    let j0_inverse = j0.try_inverse().ok_or(ElementError::DegenerateShape)?;
    let mut k_cc = SMatrix::<f64, 8, 8>::zeros();
    let mut k_ci = SMatrix::<f64, 8, 4>::zeros();
    let mut k_ii = SMatrix::<f64, 4, 4>::zeros();
    for [xi, eta] in bilinear::gauss_points() {
        let (n, det) = bilinear::cartesian_derivatives(xy, xi, eta);
        let mut b_c = SMatrix::<f64, 3, 8>::zeros();
        for i in 0..4 {
            b_c[(0, 2 * i)] = n[0][i];
            b_c[(1, 2 * i + 1)] = n[1][i];
            b_c[(2, 2 * i)] = n[1][i];
            b_c[(2, 2 * i + 1)] = n[0][i];
        }
        // Incompatible modes P₁ = 1 − ξ², P₂ = 1 − η², with Taylor's derivatives
        // J₀⁻¹ ∂P/∂ξ · det J₀ / det J.
        let scale = det0 / det;
        let p = [
            j0_inverse * Vector2::new(-2.0 * xi, 0.0) * scale,
            j0_inverse * Vector2::new(0.0, -2.0 * eta) * scale,
        ];
        // Columns: u with P₁, u with P₂, v with P₁, v with P₂.
        let mut b_i = SMatrix::<f64, 3, 4>::zeros();
        for (m, g) in p.iter().enumerate() {
            b_i[(0, m)] = g.x;
            b_i[(2, m)] = g.y;
            b_i[(1, 2 + m)] = g.y;
            b_i[(2, 2 + m)] = g.x;
        }
        let db_i = d * b_i * det;
        k_cc += b_c.transpose() * d * b_c * det;
        k_ci += b_c.transpose() * db_i;
        k_ii += b_i.transpose() * db_i;
    }
    let k_ii_inverse = k_ii
        .cholesky()
        .ok_or(ElementError::DegenerateShape)?
        .inverse();
    Ok(k_cc - k_ci * k_ii_inverse * k_ci.transpose())
}
