//! Flat shell element (to be written).
use nalgebra::Vector3;

use super::{ElementError, ElementMatrices};
use crate::mesh::{Material, ModelOptions, ShellSection};

/// Stiffness and lumped mass of a 3- or 4-node flat shell.
pub fn shell_matrices(
    points: &[Vector3<f64>],
    section: &ShellSection,
    material: &Material,
    options: &ModelOptions,
) -> Result<ElementMatrices, ElementError> {
    let _ = (points, section, material, options);
    todo!("shell element")
}
