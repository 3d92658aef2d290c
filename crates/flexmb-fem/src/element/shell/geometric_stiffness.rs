//! The geometric (initial-stress) stiffness of the flat shell under its membrane stress.
//!
//! A shell carrying the in-plane stress resultants `N = [Nxx Nyy Nxy]` (force per length, tension
//! positive) stores, when its points move by `u = (u, v, w)` (local), the extra energy
//! `½ ∫ ∇uᵢᵀ [Nxx Nxy; Nxy Nyy] ∇uᵢ dA` summed over the three components (the von Kármán plate's
//! `½ ∫ N ∇w ∇w` for `w`, and the same in-plane). With the translations interpolated from the
//! nodes (bilinear on the quadrilateral, linear on the triangle) the block of nodes a and b is
//! `∫ ∇Nₐᵀ N ∇N_b dA · I₃` (Cook et al., *Concepts and Applications of Finite Element Analysis*, 4th
//! ed., §18.5; Zienkiewicz and Taylor, *The Finite Element Method*, vol. 2, §9.4), by the 2 × 2 Gauss
//! rule on the quadrilateral, exactly on the triangle. A scalar times `I₃` is the same in every
//! axes, so the block needs no turning into body axes; a warped quadrilateral's rigid links to its
//! plane are left out (of the size of the warp against the element, at most
//! [`WARP_TOLERANCE`](super::WARP_TOLERANCE)).
//!
//! The stress resultants come from the membrane strain of the element's nodal displacements by the
//! same interpolation: on the quadrilateral without QM6's incompatible modes (exact for a uniform
//! strain, which QM6 passes; the in-plane bending strain those modes add is left out of `N`), on the
//! triangle the constant strain of its membrane. The bending moments' and transverse shears'
//! initial-stress terms are not included (the membrane stress dominates a thin shell's stiffening).

use nalgebra::{DMatrix, Matrix2, Vector2, Vector3};

use super::frame::ElementFrame;
use super::{bilinear, membrane};
use crate::element::validate::{positive, Elastic};
use crate::element::ElementError;
use crate::mesh::{Material, ShellSection};

/// The `6n × 6n` geometric stiffness (body-frame dofs `ux uy uz rx ry rz` node by node; zero on the
/// rotations) of the shell with nodes at `points` whose nodes move by `displacements` (translations,
/// body frame), under the membrane stress that displacement causes (module documentation).
pub fn shell_geometric_stiffness(
    points: &[Vector3<f64>],
    section: &ShellSection,
    material: &Material,
    displacements: &[Vector3<f64>],
) -> Result<DMatrix<f64>, ElementError> {
    let elastic = Elastic::new(material)?;
    let t = positive("shell thickness", section.thickness)?;
    let frame = ElementFrame::new(points)?;
    let d = membrane::plane_stress(elastic.youngs_modulus, elastic.poisson_ratio, t);
    let n = points.len();
    let local: Vec<Vector2<f64>> = displacements.iter().map(|u| (frame.axes * u).xy()).collect();
    // (gradients of the shape functions, area weight) at each point of the rule.
    let rule: Vec<(Vec<Vector2<f64>>, f64)> = if n == 3 {
        let (gradients, area) = membrane::triangle_gradients(&frame.plane);
        vec![(gradients.to_vec(), area)]
    } else {
        bilinear::gauss_points()
            .iter()
            .map(|&[xi, eta]| {
                let (g, det) = bilinear::cartesian_derivatives(&frame.plane, xi, eta);
                ((0..4).map(|i| Vector2::new(g[0][i], g[1][i])).collect(), det)
            })
            .collect()
    };
    let mut k = DMatrix::zeros(6 * n, 6 * n);
    for (gradients, weight) in &rule {
        let mut strain = nalgebra::Vector3::zeros();
        for (g, u) in gradients.iter().zip(&local) {
            strain += nalgebra::Vector3::new(g.x * u.x, g.y * u.y, g.y * u.x + g.x * u.y);
        }
        let resultant = d * strain;
        let stress = Matrix2::new(resultant[0], resultant[2], resultant[2], resultant[1]);
        for (a, ga) in gradients.iter().enumerate() {
            for (b, gb) in gradients.iter().enumerate() {
                let value = weight * ga.dot(&(stress * gb));
                for i in 0..3 {
                    k[(6 * a + i, 6 * b + i)] += value;
                }
            }
        }
    }
    Ok(k)
}
