//! The solid elements' identities: shape functions (partition of unity, one at their node and zero at
//! the others, derivatives), stiffness (symmetric, exactly six rigid motions without energy, the exact
//! energy of every uniform strain on an affine element: the patch test), mass (the element's mass,
//! positive lumped masses) and the errors of inverted elements and incompressible materials.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::isoparametric::ShapeFunctionsAt;
use super::*;
use crate::element::ElementError;
use crate::mesh::{Material, ModelOptions};

fn steel() -> Material {
    Material { name: "steel".into(), youngs_modulus: 210e9, poisson_ratio: 0.3, density: 7850.0 }
}

/// An affine map of the reference element, oblique and stretched: `x = x₀ + A ξ`.
fn affine(x: [f64; 3]) -> Vector3<f64> {
    let a = Matrix3::new(0.30, 0.05, -0.02, 0.04, 0.20, 0.03, -0.01, 0.06, 0.25);
    Vector3::new(1.0, -2.0, 0.5) + a * Vector3::from(x)
}

/// The affine map plus a smooth distortion (curved edges, varying Jacobian).
fn distorted(x: [f64; 3]) -> Vector3<f64> {
    affine(x) + 0.02 * Vector3::new(x[0] * x[1], x[1] * x[2] + x[0] * x[0], x[2] * x[0])
}

fn points(formulation: SolidFormulation, map: fn([f64; 3]) -> Vector3<f64>) -> Vec<Vector3<f64>> {
    natural_nodes(formulation).into_iter().map(map).collect()
}

fn translations(k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = k.nrows() / 6;
    DMatrix::from_fn(3 * n, 3 * n, |r, c| k[(6 * (r / 3) + r % 3, 6 * (c / 3) + c % 3)])
}

fn shape_functions(formulation: SolidFormulation) -> ShapeFunctionsAt {
    family(formulation).shape_at
}

