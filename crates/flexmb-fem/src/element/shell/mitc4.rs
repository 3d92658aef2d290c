//! The bending and transverse shear stiffness of the quadrilateral: MITC4 (Bathe & Dvorkin, "A
//! four-node plate bending element based on Mindlin/Reissner plate theory and a mixed
//! interpolation", IJNME 21, 1985, 367–383).
//!
//! Mindlin–Reissner plate: w and the rotations βx, βy of the normal (u = z βx, v = z βy through the
//! thickness) are interpolated bilinearly and independently. For a positive w along local z and
//! rotations θ about the local axes, u = z θy and v = −z θx, so βx = θy and βy = −θx.
//!
//! - Bending: ½ ∫ κᵀ D_b κ dA, κ = [∂βx/∂x, ∂βy/∂y, ∂βx/∂y + ∂βy/∂x], 2 × 2 Gauss.
//! - Transverse shear, γ = β + ∇w, with energy ½ ∫ k G t γᵀγ dA, k = 5/6: not from the
//!   displacements, which lock for thin plates, but from the assumed covariant strains
//!   γ̃_ξ = ½(1 − η) γ_ξ(0, −1) + ½(1 + η) γ_ξ(0, 1) and
//!   γ̃_η = ½(1 − ξ) γ_η(−1, 0) + ½(1 + ξ) γ_η(1, 0), tied to the displacement-based covariant
//!   strains γ_ξ = γ · ∂x/∂ξ, γ_η = γ · ∂x/∂η at the midsides; the Cartesian strains are
//!   γ = J⁻¹ [γ̃_ξ; γ̃_η], and the energy is integrated by 2 × 2 Gauss.
//!
//! Along each side the tied strain is the mean of γ along that side, which is zero for any w with
//! a linear tangential derivative and Kirchhoff rotations: the element is free of shear locking,
//! has no spurious zero-energy modes, and passes the constant-curvature patch test on distorted
//! meshes.

use nalgebra::{Matrix2, Matrix3, SMatrix, Vector2};

use super::bilinear;

/// The shear correction factor of a homogeneous plate.
pub(super) const SHEAR_CORRECTION: f64 = 5.0 / 6.0;

/// The MITC4 stiffness, degrees of freedom `(w θx θy)` of each node (θ about the local axes), for
/// bending elasticity `d_b` (moments per unit curvature) and shear stiffness `shear` = k G t.
pub(super) fn mitc4(xy: &[Vector2<f64>], d_b: &Matrix3<f64>, shear: f64) -> SMatrix<f64, 12, 12> {
    // Displacement-based covariant shear strains at the tying points: γ_ξ at (0, ∓1) (sides 1–2 and
    // 4–3), γ_η at (∓1, 0) (sides 1–4 and 2–3).
    let xi_bottom = covariant_shear(xy, 0.0, -1.0)[0];
    let xi_top = covariant_shear(xy, 0.0, 1.0)[0];
    let eta_left = covariant_shear(xy, -1.0, 0.0)[1];
    let eta_right = covariant_shear(xy, 1.0, 0.0)[1];

    let mut k = SMatrix::<f64, 12, 12>::zeros();
    for [xi, eta] in bilinear::gauss_points() {
        let (n, det) = bilinear::cartesian_derivatives(xy, xi, eta);
        let mut b_b = SMatrix::<f64, 3, 12>::zeros();
        for i in 0..4 {
            // βx = θy (column 3i + 2), βy = −θx (column 3i + 1).
            b_b[(0, 3 * i + 2)] = n[0][i];
            b_b[(1, 3 * i + 1)] = -n[1][i];
            b_b[(2, 3 * i + 2)] = n[1][i];
            b_b[(2, 3 * i + 1)] = -n[0][i];
        }
        k += b_b.transpose() * d_b * b_b * det;

        let assumed_xi = xi_bottom * (0.5 * (1.0 - eta)) + xi_top * (0.5 * (1.0 + eta));
        let assumed_eta = eta_left * (0.5 * (1.0 - xi)) + eta_right * (0.5 * (1.0 + xi));
        let j = bilinear::jacobian(xy, xi, eta);
        let j_inverse = Matrix2::new(j[(1, 1)], -j[(0, 1)], -j[(1, 0)], j[(0, 0)]) / det;
        let mut b_s = SMatrix::<f64, 2, 12>::zeros();
        for c in 0..12 {
            let g = j_inverse * Vector2::new(assumed_xi[c], assumed_eta[c]);
            b_s[(0, c)] = g.x;
            b_s[(1, c)] = g.y;
        }
        k += b_s.transpose() * b_s * (shear * det);
    }
    k
}

/// The displacement-based covariant transverse shear strains γ_ξ, γ_η at (ξ, η) as rows over the
/// twelve degrees of freedom: γ_ξ = ∂w/∂ξ + βx x_ξ + βy y_ξ, and likewise for η.
fn covariant_shear(xy: &[Vector2<f64>], xi: f64, eta: f64) -> [SMatrix<f64, 1, 12>; 2] {
    let n = bilinear::shape(xi, eta);
    let dn = bilinear::natural_derivatives(xi, eta);
    let j = bilinear::jacobian(xy, xi, eta);
    let mut rows = [SMatrix::<f64, 1, 12>::zeros(); 2];
    for (r, row) in rows.iter_mut().enumerate() {
        let (x_r, y_r) = (j[(r, 0)], j[(r, 1)]);
        for i in 0..4 {
            row[3 * i] = dn[r][i];
            row[3 * i + 2] = n[i] * x_r;
            row[3 * i + 1] = -n[i] * y_r;
        }
    }
    rows
}
