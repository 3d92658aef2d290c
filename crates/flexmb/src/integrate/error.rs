//! Why an integration stopped early. Every variant carries the time.

/// An integration failure.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum IntegrationError {
    #[error("step size {h:.3e} s too small at t = {t:.6} s: {reason}")]
    /// The step size fell below what the time resolves, for `reason`.
    StepSizeTooSmall {
        /// Time (s).
        t: f64,
        /// The step size (s).
        h: f64,
        /// Why the last attempt failed.
        reason: String,
    },
    #[error("the step from t = {t:.6} s failed {attempts} attempts without its size falling (last {h:.3e} s): {reason}")]
    /// The attempts at one step failed more often than a shortening step can (an attempt moved longer
    /// again after each failure), for `reason`.
    AttemptsWithoutProgress {
        /// Time (s).
        t: f64,
        /// The last attempt's step size (s).
        h: f64,
        /// The attempts made.
        attempts: usize,
        /// Why the last attempt failed.
        reason: String,
    },
    #[error("more than {max_steps} steps before t = {t:.6} s")]
    /// The step limit was reached.
    TooManySteps {
        /// Time (s).
        t: f64,
        /// The limit.
        max_steps: usize,
    },
    #[error("inconsistent initial conditions at t = {t:.6} s: {reason}")]
    /// The integrator cannot start from the state given.
    InitialConditions {
        /// Time (s).
        t: f64,
        /// Why.
        reason: String,
    },
}

/// Why the last attempt at a step of an implicit method failed, kept without allocating so that
/// recoverable failures cost nothing; [`describe`](Self::describe) turns it into a message if the step
/// size underflows. `step` is what the method needs to rebuild the failed attempt's predictor: the BDF's
/// `c = α/h`, the generalized-α method's `h`.
#[derive(Clone, Copy, Debug)]
pub(crate) enum AttemptFailure {
    None,
    Singular { t_new: f64, step: f64 },
    Newton { t_new: f64, step: f64 },
    ErrorTest { error_norm: f64, t_new: f64, step: f64 },
}

impl AttemptFailure {
    /// The reason of a step-size underflow; `worst_equation(t_new, step)` names the worst residuals at
    /// the failed attempt's predictor (only called here, so it may allocate).
    pub(crate) fn describe(self, mut worst_equation: impl FnMut(f64, f64) -> String) -> String {
        match self {
            AttemptFailure::None => String::new(),
            AttemptFailure::Singular { t_new, step } => {
                format!("the iteration matrix is singular; {}", worst_equation(t_new, step))
            }
            AttemptFailure::Newton { t_new, step } => {
                format!("the Newton iteration does not converge; {}", worst_equation(t_new, step))
            }
            AttemptFailure::ErrorTest { error_norm, t_new, step } => {
                // The equations at the predictor say where (a lock or a singular position names the joint).
                format!("the local error test fails (weighted error {error_norm:.2e}); {}", worst_equation(t_new, step))
            }
        }
    }
}
