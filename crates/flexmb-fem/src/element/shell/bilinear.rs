//! The bilinear quadrilateral: shape functions in the natural coordinates ξ, η ∈ [−1, 1], the
//! Jacobian of the map to the element plane, and the 2 × 2 Gauss rule.
//!
//! Node i sits at (ξᵢ, ηᵢ) = (−1, −1), (1, −1), (1, 1), (−1, 1) and has the shape function
//! Nᵢ = ¼ (1 + ξᵢ ξ)(1 + ηᵢ η). The Jacobian is J = [x_ξ y_ξ; x_η y_η], so that
//! [∂/∂x; ∂/∂y] = J⁻¹ [∂/∂ξ; ∂/∂η].

use nalgebra::{Matrix2, Vector2};

/// The natural coordinates of the nodes.
pub(super) const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// The points of the 2 × 2 Gauss rule, whose weights are all 1.
pub(super) fn gauss_points() -> [[f64; 2]; 4] {
    let g = 1.0 / 3f64.sqrt();
    [[-g, -g], [g, -g], [g, g], [-g, g]]
}

/// The shape functions at (ξ, η).
pub(super) fn shape(xi: f64, eta: f64) -> [f64; 4] {
    CORNERS.map(|[a, b]| 0.25 * (1.0 + a * xi) * (1.0 + b * eta))
}

/// The derivatives of the shape functions with respect to ξ (first row) and η (second row).
pub(super) fn natural_derivatives(xi: f64, eta: f64) -> [[f64; 4]; 2] {
    [
        CORNERS.map(|[a, b]| 0.25 * a * (1.0 + b * eta)),
        CORNERS.map(|[a, b]| 0.25 * b * (1.0 + a * xi)),
    ]
}

/// The Jacobian J = [x_ξ y_ξ; x_η y_η] at (ξ, η) of the element with nodes `xy`.
pub(super) fn jacobian(xy: &[Vector2<f64>], xi: f64, eta: f64) -> Matrix2<f64> {
    let d = natural_derivatives(xi, eta);
    let mut j = Matrix2::zeros();
    for (i, p) in xy.iter().enumerate() {
        for r in 0..2 {
            j[(r, 0)] += d[r][i] * p.x;
            j[(r, 1)] += d[r][i] * p.y;
        }
    }
    j
}

/// The derivatives of the shape functions with respect to x (first row) and y (second row) at
/// (ξ, η), and det J there.
pub(super) fn cartesian_derivatives(
    xy: &[Vector2<f64>],
    xi: f64,
    eta: f64,
) -> ([[f64; 4]; 2], f64) {
    let j = jacobian(xy, xi, eta);
    let det = j.determinant();
    let inverse = Matrix2::new(j[(1, 1)], -j[(0, 1)], -j[(1, 0)], j[(0, 0)]) / det;
    let d = natural_derivatives(xi, eta);
    let mut out = [[0.0; 4]; 2];
    for i in 0..4 {
        let g = inverse * Vector2::new(d[0][i], d[1][i]);
        out[0][i] = g.x;
        out[1][i] = g.y;
    }
    (out, det)
}
