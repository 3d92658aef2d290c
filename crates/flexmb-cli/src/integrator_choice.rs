//! Integrators by name, as the command line and model files write them.

use flexmb::integrate::Method;

/// The method named `name` (`spectral_radius` is the generalized-α method's ρ∞).
pub fn parse_method(name: &str, spectral_radius: f64) -> Result<Method, String> {
    let _ = spectral_radius;
    match name {
        "bdf" => Ok(Method::Bdf),
        other => Err(format!("unknown integrator `{other}`; expected {}", METHOD_NAMES.join(", "))),
    }
}

/// The integrators [`parse_method`] knows.
pub const METHOD_NAMES: &[&str] = &["bdf"];

