//! The bending stiffness of the triangle: the discrete Kirchhoff triangle, DKT (Batoz, Bathe & Ho,
//! "A study of three-node triangular plate bending elements", IJNME 15, 1980, 1771–1812).
//!
//! The rotations βx, βy of the normal (u = z βx, v = z βy through the thickness) are quadratic over
//! the triangle; their midside values are eliminated by imposing the Kirchhoff hypothesis
//! (γ = β + ∇w = 0) at the corners and, integrated along each side with w cubic and the tangential
//! rotation linear, at the side midpoints, and by taking the normal rotation linear along each side.
//! What remains is βx = Hxᵀ U, βy = Hyᵀ U in the corner values U = (w, θx, θy) of each node, with
//! θx = ∂w/∂y and θy = −∂w/∂x at the corners (the functions Hx, Hy of BBH 1980, built from
//! the side coefficients a, b, c, d, e). Transverse shear energy is neglected (thin
//! plates); the bending energy ½ ∫ κᵀ D_b κ dA with κ = [∂βx/∂x, ∂βy/∂y, ∂βx/∂y + ∂βy/∂x] is
//! integrated exactly by the 3-point midside rule (κ is linear).
//!
//! The element passes the constant-curvature patch test on any triangle mesh.

use nalgebra::{Matrix2, Matrix3, SMatrix, Vector2};

/// The DKT bending stiffness, degrees of freedom `(w θx θy)` of each node, local rotations (θx
/// about local x, θy about local y), for bending elasticity `d_b` (moments per unit curvature).
pub(super) fn dkt(xy: &[Vector2<f64>], d_b: &Matrix3<f64>) -> SMatrix<f64, 9, 9> {
    let shape = DktShape::new(xy);
    let area = 0.5 * (xy[1] - xy[0]).perp(&(xy[2] - xy[0]));
    let mut k = SMatrix::<f64, 9, 9>::zeros();
    for [xi, eta] in [[0.5, 0.0], [0.5, 0.5], [0.0, 0.5]] {
        let b = shape.curvature(xi, eta);
        k += b.transpose() * d_b * b * (area / 3.0);
    }
    k
}

/// The side coefficients of the DKT's rotation functions and the inverse Jacobian of the triangle.
pub(super) struct DktShape {
    /// a, b, c, d, e of BBH 1980 for the sides 4 = 2–3, 5 = 3–1, 6 = 1–2 (indices 0, 1, 2).
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    d: [f64; 3],
    e: [f64; 3],
    /// J⁻¹ of the map from (ξ, η) (area coordinates L₂, L₃) to (x, y).
    jacobian_inverse: Matrix2<f64>,
}

impl DktShape {
    pub(super) fn new(xy: &[Vector2<f64>]) -> Self {
        let (mut a, mut b, mut c, mut d, mut e) =
            ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        for (s, (i, j)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
            let (x, y) = (xy[i].x - xy[j].x, xy[i].y - xy[j].y);
            let l2 = x * x + y * y;
            a[s] = -x / l2;
            b[s] = 0.75 * x * y / l2;
            c[s] = (0.25 * x * x - 0.5 * y * y) / l2;
            d[s] = -y / l2;
            e[s] = (0.25 * y * y - 0.5 * x * x) / l2;
        }
        let (x21, y21) = (xy[1].x - xy[0].x, xy[1].y - xy[0].y);
        let (x31, y31) = (xy[2].x - xy[0].x, xy[2].y - xy[0].y);
        let jacobian = Matrix2::new(x21, y21, x31, y31);
        let det = jacobian.determinant();
        let jacobian_inverse = Matrix2::new(y31, -y21, -x31, x21) / det;
        Self {
            a,
            b,
            c,
            d,
            e,
            jacobian_inverse,
        }
    }

