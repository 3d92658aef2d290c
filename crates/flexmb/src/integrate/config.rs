//! Integrator settings with documented defaults.

/// Settings of the BDF integrator.
#[derive(Clone, Copy, Debug)]
pub struct BdfConfig {
    /// Relative tolerance of the local error test on positions and velocities. Default `1e-6`.
    pub rtol: f64,
    /// Absolute tolerance (m, rad, m/s, rad/s alike). Default `1e-6`.
    pub atol: f64,
    /// Largest step (s). Default unlimited.
    pub h_max: f64,
    /// First step (s); chosen from the initial derivatives when `None`.
    pub h_init: Option<f64>,
    /// Highest order used, 1 to 5. Default 5.
    pub max_order: usize,
    /// Most steps before giving up. Default 10⁷.
    pub max_steps: usize,
}

impl Default for BdfConfig {
    fn default() -> Self {
        Self { rtol: 1e-6, atol: 1e-6, h_max: f64::INFINITY, h_init: None, max_order: 5, max_steps: 10_000_000 }
    }
}

/// The integration method of a simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Method {
    /// Variable-order (1–5), variable-step BDF on the stabilized index-2 equations (stiff; default).
    #[default]
    Bdf,
}
