//! Solid (continuum) elements: isoparametric tetrahedra, wedges and bricks with three translations
//! per node, each the CalculiX/Abaqus element of the same name and the same formulation, so that
//! flexmb and `ccx` give the same frequencies for the same deck (to 1e-6, see
//! `tests/solid_calculix.rs`). One file per family:
//!
//! | element | nodes | shape functions | stiffness rule | mass rule | lumped mass | file |
//! |---|---|---|---|---|---|---|
//! | C3D4 | 4 | linear tetrahedron | 1 point | 4 points | row sum | `tetrahedron.rs` |
//! | C3D10 | 10 | quadratic tetrahedron | 4 points | 4 points | HRZ | `tetrahedron.rs` |
//! | C3D6 | 6 | linear wedge | 2 points | 2 points | row sum | `wedge.rs` |
//! | C3D15 | 15 | quadratic wedge | 3 × 3 points | 3 × 3 points | HRZ | `wedge.rs` |
//! | C3D8 | 8 | trilinear brick | 2 × 2 × 2 | 2 × 2 × 2 | row sum | `hexahedron.rs` |
//! | C3D8I | 8 (+ 9 bubbles) | trilinear + incompatible modes | 2 × 2 × 2 | 2 × 2 × 2 | row sum | `incompatible_modes.rs` |
//! | C3D20 | 20 | serendipity brick | 3 × 3 × 3 | 3 × 3 × 3 | HRZ | `hexahedron.rs` |
//! | C3D20R | 20 | serendipity brick | 2 × 2 × 2 (reduced) | 2 × 2 × 2 | HRZ | `hexahedron.rs` |
//!
//! The integration points are CalculiX's (`quadrature.rs`); the Jacobian, the strain–displacement
//! product `Bᵀ D B` of an isotropic material and the mass points are shared (`isoparametric.rs`).
//! The geometric (initial-stress) stiffness under the element's stress is `geometric_stiffness.rs`.
//!
//! **Which 8-node brick.** C3D8 (full integration) locks in bending: a cantilever of one brick
//! through the thickness is several times too stiff. Of the two remedies CalculiX offers, flexmb
//! takes C3D8I, the incompatible modes (`incompatible_modes.rs`): it bends exactly for rectangular
//! elements, needs no tuning parameter, and has no zero-energy modes, where C3D8R's one-point
//! integration needs an artificial hourglass stiffness whose size is a chosen constant and whose
//! spurious modes can appear among the low frequencies of a coarse free-free mesh — the very modes a
//! reduced flexible body is made of. The shell membrane (QM6) takes the same remedy.
//!
//! **Zero-energy modes.** CalculiX's rules are exact for the stiffness of undistorted C3D4, C3D8
//! and C3D20 elements and of C3D10 with straight edges; two are reduced and leave a single element
//! modes without energy besides its rigid motions: C3D6 (one, its two points on the axis) and C3D20R
//! (six). Neighbours restrain them in a mesh of more than one element (the ccx comparison meshes
//! have none), but a body of one such element, or a layer of C3D6 one element thick, may have them.
//!
//! **Consistent mass.** `∫ ρ Nᵀ N dV` as mass points at the integration points of the mass rule
//! (the same rule as the stiffness, as in CalculiX, except for C3D4, see below). These rules
//! integrate the mass, its first and its second moments exactly for elements with straight edges,
//! so the body's mass properties and inertia invariants are exact; the product `Nₐ N_b` is exact for
//! C3D8, C3D8I and C3D20, not for the others (CalculiX's "consistent" mass of C3D10, C3D6, C3D15 and
//! C3D20R is this one). C3D4's mass is taken at its 4-point rule, exact, where CalculiX's 1-point
//! rule would put the whole mass at the centroid (wrong second moments).
//!
//! **Lumped mass.** Row sums of the consistent mass for the linear elements (all positive: their
//! shape functions are). The quadratic elements' row sums are zero or negative at the corners, so
//! they take the HRZ lumping (Hinton, Rock and Zienkiewicz 1976): the diagonal of the consistent
//! mass, scaled so that it sums to the element's mass. Solids carry no rotary inertia.
//!
//! **Errors.** An element whose Jacobian determinant is not positive at an integration point
//! (nodes out of order: inverted; or collapsed) is refused with that determinant; a Poisson's ratio
//! of ½ (incompressible) is refused (λ would be infinite).

mod geometric_stiffness;
mod hexahedron;
mod incompatible_modes;
mod isoparametric;
mod quadrature;
mod stress;
mod tetrahedron;
mod wedge;

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::validate::Elastic;
use super::{ElementError, ElementMatrices, MassPoint, NodalMass};
use crate::mesh::{MassModel, Material, ModelOptions, SolidFormulation};
pub use geometric_stiffness::solid_geometric_stiffness;
use isoparametric::{lame, mass_points, stiffness, ShapeFunctionsAt};
use quadrature::IntegrationPoint;

pub use stress::solid_stress_matrix;

/// How an element's mass is lumped at its nodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Lumping {
    /// Row sums of the consistent mass.
    RowSum,
    /// The diagonal of the consistent mass scaled to the element's mass (HRZ).
    DiagonalScaling,
}

/// What a formulation is made of.
struct Family {
    shape_at: ShapeFunctionsAt,
    reference_volume: f64,
    stiffness_rule: Vec<IntegrationPoint>,
    mass_rule: Vec<IntegrationPoint>,
    lumping: Lumping,
}

