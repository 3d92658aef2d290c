//! Integrator settings with documented defaults.

/// Settings of the BDF that the other methods do not share (tolerances and step limits are in
/// [`Tolerances`](super::Tolerances)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BdfConfig {
    /// Highest order used, 1 to 5. Default 5.
    pub max_order: usize,
    /// Detect steps limited by the stability of orders 3–5 and choose the order accordingly. BDF orders
    /// above 2 are not A-stable: a lightly damped oscillation whose `h λ` falls near the imaginary axis
    /// (for 2 % damping: `h ω` from 0.47 to 1.8 at order 3, 0.59 to 4.6 at order 4, 0.81 to 9.2 at order 5)
    /// is amplified, and the step then hovers at that edge with repeated error-test failures. With this
    /// on, an error-test failure whose estimate grew fast at an unchanged step marks the step size as
    /// unstable for the order; the order's later steps are kept below it (a bound that slowly relaxes),
    /// the order selection weighs each order's step with its bound, and an order held back by its bound
    /// drops straight to 2 when order 2 allows a larger step. Default `false` (the plain order selection,
    /// which is what non-oscillatory models want: on rigid mechanisms the growth test also fires at fast
    /// transients); [`for_model`](Self::for_model) turns it on for models with flexible bodies.
    pub stability_limits: bool,
}

impl BdfConfig {
    /// The defaults for `model`: orders up to 5, with [`stability_limits`](Self::stability_limits) on when
    /// the model has a flexible body (its lightly damped high modes limit orders 3–5 by stability). On the
    /// shipped flexible pendulum over 2 s (4 modes; 10 modes), orders up to 5 with the stability limits take
    /// about the steps of orders up to 2 at loose tolerances, where order 2 is chosen (rtol 1e-6: 1910 and
    /// 1975 steps against 2070 and 2003), and far fewer at tight ones, where orders 3–5 are accuracy-limited
    /// (rtol 1e-9: 3384 and 9978 against 21683 and 21445); without the limits orders up to 5 take 2545
    /// and 11543 steps at 1e-6.
    pub fn for_model(model: &crate::Model) -> BdfConfig {
        let flexible = (0..model.bodies().len()).any(|b| model.modal_body(crate::model::BodyId(b)).is_some());
        BdfConfig { stability_limits: flexible, ..Default::default() }
    }
}

impl Default for BdfConfig {
    fn default() -> Self {
        Self { max_order: 5, stability_limits: false }
    }
}

/// The integration method of a simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Variable-order (1–5), variable-step BDF on the stabilized index-2 equations (stiff; default).
    Bdf(BdfConfig),
    /// Variable-order (1–12), variable-step Adams–Bashforth–Moulton PECE method of Shampine and Gordon,
    /// the DADS code's non-stiff method, on `y = [q, v]` with the positions and velocities projected
    /// onto the constraints after every step (non-stiff: the step follows the highest frequency); see
    /// [`AdamsConfig`](super::AdamsConfig).
    Adams(super::AdamsConfig),
    /// Generalized-α (Arnold–Brüls, stabilized index-2 constraints, Lie-group position update) with
    /// high-frequency spectral radius `spectral_radius` ∈ [0, 1], fixed second order, step size from a
    /// local error estimate; see [`GeneralizedAlphaConfig`].
    GeneralizedAlpha(GeneralizedAlphaConfig),
}

impl Default for Method {
    /// The BDF with its default settings.
    fn default() -> Self {
        Method::Bdf(BdfConfig::default())
    }
}

impl Method {
    /// The generalized-α method with high-frequency spectral radius `spectral_radius` and the step size
    /// from its local error estimate.
    pub fn generalized_alpha(spectral_radius: f64) -> Self {
        Method::GeneralizedAlpha(GeneralizedAlphaConfig { spectral_radius, ..Default::default() })
    }
}

/// Settings of the generalized-α method that the other methods do not share (tolerances and step limits
/// are in [`Tolerances`](super::Tolerances)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeneralizedAlphaConfig {
    /// Spectral radius at infinite frequency `ρ∞` ∈ [0, 1]: the factor by which the amplitude of an
    /// unresolved high-frequency motion is multiplied each step. 1 damps nothing (trapezoidal rule),
    /// 0 annihilates such motions in one step. Default 0.8
    /// ([`DEFAULT_SPECTRAL_RADIUS`](Self::DEFAULT_SPECTRAL_RADIUS)).
    pub spectral_radius: f64,
    /// Step size held fixed at this value (s), without error control (for convergence studies);
    /// only a Newton failure shortens a step. Default `None`: steps from the local error estimate.
    pub fixed_step: Option<f64>,
}