    /// Hx and Hy (BBH 1980) for the values (or derivatives) `n` of the six quadratic shape functions
    /// N₁ … N₆ (corners 1, 2, 3, then the midsides of 2–3, 3–1, 1–2); H is linear in them.
    fn h(&self, n: &[f64; 6]) -> ([f64; 9], [f64; 9]) {
        let (a, b, c, d, e) = (&self.a, &self.b, &self.c, &self.d, &self.e);
        let (n1, n2, n3, n4, n5, n6) = (n[0], n[1], n[2], n[3], n[4], n[5]);
        let hx = [
            1.5 * (a[2] * n6 - a[1] * n5),
            b[1] * n5 + b[2] * n6,
            n1 - c[1] * n5 - c[2] * n6,
            1.5 * (a[0] * n4 - a[2] * n6),
            b[2] * n6 + b[0] * n4,
            n2 - c[2] * n6 - c[0] * n4,
            1.5 * (a[1] * n5 - a[0] * n4),
            b[0] * n4 + b[1] * n5,
            n3 - c[0] * n4 - c[1] * n5,
        ];
        let hy = [
            1.5 * (d[2] * n6 - d[1] * n5),
            -n1 + e[1] * n5 + e[2] * n6,
            -b[1] * n5 - b[2] * n6,
            1.5 * (d[0] * n4 - d[2] * n6),
            -n2 + e[2] * n6 + e[0] * n4,
            -b[2] * n6 - b[0] * n4,
            1.5 * (d[1] * n5 - d[0] * n4),
            -n3 + e[0] * n4 + e[1] * n5,
            -b[0] * n4 - b[1] * n5,
        ];
        (hx, hy)
    }

    /// The rotations (βx, βy) at (ξ, η) as rows over the nine degrees of freedom.
    #[cfg(test)]
    pub(super) fn rotations(&self, xi: f64, eta: f64) -> SMatrix<f64, 2, 9> {
        let (l1, l2, l3) = (1.0 - xi - eta, xi, eta);
        let n = [
            l1 * (2.0 * l1 - 1.0),
            l2 * (2.0 * l2 - 1.0),
            l3 * (2.0 * l3 - 1.0),
            4.0 * l2 * l3,
            4.0 * l3 * l1,
            4.0 * l1 * l2,
        ];
        let (hx, hy) = self.h(&n);
        SMatrix::<f64, 2, 9>::from_fn(|r, c| if r == 0 { hx[c] } else { hy[c] })
    }

    /// The curvature matrix B at (ξ, η): κ = B U.
    pub(super) fn curvature(&self, xi: f64, eta: f64) -> SMatrix<f64, 3, 9> {
        let (l1, l2, l3) = (1.0 - xi - eta, xi, eta);
        // ∂N/∂ξ and ∂N/∂η with L₁ = 1 − ξ − η, L₂ = ξ, L₃ = η.
        let n_xi = [
            1.0 - 4.0 * l1,
            4.0 * l2 - 1.0,
            0.0,
            4.0 * l3,
            -4.0 * l3,
            4.0 * (l1 - l2),
        ];
        let n_eta = [
            1.0 - 4.0 * l1,
            0.0,
            4.0 * l3 - 1.0,
            4.0 * l2,
            4.0 * (l1 - l3),
            -4.0 * l2,
        ];
        let (hx_xi, hy_xi) = self.h(&n_xi);
        let (hx_eta, hy_eta) = self.h(&n_eta);
        let j = &self.jacobian_inverse;
        let mut b = SMatrix::<f64, 3, 9>::zeros();
        for k in 0..9 {
            let hx_x = j[(0, 0)] * hx_xi[k] + j[(0, 1)] * hx_eta[k];
            let hx_y = j[(1, 0)] * hx_xi[k] + j[(1, 1)] * hx_eta[k];
            let hy_x = j[(0, 0)] * hy_xi[k] + j[(0, 1)] * hy_eta[k];
            let hy_y = j[(1, 0)] * hy_xi[k] + j[(1, 1)] * hy_eta[k];
            b[(0, k)] = hx_x;
            b[(1, k)] = hy_y;
            b[(2, k)] = hx_y + hy_x;
        }
        b
    }
}
