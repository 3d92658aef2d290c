//! The 8-node brick enhanced by incompatible modes (CalculiX/Abaqus C3D8I): the trilinear field plus,
//! along each body axis, the three bubble displacements `(1 − ξ²)`, `(1 − η²)`, `(1 − ζ²)` that let
//! the element bend without the shear locking of the plain C3D8 (Wilson, Taylor, Doherty and
//! Ghaboussi 1973; Taylor, Beresford and Wilson 1976). The nine bubble amplitudes belong to the
//! element alone: they carry no mass and are condensed out statically,
//! `K = K_uu − K_ua K_aa⁻¹ K_au`.
//!
//! As CalculiX does (`shape8hu.f`), the bubbles' Cartesian gradients use the Jacobian at the element
//! centre, `∇ψ = J₀⁻ᵀ ∂ψ/∂ξ`, and the stiffness is integrated with 2 × 2 × 2 Gauss points weighted
//! by `det J` at each point. (Taylor's correction would weight them by `det J₀ / det J` so that a
//! distorted element still passes the patch test; CalculiX does not, and neither do we, so that the
//! two give the same matrices. Parallelepipeds, where `det J = det J₀`, pass it either way.)

use nalgebra::{DMatrix, Vector3};

use super::hexahedron::{self, REFERENCE_VOLUME};
use super::isoparametric::{add_stiffness, cartesian_gradients, checked_determinant};
use super::quadrature::brick;
use crate::element::ElementError;

/// The condensed stiffness (24 × 24, translations node by node) of the incompatible-mode brick.
pub(super) fn stiffness(points: &[Vector3<f64>], moduli: (f64, f64)) -> Result<DMatrix<f64>, ElementError> {
    let k = enhanced_stiffness(points, moduli)?;
    let k_uu = k.view((0, 0), (24, 24));
    let k_ua = k.view((0, 24), (24, 9));
    let condensed = k_uu + k_ua * bubble_amplitudes(&k)?;
    Ok((&condensed + condensed.transpose()) * 0.5)
}

/// `−K_aa⁻¹ K_au` (9 × 24): the bubble amplitudes that the nodal translations `u` leave in
/// equilibrium, `α = −K_aa⁻¹ K_au u`, from the enhanced stiffness `k` (33 × 33).
fn bubble_amplitudes(k: &DMatrix<f64>) -> Result<DMatrix<f64>, ElementError> {
    let k_au = k.view((24, 0), (9, 24)).into_owned();
    let k_aa = k.view((24, 24), (9, 9)).into_owned();
    let Some(cholesky) = k_aa.cholesky() else {
        return Err(ElementError::InvertedSolid { determinant: 0.0, relative: 0.0, at: [0.0; 3] });
    };
    Ok(-cholesky.solve(&k_au))
}

/// The stiffness (33 × 33) of the nodal translations (rows 0–23) and the nine bubble amplitudes
/// (rows 24–32: along x, y, z of the bubble `1 − ξ²`, then of `1 − η²` and `1 − ζ²`).
fn enhanced_stiffness(points: &[Vector3<f64>], (lambda, mu): (f64, f64)) -> Result<DMatrix<f64>, ElementError> {
    let centre = hexahedron::linear([0.0; 3]);
    let (j0, _) = checked_determinant(points, &centre, [0.0; 3], REFERENCE_VOLUME)?;
    let mut k = DMatrix::zeros(33, 33);
    for point in brick(2) {
        let shape = hexahedron::linear(point.natural);
        let (j, det) = checked_determinant(points, &shape, point.natural, REFERENCE_VOLUME)?;
        let mut gradients = cartesian_gradients(&j, &shape.derivatives);
        gradients.extend(cartesian_gradients(&j0, &bubble_derivatives(point.natural)));
        add_stiffness(&mut k, &gradients, lambda, mu, point.weight * det);
    }
    Ok(k)
}

/// The natural derivatives of the three bubbles `1 − ξ²`, `1 − η²`, `1 − ζ²` at `natural`.
fn bubble_derivatives(natural: [f64; 3]) -> Vec<Vector3<f64>> {
    (0..3).map(|axis| Vector3::ith(axis, -2.0 * natural[axis])).collect()
}

/// The matrix (33 × 24) that maps the 24 nodal translations `u` to the amplitudes of the eleven
/// displacement fields of the element: the identity on the eight nodes', `−K_aa⁻¹ K_au` on the
/// three bubbles' (the amplitudes that leave the bubbles in equilibrium).
pub(super) fn field_amplitudes(points: &[Vector3<f64>], moduli: (f64, f64)) -> Result<DMatrix<f64>, ElementError> {
    let k = enhanced_stiffness(points, moduli)?;
    let mut amplitudes = DMatrix::zeros(33, 24);
    amplitudes.view_mut((0, 0), (24, 24)).fill_with_identity();
    amplitudes.view_mut((24, 0), (9, 24)).copy_from(&bubble_amplitudes(&k)?);
    Ok(amplitudes)
}

/// The Cartesian gradients of the eleven fields at natural coordinates `natural`: the eight nodes'
/// (with the Jacobian there), then the three bubbles' (with the centre's, as in the stiffness).
pub(super) fn field_gradients(points: &[Vector3<f64>], natural: [f64; 3]) -> Vec<Vector3<f64>> {
    let centre = hexahedron::linear([0.0; 3]);
    let j0 = super::isoparametric::jacobian(points, &centre);
    let shape = hexahedron::linear(natural);
    let j = super::isoparametric::jacobian(points, &shape);
    let mut gradients = cartesian_gradients(&j, &shape.derivatives);
    gradients.extend(cartesian_gradients(&j0, &bubble_derivatives(natural)));
    gradients
}
