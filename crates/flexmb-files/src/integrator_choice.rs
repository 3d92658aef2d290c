//! Integrators by name, as the command line and model files write them.

use flexmb::integrate::{AdamsConfig, GeneralizedAlphaConfig, Method};

/// The method named `name` (`spectral_radius` is the generalized-α method's ρ∞).
pub fn parse_method(name: &str, spectral_radius: f64) -> Result<Method, String> {
    match name {
        "bdf" => Ok(Method::default()),
        "adams" => Ok(Method::Adams(AdamsConfig::default())),
        "gen-alpha" => {
            if !(0.0..=1.0).contains(&spectral_radius) {
                return Err(format!("the spectral radius must be between 0 and 1, got {spectral_radius}"));
            }
            Ok(Method::generalized_alpha(spectral_radius))
        }
        other => Err(format!("unknown integrator `{other}`; expected {}", METHOD_NAMES.join(", "))),
    }
}

/// The integrators [`parse_method`] knows.
pub const METHOD_NAMES: &[&str] = &["bdf", "adams", "gen-alpha"];


/// A study's integrator: a method name, or `bdf:K` for the BDF with orders up to `K` (1 to 5), e.g.
/// `bdf:2` for the A-stable orders only. Returns the method and the order limit, if any.
pub fn parse_study_integrator(name: &str) -> Result<(Method, Option<usize>), String> {
    match name.split_once(':') {
        Some(("bdf", k)) => match k.parse::<usize>() {
            Ok(k) if (1..=5).contains(&k) => Ok((Method::default(), Some(k))),
            _ => Err(format!("`{name}`: the BDF's highest order after `bdf:` must be 1 to 5")),
        },
        Some(_) => Err(format!("`{name}`: only the BDF takes an order limit (`bdf:2`)")),
        None => parse_method(name, GeneralizedAlphaConfig::DEFAULT_SPECTRAL_RADIUS).map(|m| (m, None)),
    }
}