#[test]
fn shape_functions_interpolate_their_nodes_and_have_the_right_derivatives() {
    let inside = [[0.2, 0.1, 0.3], [0.1, 0.25, -0.4], [0.05, 0.6, 0.1]];
    for formulation in SolidFormulation::ALL {
        let shape_at = shape_functions(formulation);
        let nodes = natural_nodes(formulation);
        for (a, node) in nodes.iter().enumerate() {
            let values = shape_at(*node).values;
            for (b, v) in values.iter().enumerate() {
                let expected = if a == b { 1.0 } else { 0.0 };
                assert!((v - expected).abs() < 1e-14, "{formulation:?}: N{b} at node {a} is {v}");
            }
        }
        for x in inside {
            let shape = shape_at(x);
            assert!((shape.values.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(shape.derivatives.iter().sum::<Vector3<f64>>().norm() < 1e-13);
            let h = 1e-6;
            for k in 0..3 {
                let (mut plus, mut minus) = (x, x);
                plus[k] += h;
                minus[k] -= h;
                let (p, m) = (shape_at(plus).values, shape_at(minus).values);
                for a in 0..nodes.len() {
                    let numeric = (p[a] - m[a]) / (2.0 * h);
                    assert!((numeric - shape.derivatives[a][k]).abs() < 1e-8, "{formulation:?}: dN{a}/dx{k}");
                }
            }
        }
    }
}

/// Zero-energy modes of one element besides the rigid motions: those of CalculiX's reduced rules,
/// C3D6's two points and C3D20R's 2 × 2 × 2.
fn spurious_modes(formulation: SolidFormulation) -> usize {
    match formulation {
        SolidFormulation::LinearWedge => 1,
        SolidFormulation::ReducedQuadraticBrick => 6,
        _ => 0,
    }
}

#[test]
fn stiffness_has_exactly_the_six_rigid_motions() {
    for formulation in SolidFormulation::ALL {
        let p = points(formulation, distorted);
        let k = translations(&solid_matrices(&p, formulation, &steel(), &ModelOptions::default()).unwrap().stiffness);
        assert!((&k - k.transpose()).amax() < 1e-13 * k.amax(), "{formulation:?} asymmetric");
        let mut values: Vec<f64> = k.clone().symmetric_eigen().eigenvalues.iter().map(|v| v / k.amax()).collect();
        values.sort_by(f64::total_cmp);
        let zero = 6 + spurious_modes(formulation);
        assert!(values[..zero].iter().all(|v| v.abs() < 1e-10), "{formulation:?}: {:?}", &values[..zero + 1]);
        assert!(values[zero] > 1e-4, "{formulation:?}: eigenvalue {} is {:e}; {:?}", zero + 1, values[zero], &values[..12]);
        for axis in 0..3 {
            let e = Vector3::ith(axis, 1.0);
            for rotation in [false, true] {
                let u = DVector::from_iterator(3 * p.len(), p.iter().flat_map(|x| if rotation { e.cross(x) } else { e }.iter().copied().collect::<Vec<_>>()));
                assert!((&k * &u).amax() < 1e-10 * k.amax() * u.amax(), "{formulation:?}: rigid motion");
            }
        }
    }
}

#[test]
fn uniform_strains_have_their_exact_energy_on_affine_elements() {
    let strain: Matrix3<f64> = Matrix3::new(1.0, 0.3, -0.2, 0.3, -0.5, 0.4, -0.2, 0.4, 0.7) * 1e-3;
    let (lambda, mu) = lame(210e9, 0.3);
    let density_energy = lambda * strain.trace().powi(2) + 2.0 * mu * strain.component_mul(&strain).sum();
    for formulation in SolidFormulation::ALL {
        let p = points(formulation, affine);
        let matrices = solid_matrices(&p, formulation, &steel(), &ModelOptions::default()).unwrap();
        let k = translations(&matrices.stiffness);
        let volume = matrices.lumped_mass.iter().map(|m| m.mass).sum::<f64>() / 7850.0;
        let u = DVector::from_iterator(3 * p.len(), p.iter().flat_map(|x| (strain * x).iter().copied().collect::<Vec<_>>()));
        let energy = u.dot(&(&k * &u));
        let exact = volume * density_energy;
        assert!((energy - exact).abs() < 1e-10 * exact, "{formulation:?}: {energy} against {exact}");
    }
}

#[test]
fn the_mass_is_the_element_mass_and_lumps_positively() {
    for formulation in SolidFormulation::ALL {
        let p = points(formulation, distorted);
        let options = ModelOptions { mass: Some(MassModel::Consistent), ..ModelOptions::default() };
        let matrices = solid_matrices(&p, formulation, &steel(), &options).unwrap();
        let consistent: f64 = matrices.consistent_mass.iter().map(|m| m.mass).sum();
        let lumped: Vec<f64> = matrices.lumped_mass.iter().map(|m| m.mass).collect();
        let total: f64 = lumped.iter().sum();
        assert!((consistent - total).abs() < 1e-12 * total, "{formulation:?}");
        assert!(lumped.iter().all(|&m| m > 0.0), "{formulation:?}: {lumped:?}");
        // The affine element's volume is |det A| times the reference volume.
        let a = Matrix3::new(0.30, 0.05, -0.02, 0.04, 0.20, 0.03, -0.01, 0.06, 0.25);
        let affine_volume = a.determinant() * family(formulation).reference_volume;
        let affine_mass: f64 = solid_matrices(&points(formulation, affine), formulation, &steel(), &options)
            .unwrap()
            .consistent_mass
            .iter()
            .map(|m| m.mass)
            .sum();
        assert!((affine_mass - 7850.0 * affine_volume).abs() < 1e-12 * affine_mass, "{formulation:?}");
    }
}

#[test]
fn the_consistent_mass_of_c3d8_is_the_textbook_one() {
    // A unit cube: M = ρ V / 216 · (2^(3 − d)) where d counts the coordinates in which two nodes differ.
    let p = points(SolidFormulation::LinearBrick, |x| Vector3::from(x.map(|c| (c + 1.0) / 2.0)));
    let options = ModelOptions { mass: Some(MassModel::Consistent), ..ModelOptions::default() };
    let matrices = solid_matrices(&p, SolidFormulation::LinearBrick, &steel(), &options).unwrap();
    for a in 0..8 {
        for b in 0..8 {
            let m: f64 = matrices.consistent_mass.iter().map(|g| {
                let na = g.interpolation[a].1[(0, 0)];
                let nb = g.interpolation[b].1[(0, 0)];
                g.mass * na * nb
            }).sum();
            let d = (0..3).filter(|&k| hexahedron::NODES[a][k] != hexahedron::NODES[b][k]).count() as i32;
            let expected = 7850.0 / 216.0 * 2f64.powi(3 - d);
            assert!((m - expected).abs() < 1e-12 * expected, "M{a}{b} = {m}, expected {expected}");
        }
    }
}

#[test]
fn inverted_elements_and_incompressible_materials_are_refused() {
    for formulation in SolidFormulation::ALL {
        let mut p = points(formulation, affine);
        // Mirror the element: every Jacobian determinant changes sign.
        p.iter_mut().for_each(|x| x.z = -x.z);
        let error = solid_matrices(&p, formulation, &steel(), &ModelOptions::default()).unwrap_err();
        assert!(matches!(error, ElementError::InvertedSolid { determinant, .. } if determinant < 0.0), "{formulation:?}: {error}");
        assert!(error.to_string().contains("inverted"), "{error}");
    }
    let p = points(SolidFormulation::LinearBrick, affine);
    let rubber = Material { poisson_ratio: 0.5, ..steel() };
    let error = solid_matrices(&p, SolidFormulation::LinearBrick, &rubber, &ModelOptions::default()).unwrap_err();
    assert!(error.to_string().contains("Poisson"), "{error}");
    let error = solid_matrices(&p[..7], SolidFormulation::LinearBrick, &steel(), &ModelOptions::default()).unwrap_err();
    assert_eq!(error.to_string(), "the element has 7 nodes; a C3D8 needs 8");
}
