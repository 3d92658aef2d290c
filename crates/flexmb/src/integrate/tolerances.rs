//! The tolerance and step-control record every integration method reads.

/// Error tolerances and step limits of a time integration, common to the BDF, the Adams method and the
/// generalized-α method; what only one method uses is in that method's own settings
/// ([`BdfConfig`](super::BdfConfig), [`AdamsConfig`](super::AdamsConfig),
/// [`GeneralizedAlphaConfig`](super::GeneralizedAlphaConfig)).
///
/// Each method's local error test passes when the RMS norm of the error estimate, each component
/// weighted by `atol + rtol |y|`, is at most 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance of the local error test on positions and velocities. Default `1e-6`.
    pub rtol: f64,
    /// Absolute tolerance (m, rad, m/s, rad/s alike). Default `1e-6`.
    pub atol: f64,
    /// Largest step (s). Default unlimited.
    pub h_max: f64,
    /// First step (s); chosen by the method from the initial derivatives when `None` (the default).
    pub h_init: Option<f64>,
    /// Most steps before giving up. Default 10⁷.
    pub max_steps: usize,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self { rtol: 1e-6, atol: 1e-6, h_max: f64::INFINITY, h_init: None, max_steps: 10_000_000 }
    }
}

impl Tolerances {
    /// The defaults with relative and absolute tolerance `rtol` and `atol`.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self { rtol, atol, ..Default::default() }
    }

    /// The tolerance of the simplified Newton iterations of the implicit methods (the BDF and the
    /// generalized-α method) in the weighted norm of the error test: `√rtol`, at most 0.03, and at least
    /// `10 ε / rtol` (what the increments can resolve).
    pub(crate) fn newton_tolerance(&self) -> f64 {
        (10.0 * f64::EPSILON / self.rtol).max(self.rtol.sqrt().min(0.03))
    }
}
