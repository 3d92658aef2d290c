//! Checks of the material and section properties an element needs, with the error that names them.

use super::ElementError;
use crate::mesh::Material;

/// `value`, if it is positive and finite.
pub(crate) fn positive(property: &'static str, value: f64) -> Result<f64, ElementError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(ElementError::InvalidProperty { property, value })
    }
}

/// `value`, if it is zero or positive and finite.
pub(crate) fn non_negative(property: &'static str, value: f64) -> Result<f64, ElementError> {
    if value >= 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(ElementError::OutOfRange {
            property,
            requirement: "non-negative and finite",
            value,
        })
    }
}

/// The elastic constants and density of an isotropic material, checked: E > 0, −1 < ν ≤ ½ (the
/// bounds of a positive-definite isotropic strain energy in plane stress; ν = ½ is still fine there),
/// ρ ≥ 0.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Elastic {
    /// Young's modulus E.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Shear modulus G = E / (2 (1 + ν)).
    pub shear_modulus: f64,
    /// Density ρ.
    pub density: f64,
}

impl Elastic {
    pub(crate) fn new(material: &Material) -> Result<Self, ElementError> {
        let youngs_modulus = positive("Young's modulus", material.youngs_modulus)?;
        let nu = material.poisson_ratio;
        if !(nu > -1.0 && nu <= 0.5) {
            return Err(ElementError::OutOfRange {
                property: "Poisson's ratio",
                requirement: "in (-1, 0.5]",
                value: nu,
            });
        }
        let density = non_negative("density", material.density)?;
        Ok(Self {
            youngs_modulus,
            poisson_ratio: nu,
            shear_modulus: material.shear_modulus(),
            density,
        })
    }
}
