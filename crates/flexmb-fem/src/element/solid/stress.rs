//! Stress recovery of the solid elements: the stress at each node of an element, evaluated at the
//! node's natural coordinates, `σ = D B(ξₐ) u` (isotropic D, the strain of the element's own
//! displacement field there). The incompatible-mode brick adds its bubbles' strain, their amplitudes
//! condensed from the nodal translations as in its stiffness.
//!
//! Evaluating at the nodes rather than extrapolating from the integration points: the two agree for
//! the linear elements (whose strain field is what it is) and for any element whose exact strain is
//! within its interpolation (a bar in tension, a brick in pure bending with incompatible modes, a
//! quadratic element under a linearly varying moment); elsewhere they differ by the discretization
//! error, which the averaging over the elements at a node then halves in practice.

use nalgebra::{DMatrix, Vector3};

use super::isoparametric::{cartesian_gradients, jacobian, lame};
use super::{family, incompatible_modes, natural_nodes};
use crate::element::stress_points::{ElementStress, StressPlace};
use crate::element::validate::Elastic;
use crate::element::ElementError;
use crate::mesh::{Material, SolidFormulation};

/// The stress at the nodes of a solid element whose nodes are at `points`: one [`StressPlace::Solid`]
/// point per node, each σ (σxx σyy σzz σxy σyz σzx, body axes) from the element's nodal
/// displacements.
pub fn solid_stress_matrix(
    points: &[Vector3<f64>],
    formulation: SolidFormulation,
    material: &Material,
) -> Result<ElementStress, ElementError> {
    let elastic = Elastic::new(material)?;
    let (lambda, mu) = lame(elastic.youngs_modulus, elastic.poisson_ratio);
    let n = points.len();
    let enhanced = formulation == SolidFormulation::IncompatibleModeBrick;
    // The amplitudes of the displacement fields (3 per field) from the nodal translations (3 n).
    let amplitudes = match enhanced {
        true => incompatible_modes::field_amplitudes(points, (lambda, mu))?,
        false => DMatrix::identity(3 * n, 3 * n),
    };
    let shape_at = family(formulation).shape_at;
    let mut matrix = DMatrix::zeros(6 * n, 6 * n);
    for (a, natural) in natural_nodes(formulation).into_iter().enumerate() {
        let gradients = match enhanced {
            true => incompatible_modes::field_gradients(points, natural),
            false => {
                let shape = shape_at(natural);
                cartesian_gradients(&jacobian(points, &shape), &shape.derivatives)
            }
        };
        let stress = elasticity(lambda, mu) * strain_displacement(&gradients) * &amplitudes;
        for b in 0..n {
            for i in 0..3 {
                matrix.view_mut((6 * a, 6 * b + i), (6, 1)).copy_from(&stress.column(3 * b + i));
            }
        }
    }
    Ok(ElementStress { points: (0..n).map(|a| (a, StressPlace::Solid)).collect(), matrix, shared: true })
}

/// The strain (εxx εyy εzz γxy γyz γzx) of displacement fields with Cartesian gradients
/// `gradients`, from their amplitudes (3 per field): 6 × 3 m.
fn strain_displacement(gradients: &[Vector3<f64>]) -> DMatrix<f64> {
    let mut b = DMatrix::zeros(6, 3 * gradients.len());
    for (k, g) in gradients.iter().enumerate() {
        let c = 3 * k;
        b[(0, c)] = g.x;
        b[(1, c + 1)] = g.y;
        b[(2, c + 2)] = g.z;
        b[(3, c)] = g.y;
        b[(3, c + 1)] = g.x;
        b[(4, c + 1)] = g.z;
        b[(4, c + 2)] = g.y;
        b[(5, c + 2)] = g.x;
        b[(5, c)] = g.z;
    }
    b
}

/// The isotropic elasticity matrix (6 × 6, engineering shear strains) of Lamé's constants.
fn elasticity(lambda: f64, mu: f64) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |r, c| match (r < 3, c < 3) {
        (true, true) => lambda + if r == c { 2.0 * mu } else { 0.0 },
        (false, false) if r == c => mu,
        _ => 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel() -> Material {
        Material { name: "steel".into(), youngs_modulus: 210e9, poisson_ratio: 0.3, density: 7850.0 }
    }

    /// A uniform strain (any affine displacement field on an element with straight edges) gives the
    /// same stress `D ε` at every node, for every formulation: the stress patch test.
    #[test]
    fn a_uniform_strain_gives_hookes_stress_at_every_node() {
        let strain = nalgebra::Matrix3::new(1.0, 0.4, -0.2, 0.4, -0.5, 0.3, -0.2, 0.3, 0.8) * 1e-4;
        let rotation = nalgebra::Matrix3::new(0.0, -0.7, 0.0, 0.7, 0.0, 0.2, 0.0, -0.2, 0.0) * 1e-3;
        let (lambda, mu) = lame(210e9, 0.3);
        let expected = strain * (2.0 * mu) + nalgebra::Matrix3::identity() * (lambda * strain.trace());
        let voigt = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
        for formulation in SolidFormulation::ALL {
            let a = nalgebra::Matrix3::new(0.30, 0.05, -0.02, 0.04, 0.20, 0.03, -0.01, 0.06, 0.25);
            let points: Vec<Vector3<f64>> =
                natural_nodes(formulation).iter().map(|x| Vector3::new(1.0, -2.0, 0.5) + a * Vector3::from(*x)).collect();
            let recovery = solid_stress_matrix(&points, formulation, &steel()).unwrap();
            let u = DMatrix::from_fn(6 * points.len(), 1, |r, _| match r % 6 {
                i @ 0..=2 => ((strain + rotation) * points[r / 6])[i],
                _ => 0.0,
            });
            let sigma = &recovery.matrix * u;
            for (p, &(node, place)) in recovery.points.iter().enumerate() {
                assert_eq!((node, place), (p, StressPlace::Solid));
                for (k, &(i, j)) in voigt.iter().enumerate() {
                    let error = (sigma[6 * p + k] - expected[(i, j)]).abs();
                    assert!(error < 1e-6 * expected.norm(), "{formulation:?} node {p} component {k}: {error}");
                }
            }
        }
    }
}
