//! Stress recovery of the flat shell: at each node, the plane stress on the element's top (z = +t/2
//! along its normal) and bottom (z = −t/2) surfaces, `σ = C (ε_m ± t/2 κ)` with C the plane-stress
//! elasticity, ε_m the membrane strain and κ the curvature at the node:
//!
//! - triangle: ε_m of the constant-strain triangle, κ of the DKT at the corner (its curvature is
//!   linear over the element);
//! - quadrilateral: ε_m of the bilinear displacement at the corner (QM6's incompatible modes, which
//!   soften in-plane bending, are left out), κ of MITC4's bilinear rotations there.
//!
//! The transverse shear is zero at the surfaces; σzz is zero (plane stress). The surfaces are the
//! element's: a node's top stress is the mean over the elements around it, so the elements of a
//! mesh must have their normals on the same side (as the generators and most meshers make them).

use nalgebra::{DMatrix, SMatrix, Vector2, Vector3};

use super::frame::ElementFrame;
use super::{bilinear, dkt, membrane, to_local};
use crate::element::stress_points::{ElementStress, StressPlace};
use crate::element::validate::{positive, Elastic};
use crate::element::ElementError;
use crate::mesh::{Material, ShellSection};

/// The stress on the top and bottom surfaces at each node of a 3- or 4-node flat shell.
pub fn shell_stress_matrix(
    points: &[Vector3<f64>],
    section: &ShellSection,
    material: &Material,
) -> Result<ElementStress, ElementError> {
    let elastic = Elastic::new(material)?;
    let t = positive("shell thickness", section.thickness)?;
    let frame = ElementFrame::new(points)?;
    let n = points.len();
    let xy = &frame.plane;
    let c = membrane::plane_stress(elastic.youngs_modulus, elastic.poisson_ratio, 1.0);
    let transform = to_local(&frame);
    let axes = frame.axes;
    let mut matrix = DMatrix::zeros(6 * 2 * n, 6 * n);
    let mut points_out = Vec::new();
    for a in 0..n {
        // Membrane strain and curvature at node a over the local dofs `u v w θx θy θz` of each node.
        let mut strain = DMatrix::<f64>::zeros(3, 6 * n);
        let mut curvature = DMatrix::<f64>::zeros(3, 6 * n);
        let gradients: Vec<Vector2<f64>> = if n == 3 {
            membrane::triangle_gradients(xy).0.to_vec()
        } else {
            let [xi, eta] = bilinear::CORNERS[a];
            let (d, _) = bilinear::cartesian_derivatives(xy, xi, eta);
            (0..4).map(|i| Vector2::new(d[0][i], d[1][i])).collect()
        };
        for (i, g) in gradients.iter().enumerate() {
            strain[(0, 6 * i)] = g.x;
            strain[(1, 6 * i + 1)] = g.y;
            strain[(2, 6 * i)] = g.y;
            strain[(2, 6 * i + 1)] = g.x;
            if n == 4 {
                // βx = θy, βy = −θx (mitc4.rs): κ = [∂βx/∂x, ∂βy/∂y, ∂βx/∂y + ∂βy/∂x].
                curvature[(0, 6 * i + 4)] = g.x;
                curvature[(1, 6 * i + 3)] = -g.y;
                curvature[(2, 6 * i + 4)] = g.y;
                curvature[(2, 6 * i + 3)] = -g.x;
            }
        }
        if n == 3 {
            let natural = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]][a];
            let b: SMatrix<f64, 3, 9> = dkt::DktShape::new(xy).curvature(natural[0], natural[1]);
            for i in 0..3 {
                for (k, dof) in [2, 3, 4].into_iter().enumerate() {
                    for r in 0..3 {
                        curvature[(r, 6 * i + dof)] = b[(r, 3 * i + k)];
                    }
                }
            }
        }
        for (s, (place, z)) in [(StressPlace::Top, 0.5 * t), (StressPlace::Bottom, -0.5 * t)].into_iter().enumerate() {
            let plane = c * (&strain + &curvature * z) * &transform;
            let p = 2 * a + s;
            for (component, (i, j)) in [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                // Body components of Λᵀ σ_loc Λ, σ_loc holding σxx, σyy, τxy.
                let l = |row: usize, col: usize| axes[(row, col)];
                let row = plane.row(0) * (l(0, i) * l(0, j))
                    + plane.row(1) * (l(1, i) * l(1, j))
                    + plane.row(2) * (l(0, i) * l(1, j) + l(1, i) * l(0, j));
                matrix.row_mut(6 * p + component).copy_from(&row);
            }
            points_out.push((a, place));
        }
    }
    Ok(ElementStress { points: points_out, matrix, shared: true })
}
