//! 3D beam element (to be written).
use nalgebra::Vector3;

use super::{ElementError, ElementMatrices};
use crate::mesh::{BeamSection, Material};

/// Stiffness and lumped mass of a 2-node 3D beam from `a` to `b`.
pub fn beam_matrices(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    section: &BeamSection,
    material: &Material,
    rotary_inertia: bool,
) -> Result<ElementMatrices, ElementError> {
    let _ = (a, b, section, material, rotary_inertia);
    todo!("beam element")
}
