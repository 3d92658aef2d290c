//! Why an integration stopped early. Every variant carries the time.

/// An integration failure.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum IntegrationError {
    #[error("step size {h:.3e} s too small at t = {t:.6} s: {reason}")]
    StepSizeTooSmall { t: f64, h: f64, reason: String },
    #[error("more than {max_steps} steps before t = {t:.6} s")]
    TooManySteps { t: f64, max_steps: usize },
    #[error("inconsistent initial conditions at t = {t:.6} s: {reason}")]
    InitialConditions { t: f64, reason: String },
}