impl Default for GeneralizedAlphaConfig {
    fn default() -> Self {
        Self { spectral_radius: Self::DEFAULT_SPECTRAL_RADIUS, fixed_step: None }
    }
}

impl GeneralizedAlphaConfig {
    /// The default spectral radius at infinity, 0.8. The constraint forces' step-to-step oscillation that
    /// `ρ∞` damps (see [`undamped_warning`](Self::undamped_warning)) fed Andrews' squeezer an energy gain at
    /// loose tolerances: over the run at rtol 1e-3 its crank led by 10 tolerances at ρ∞ = 0.9 (21.7 at 0.99,
    /// 18.3 at 0.95), 0.67 at 0.8 and 0.26 at 0.6; at 1e-4 0.94 against 0.34. On the other benchmarks of
    /// docs/accuracy.md 0.8 gives the same errors (within 0.9 to 1.04 times those of 0.9, 1e-3 to 1e-6) in
    /// 2 to 4 % more steps, and the peer cases at the peer's accuracy the same deviations from the converged
    /// peer results (the chain of four rods at 1e-7 718,573 steps against 702,846). Chrono's HHT default
    /// (α = −0.2) is ρ∞ ≈ 0.67, the peer's (Exudyn's) 0.9.
    pub const DEFAULT_SPECTRAL_RADIUS: f64 = 0.8;

    /// The spectral radius above which [`undamped_warning`](Self::undamped_warning) warns under error control.
    pub const NEARLY_UNDAMPED: f64 = 0.99;

    /// A warning for a person where `ρ∞` above [`NEARLY_UNDAMPED`](Self::NEARLY_UNDAMPED) meets error
    /// control (no fixed step); `None` otherwise.
    ///
    /// Near `ρ∞ = 1` little damps the step-to-step oscillation of the constraint forces (the multipliers,
    /// and with them the accelerations, alternate about their smooth values, as with the trapezoidal rule on
    /// a constrained system). The error estimate takes the curvature of the accelerations from the
    /// velocities, which average it out (`GeneralizedAlpha::error_norm`), so the steps no longer collapse
    /// (at rtol 1e-4 and ρ∞ = 1 the peer's 3-D pendulum 1,998 steps, 1.04 tolerances off, the slider-crank
    /// 25,121 and 0.90, Bricard 2,346 and 1.44, the flyball governor 5,428 and 0.93, the heavy top 116,939
    /// and 0.04). But the oscillation feeds energy into some motions, which no estimate of one step sees:
    /// Andrews' squeezer at rtol 1e-4 is 21 tolerances off at ρ∞ = 1 (0.33 at 0.8), at 1e-3 21.7 at 0.99
    /// and 10.1 at 0.9 (0.67 at 0.8); and the double four-bar's first singular position stops the run at
    /// ρ∞ = 1 (t = 0.675 s, rtol 1e-4 and 1e-6). With a fixed step there is no estimate.
    pub fn undamped_warning(&self) -> Option<String> {
        let rho = self.spectral_radius;
        (self.fixed_step.is_none() && rho > Self::NEARLY_UNDAMPED).then(|| {
            format!(
                "spectral radius ρ∞ = {rho} of the generalized-α method under error control: so near 1 little damps the \
                 step-to-step oscillation of the constraint forces, which can feed energy into the motion where no \
                 error estimate sees it (Andrews' squeezer at ρ∞ = 1 and rtol 1e-4: 21 tolerances off, 0.33 at 0.8) and \
                 stops the double four-bar at its first singular position; give ρ∞ of at most {limit} ({default} by \
                 default), or a fixed step (fixed_step, --fixed-step), at which ρ∞ = 1 is the trapezoidal rule",
                limit = Self::NEARLY_UNDAMPED,
                default = Self::DEFAULT_SPECTRAL_RADIUS
            )
        })
    }

    /// Checks that `ρ∞` is in [0, 1] and a fixed step positive.
    pub fn validate(&self) -> Result<(), String> {
        let rho = self.spectral_radius;
        if !(0.0..=1.0).contains(&rho) {
            return Err(format!("the spectral radius ρ∞ of the generalized-α method must be in [0, 1], got {rho}"));
        }
        if let Some(h) = self.fixed_step {
            if !(h > 0.0 && h.is_finite()) {
                return Err(format!("the fixed step of the generalized-α method must be positive, got {h}"));
            }
        }
        Ok(())
    }
}