fn family(formulation: SolidFormulation) -> Family {
    use SolidFormulation::*;
    let (shape_at, reference_volume): (ShapeFunctionsAt, f64) = match formulation {
        LinearTetrahedron => (tetrahedron::linear, tetrahedron::REFERENCE_VOLUME),
        QuadraticTetrahedron => (tetrahedron::quadratic, tetrahedron::REFERENCE_VOLUME),
        LinearWedge => (wedge::linear, wedge::REFERENCE_VOLUME),
        QuadraticWedge => (wedge::quadratic, wedge::REFERENCE_VOLUME),
        LinearBrick | IncompatibleModeBrick => (hexahedron::linear, hexahedron::REFERENCE_VOLUME),
        QuadraticBrick | ReducedQuadraticBrick => (hexahedron::quadratic, hexahedron::REFERENCE_VOLUME),
    };
    let (stiffness_rule, mass_rule) = match formulation {
        LinearTetrahedron => (quadrature::tetrahedron_centroid(), quadrature::tetrahedron_4()),
        QuadraticTetrahedron => (quadrature::tetrahedron_4(), quadrature::tetrahedron_4()),
        LinearWedge => (quadrature::wedge(1, 2), quadrature::wedge(1, 2)),
        QuadraticWedge => (quadrature::wedge(3, 3), quadrature::wedge(3, 3)),
        LinearBrick | IncompatibleModeBrick | ReducedQuadraticBrick => (quadrature::brick(2), quadrature::brick(2)),
        QuadraticBrick => (quadrature::brick(3), quadrature::brick(3)),
    };
    let lumping = match formulation {
        LinearTetrahedron | LinearWedge | LinearBrick | IncompatibleModeBrick => Lumping::RowSum,
        _ => Lumping::DiagonalScaling,
    };
    Family { shape_at, reference_volume, stiffness_rule, mass_rule, lumping }
}

/// Stiffness and mass of a solid element with nodes at `points` (in the order of `formulation`).
///
/// Errors: `NodeCount` for the wrong number of points, `InvertedSolid` for a Jacobian determinant
/// that is not positive at an integration point, `InvalidProperty` / `OutOfRange` for Young's
/// modulus, Poisson's ratio (−1 < ν < ½) or density out of range.
pub fn solid_matrices(
    points: &[Vector3<f64>],
    formulation: SolidFormulation,
    material: &Material,
    options: &ModelOptions,
) -> Result<ElementMatrices, ElementError> {
    let expected = formulation.node_count();
    if points.len() != expected {
        return Err(ElementError::NodeCount { kind: formulation.abaqus_name(), expected: node_count_name(expected), found: points.len() });
    }
    let elastic = Elastic::new(material)?;
    if elastic.poisson_ratio >= 0.5 {
        return Err(ElementError::OutOfRange { property: "Poisson's ratio of a solid", requirement: "in (-1, 0.5)", value: elastic.poisson_ratio });
    }
    let moduli = lame(elastic.youngs_modulus, elastic.poisson_ratio);
    let family = family(formulation);
    let translational = match formulation {
        SolidFormulation::IncompatibleModeBrick => incompatible_modes::stiffness(points, moduli)?,
        _ => stiffness(points, family.shape_at, &family.stiffness_rule, family.reference_volume, moduli)?,
    };
    let consistent = mass_points(points, family.shape_at, &family.mass_rule, family.reference_volume, elastic.density)?;
    let lumped = lumped_masses(&consistent, points.len(), family.lumping);
    Ok(ElementMatrices {
        stiffness: with_rotations(&translational),
        lumped_mass: lumped.into_iter().map(|mass| NodalMass { mass, rotary_inertia: Matrix3::zeros() }).collect(),
        consistent_mass: if options.solid_mass() == MassModel::Consistent { consistent } else { Vec::new() },
    })
}

/// The natural coordinates of the nodes of `formulation`, in its node order.
fn natural_nodes(formulation: SolidFormulation) -> Vec<[f64; 3]> {
    let n = formulation.node_count();
    match formulation {
        SolidFormulation::LinearTetrahedron | SolidFormulation::QuadraticTetrahedron => tetrahedron::NODES[..n].to_vec(),
        SolidFormulation::LinearWedge | SolidFormulation::QuadraticWedge => wedge::NODES[..n].to_vec(),
        _ => hexahedron::NODES[..n].to_vec(),
    }
}

fn node_count_name(count: usize) -> &'static str {
    match count {
        4 => "4",
        6 => "6",
        8 => "8",
        10 => "10",
        15 => "15",
        _ => "20",
    }
}

/// The 6n × 6n matrix over `ux uy uz rx ry rz` of each node of a 3n × 3n one over translations
/// (zero rows and columns at the rotations, which solids do not have).
fn with_rotations(k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = k.nrows() / 3;
    DMatrix::from_fn(6 * n, 6 * n, |r, c| if r % 6 < 3 && c % 6 < 3 { k[(3 * (r / 6) + r % 6, 3 * (c / 6) + c % 6)] } else { 0.0 })
}

/// The nodes' shares of the mass of the consistent mass points, by `lumping`.
fn lumped_masses(points: &[MassPoint], nodes: usize, lumping: Lumping) -> Vec<f64> {
    let mut lumped = vec![0.0; nodes];
    let value = |block: &nalgebra::Matrix6<f64>| block[(0, 0)];
    for point in points {
        for (a, block) in &point.interpolation {
            lumped[*a] += match lumping {
                // Σ_b M_ab = Σ_g m_g N_a(g) Σ_b N_b(g) = Σ_g m_g N_a(g).
                Lumping::RowSum => point.mass * value(block),
                Lumping::DiagonalScaling => point.mass * value(block).powi(2),
            };
        }
    }
    if lumping == Lumping::DiagonalScaling {
        let total: f64 = points.iter().map(|p| p.mass).sum();
        let diagonal: f64 = lumped.iter().sum();
        if diagonal > 0.0 {
            lumped.iter_mut().for_each(|m| *m *= total / diagonal);
        }
    }
    lumped
}

#[cfg(test)]
mod tests;
