//! Mass points: the mass of a body as point masses (with rotary inertia) that move with the FE
//! displacement field. The mass matrix, its square-root factor, the inertia invariants and the mass
//! properties are all sums over mass points, so the lumped and the consistent mass differ only in
//! where the points are:
//!
//! - **lumped** (the seed's): one point at each node, moving with that node (the interpolation is
//!   the identity);
//! - **consistent**: the Gauss points of each element, moving with the element's displacement
//!   field. With a rule exact for the product of two shape functions (4 points on a beam's cubics,
//!   2 × 2 on a quadrilateral, 3 on a triangle), `Σ m_g N_gᵀ N_g = ∫ ρ Nᵀ N`, the consistent mass
//!   matrix, and the invariants are the exact integrals of formulation.md §3 over that field.
//!
//! A point's translation `u_g` and rotation `θ_g` (body frame) are `[u_g; θ_g] = Σₐ G_{g,a} d_a` over
//! the element's nodes a with their six nodal degrees of freedom `d_a = [u_a; θ_a]`.

use nalgebra::{Matrix3, Matrix6, Vector3};

/// A point mass with rotary inertia, moving with the displacement field of the nodes it
/// interpolates.
#[derive(Clone, Debug, PartialEq)]
pub struct MassPoint {
    /// Undeformed position in the body frame (m).
    pub position: Vector3<f64>,
    /// Mass (kg).
    pub mass: f64,
    /// Rotary inertia about the point, body axes (kg m²), symmetric positive semi-definite.
    pub rotary_inertia: Matrix3<f64>,
    /// For each node the point moves with (an element-local index in [`ElementMatrices`], a mesh
    /// node index after assembly), the 6 × 6 block `G` from the node's `ux uy uz rx ry rz` to the
    /// point's translation (rows 0–2) and rotation (rows 3–5), body frame.
    ///
    /// [`ElementMatrices`]: super::ElementMatrices
    pub interpolation: Vec<(usize, Matrix6<f64>)>,
}

impl MassPoint {
    /// A point at node `node` that moves with it (a lumped mass).
    pub fn at_node(node: usize, position: Vector3<f64>, mass: f64, rotary_inertia: Matrix3<f64>) -> MassPoint {
        MassPoint { position, mass, rotary_inertia, interpolation: vec![(node, Matrix6::identity())] }
    }

    /// The mass matrix of the point, `diag(m I, J)`, over its translation and rotation.
    pub fn inertia_block(&self) -> Matrix6<f64> {
        let mut d = Matrix6::zeros();
        d.fixed_view_mut::<3, 3>(0, 0).copy_from(&(Matrix3::identity() * self.mass));
        d.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.rotary_inertia);
        d
    }

    /// The rows of a square-root factor `F` of the point's mass, `Fᵀ F = diag(m I, J)`: `√m I` on the
    /// translations when the mass is positive, `J^{1/2}` on the rotations when `J` is not zero.
    /// Rows are 6-vectors over the point's translation and rotation.
    pub fn inertia_root_rows(&self) -> Vec<[f64; 6]> {
        let mut rows = Vec::with_capacity(6);
        if self.mass > 0.0 {
            let root = self.mass.sqrt();
            for k in 0..3 {
                let mut row = [0.0; 6];
                row[k] = root;
                rows.push(row);
            }
        }
        if self.rotary_inertia != Matrix3::zeros() {
            let eigen = nalgebra::SymmetricEigen::new(self.rotary_inertia);
            let roots = eigen.eigenvalues.map(|v| v.max(0.0).sqrt());
            let root = eigen.eigenvectors * Matrix3::from_diagonal(&roots) * eigen.eigenvectors.transpose();
            for r in 0..3 {
                let mut row = [0.0; 6];
                for c in 0..3 {
                    row[3 + c] = root[(r, c)];
                }
                rows.push(row);
            }
        }
        rows
    }
}

/// The nodes and weights of Gauss–Legendre quadrature with 4 points on [0, 1] (exact to degree 7).
pub(crate) fn gauss_legendre_4() -> [(f64, f64); 4] {
    let a = (3.0 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
    let b = (3.0 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
    let wa = (18.0 + 30f64.sqrt()) / 36.0;
    let wb = (18.0 - 30f64.sqrt()) / 36.0;
    [(-b, wb), (-a, wa), (a, wa), (b, wb)].map(|(x, w)| (0.5 * (1.0 + x), 0.5 * w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_degree_seven_exactly() {
        for degree in 0..=7 {
            let sum: f64 = gauss_legendre_4().iter().map(|(x, w)| w * x.powi(degree)).sum();
            assert!((sum - 1.0 / (degree as f64 + 1.0)).abs() < 1e-15, "degree {degree}: {sum}");
        }
    }

    #[test]
    fn root_rows_factor_the_point_inertia() {
        let j = Matrix3::new(2.0, 0.3, 0.1, 0.3, 1.5, -0.2, 0.1, -0.2, 1.0);
        let point = MassPoint::at_node(0, Vector3::zeros(), 3.0, j);
        let rows = point.inertia_root_rows();
        let mut product = Matrix6::zeros();
        for row in &rows {
            for a in 0..6 {
                for b in 0..6 {
                    product[(a, b)] += row[a] * row[b];
                }
            }
        }
        assert!((product - point.inertia_block()).norm() < 1e-14);
        let massless = MassPoint::at_node(0, Vector3::zeros(), 0.0, Matrix3::zeros());
        assert!(massless.inertia_root_rows().is_empty());
    }
}
