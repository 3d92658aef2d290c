//! Integrators by name, as the command line and model files write them.

use flexmb::integrate::{AdamsConfig, Method};

/// The method named `name` (`spectral_radius` is the generalized-α method's ρ∞).
pub fn parse_method(name: &str, spectral_radius: f64) -> Result<Method, String> {
    match name {
        "bdf" => Ok(Method::Bdf),
        "adams" => Ok(Method::Adams(AdamsConfig::default())),
        "gen-alpha" => {
            if !(0.0..=1.0).contains(&spectral_radius) {
                return Err(format!("the spectral radius must be between 0 and 1, got {spectral_radius}"));
            }
            Ok(Method::GeneralizedAlpha { spectral_radius })
        }
        other => Err(format!("unknown integrator `{other}`; expected {}", METHOD_NAMES.join(", "))),
    }
}

/// The integrators [`parse_method`] knows.
pub const METHOD_NAMES: &[&str] = &["bdf", "adams", "gen-alpha"];

