//! The geometric (initial-stress) stiffness of the solid elements under their stress.
//!
//! A solid carrying the Cauchy stress `σ` stores, when its points move by `u`, the extra energy
//! `½ ∫ ∇uᵢᵀ σ ∇uᵢ dV` summed over the three components `i` (the quadratic part of the Green strain
//! against the initial stress). With the displacement interpolated from the nodes the block of nodes
//! a and b is `∫ ∇Nₐᵀ σ ∇N_b dV · I₃` (`∫ B_NLᵀ σ B_NL dV`; Cook et al., *Concepts and Applications of
//! Finite Element Analysis*, 4th ed., §18.4; Bathe, *Finite Element Procedures*, §6.3), integrated by
//! the element's stiffness rule. The stress at each point is the linear-elastic one of the nodal
//! displacements, `σ = λ tr ε I + 2μ ε`; for the incompatible-mode brick (C3D8I) it is taken from the
//! compatible trilinear field alone (exact for a uniform strain, which the element passes; the
//! bending strain of its bubble modes is left out of `σ`).

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::isoparametric::{cartesian_gradients, checked_determinant, lame};
use super::{family, with_rotations};
use crate::element::validate::Elastic;
use crate::element::ElementError;
use crate::mesh::{Material, SolidFormulation};

/// The `6n × 6n` geometric stiffness (body-frame dofs `ux uy uz rx ry rz` node by node; zero on the
/// rotations, which solids do not have) of the solid with nodes at `points` (in the order of
/// `formulation`) whose nodes move by `displacements` (body frame), under the stress that
/// displacement causes (module documentation).
pub fn solid_geometric_stiffness(
    points: &[Vector3<f64>],
    formulation: SolidFormulation,
    material: &Material,
    displacements: &[Vector3<f64>],
) -> Result<DMatrix<f64>, ElementError> {
    let elastic = Elastic::new(material)?;
    let (lambda, mu) = lame(elastic.youngs_modulus, elastic.poisson_ratio);
    let family = family(formulation);
    let n = points.len();
    let mut k = DMatrix::zeros(3 * n, 3 * n);
    for point in &family.stiffness_rule {
        let shape = (family.shape_at)(point.natural);
        let (j, det) = checked_determinant(points, &shape, point.natural, family.reference_volume)?;
        let gradients = cartesian_gradients(&j, &shape.derivatives);
        let displacement_gradient: Matrix3<f64> = displacements.iter().zip(&gradients).map(|(u, g)| u * g.transpose()).sum();
        let strain = (displacement_gradient + displacement_gradient.transpose()) * 0.5;
        let stress = Matrix3::identity() * (lambda * strain.trace()) + strain * (2.0 * mu);
        let weight = point.weight * det;
        for (a, ga) in gradients.iter().enumerate() {
            for (b, gb) in gradients.iter().enumerate() {
                let value = weight * ga.dot(&(stress * gb));
                for i in 0..3 {
                    k[(3 * a + i, 3 * b + i)] += value;
                }
            }
        }
    }
    Ok(with_rotations(&k))
}
