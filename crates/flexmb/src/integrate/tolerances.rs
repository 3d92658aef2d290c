//! The tolerance and step-control record every integration method reads, the share of the tolerance a
//! step may spend (error per unit step), and the finest tolerance the arithmetic allows.

use super::ToleranceSpan;

/// Error tolerances and step limits of a time integration, common to the BDF, the Adams method and the
/// generalized-α method; what only one method uses is in that method's own settings
/// ([`BdfConfig`](super::BdfConfig), [`AdamsConfig`](super::AdamsConfig),
/// [`GeneralizedAlphaConfig`](super::GeneralizedAlphaConfig)).
///
/// **What is promised** (docs/accuracy.md): the *global* error, the largest difference over the run
/// between the computed positions and velocities and the exact ones, measured with the weights
/// `atol + rtol |y|`, stays within a small multiple of 1 over the run (with [`ToleranceSpan::Run`]; over
/// every [`span`](Self::span) of simulated time with a fixed one), and falls in proportion to the
/// tolerances.
/// To that end each method's local error test passes when the RMS norm of the error estimate, each
/// component weighted by `atol + rtol |y|`, is at most `h / span` (error per unit step, Shampine 1994
/// §1.5): the local errors of the steps of one span then add up to at most the tolerance, whatever the
/// number of steps. The share `h / span` is never below what the arithmetic resolves in one step,
/// `1e-12 / rtol` (the BDF and the generalized-α method: `1e-13 / rtol`, `share_floor::FINE_STEP_FLOOR`). [`ToleranceSpan::Run`] is the
/// default; with [`ToleranceSpan::Step`] the test is the classical one, at most 1 per step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance of the global error of positions and velocities. Default `1e-6`; at least
    /// [`FINEST`](Self::FINEST) (a finer one is raised to it, see [`attainable`](Self::attainable)).
    pub rtol: f64,
    /// Absolute tolerance (m, rad, m/s, rad/s alike). Default `1e-6`; at least [`FINEST`](Self::FINEST).
    pub atol: f64,
    /// The span of simulated time whose steps together may make an error of the tolerance: a step of
    /// size `h` may make `h / span` of it (error per unit step), and the global error then falls in
    /// proportion to the tolerance. [`ToleranceSpan::Run`], the run's length, keeps the promise: the 3-D
    /// slider-crank over 5 s 3.6 to 4.4 tolerances from 1e-3 to 1e-8 with the BDF (a fixed 1 s: 13 to
    /// 20; [`ToleranceSpan::Step`], the classical error per step: 360 to 6,500). Default
    /// [`ToleranceSpan::default`], the run's span.
    pub span: ToleranceSpan,
    /// Largest step (s). Default unlimited.
    pub h_max: f64,
    /// First step (s); chosen by the method from the initial derivatives when `None` (the default).
    pub h_init: Option<f64>,
    /// Most steps before giving up. Default 10⁷.
    pub max_steps: usize,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self { rtol: 1e-6, atol: 1e-6, span: ToleranceSpan::default(), h_max: f64::INFINITY, h_init: None, max_steps: 10_000_000 }
    }
}

/// The smallest relative error one step is held to: 1e-12, the finest tolerance. The error estimate of a
/// step is the difference of two solutions of the step's equations, each resolved to what the
/// conditioning of the mechanism allows: thousands of units of rounding near singular positions (the
/// 3-D slider-crank's rod spin, 1.7e-12 rad/s of noise), so that with 100 units (MATLAB's floor of its
/// `RelTol`) the heavy top and the slider-crank failed at rtol 1e-10, their step sizes driven to 1e-15 s.
pub(crate) const STEP_FLOOR: f64 = 1e-12;
/// What a Newton increment resolves, relative to the solution: 100 units of rounding (a body at rest on a
/// fixed joint, whose increments are rounding only, did not converge at 10 units with a share of 1e-6).
pub(crate) const NEWTON_FLOOR: f64 = 100.0 * f64::EPSILON;
/// What a Newton increment of rounding is, relative to the solution: ten units, a tenth of
/// [`NEWTON_FLOOR`] (the body at rest on a fixed joint: half a unit).
const ROUND_OFF: f64 = 10.0 * f64::EPSILON;

impl Tolerances {
    /// The finest relative and absolute tolerance accepted, 1e-12: the global error of a run is at least
    /// the rounding of each step added up (`N u` for `N` steps, 1e-12 for 5,000 steps), and the local error
    /// of a step cannot be held below 1e-12 of the solution. Finer ones
    /// are raised to it ([`attainable`](Self::attainable)).
    pub const FINEST: f64 = 1e-12;

    /// The defaults with relative and absolute tolerance `rtol` and `atol`.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self { rtol, atol, ..Default::default() }
    }

    /// These tolerances with a positive `rtol` or `atol` below [`FINEST`](Self::FINEST) raised to it, and, when one
    /// was raised, what was raised and why, for a person. Every method applies this when it starts; a
    /// [`Simulation`](crate::analysis::Simulation) also reports the message as a warning.
    pub fn attainable(&self) -> (Tolerances, Option<String>) {
        let (tolerances, raised) = self.raised_to(Self::FINEST);
        let message = raised.map(|raised| {
            format!(
                "tolerance finer than double precision can deliver: {raised}; a run's error is at least the rounding \
                 of its steps added up (about 1e-12 relative for thousands of steps)"
            )
        });
        (tolerances, message)
    }

    /// These tolerances with a positive `rtol` or `atol` below `finest` raised to it, and, when one was
    /// raised, which and to what (`rtol 1e-15 raised to 1e-12, …`).
    pub(crate) fn raised_to(&self, finest: f64) -> (Tolerances, Option<String>) {
        // Zero and what is not a positive number are left to the methods' own checks.
        let attainable = |x: f64| if x > 0.0 && x < finest { finest } else { x };
        let (rtol, atol) = (attainable(self.rtol), attainable(self.atol));
        if rtol == self.rtol && atol == self.atol {
            return (*self, None);
        }
        let raised: Vec<String> = [("rtol", self.rtol, rtol), ("atol", self.atol, atol)]
            .iter()
            .filter(|(_, asked, used)| asked != used)
            .map(|(name, asked, used)| format!("{name} {asked:e} raised to {used:e}"))
            .collect();
        (Tolerances { rtol, atol, ..*self }, Some(raised.join(", ")))
    }

    /// The share of the tolerance a step of size `h` may spend: `h / span` (at most 1), but not less than
    /// one step can resolve, [`STEP_FLOOR`]`/ rtol`. The local error test of every method passes when the
    /// weighted norm of the error estimate is at most this share.
    pub(crate) fn step_share(&self, h: f64) -> f64 {
        self.step_share_above(h, STEP_FLOOR)
    }

    /// [`step_share`](Self::step_share) with the floor `floor / rtol` in place of [`STEP_FLOOR`]`/ rtol`
    /// (`floor` relative to the solution; the BDF's is lower, [`share_floor`](super::share_floor)).
    pub(crate) fn step_share_above(&self, h: f64, floor: f64) -> f64 {
        let floor = (floor / self.rtol).min(1.0);
        let span = self.span.seconds();
        if span.is_finite() {
            (h / span).clamp(floor, 1.0)
        } else {
            1.0
        }
    }

    /// True when a step of size `h` has the share `floor / rtol` rather than its share of the span,
    /// `h / span` ([`step_share_above`](Self::step_share_above)): its local error is then held to `floor`
    /// of the solution whatever its size.
    pub(crate) fn floor_holds(&self, h: f64, floor: f64) -> bool {
        let span = self.span.seconds();
        let floor = floor / self.rtol;
        span.is_finite() && floor < 1.0 && h / span < floor
    }

    /// The share of the tolerance a first-order step of size `h` may spend: the geometric mean
    /// `√(h / span)` of error per unit step and error per step (at least [`step_share`](Self::step_share)).
    ///
    /// A first-order step's local error falls as `h²`, so error per unit step, `h²/2 |ÿ| ≤ tol h / span`,
    /// asks `h ∝ tol` and a number of steps inversely proportional to the tolerance (a generated model of
    /// 0.05 s with `max_order = 1` at 1e-6: more than 466,000 steps, against 1,042 with error per step).
    /// With this floor the steps are `h ∝ tol^(2/3)`. What it adds to the promise is bounded by
    /// Cauchy–Schwarz: the shares of `N₁` first-order steps add up to `Σ √(hᵢ / span) ≤ √(N₁ Σ hᵢ / span)
    /// ≤ √N₁` tolerances. It is the share of a BDF held to order 1 (`max_order = 1`), first order
    /// throughout: its error is then at most about `√N₁` tolerances, falling as `tol^(2/3)`, as no
    /// first-order method keeps a global error proportional to the tolerance at a number of steps that
    /// does not grow as `1 / tol`. At the default orders the promise is kept by the higher orders, and
    /// order 1 (the first steps, the restarts after three failed attempts) keeps `h / span`.
    pub(crate) fn first_order_share(&self, h: f64) -> f64 {
        self.step_share(h).sqrt()
    }

    /// The power of `h` in the ratio of a first-order estimate (of order `h²`) to
    /// [`first_order_share`](Self::first_order_share): 1.5 while the share is `√(h / span)`, 2 where it is
    /// bounded.
    pub(crate) fn first_order_error_power(&self, h: f64) -> f64 {
        if self.per_unit_step(h) {
            1.5
        } else {
            2.0
        }
    }

    /// Whether the share of a step of size `h` is `h / span` (not bounded by 1 or by the rounding floor).
    fn per_unit_step(&self, h: f64) -> bool {
        self.per_unit_step_above(h, STEP_FLOOR)
    }

    /// [`per_unit_step`](Self::per_unit_step) above the floor `floor / rtol`.
    fn per_unit_step_above(&self, h: f64, floor: f64) -> bool {
        let share = h / self.span.seconds();
        share < 1.0 && share > floor / self.rtol
    }


    /// The power of `h` in the ratio of a local error estimate of order `h^(k+1)` (`power = k + 1`) to the
    /// step's share of the tolerance: `k` while the share is `h / span`, `k + 1` where it is bounded
    /// (by 1 or by the rounding floor). Step-size selection takes this root of the ratio.
    pub(crate) fn error_power(&self, h: f64, power: usize) -> f64 {
        self.error_power_above(h, power, STEP_FLOOR)
    }

    /// [`error_power`](Self::error_power) with the share's floor `floor / rtol`
    /// ([`step_share_above`](Self::step_share_above)).
    pub(crate) fn error_power_above(&self, h: f64, power: usize, floor: f64) -> f64 {
        if self.per_unit_step_above(h, floor) {
            (power - 1).max(1) as f64
        } else {
            power as f64
        }
    }

    /// The tolerance of the simplified Newton iterations in the norm of a step's share of the tolerance
    /// (the increments' weighted norm divided by `share`, so that the corrector's unresolved part stays
    /// below the local error the step is held to): [`newton_tolerance`](Self::newton_tolerance), but at
    /// least what the increments can resolve at that share, `100 ε / (rtol · share)`.
    pub(crate) fn newton_tolerance_at(&self, share: f64) -> f64 {
        self.newton_tolerance_above(share, NEWTON_FLOOR)
    }

    /// [`newton_tolerance_at`](Self::newton_tolerance_at) with the floor `floor / (rtol · share)` in place
    /// of [`NEWTON_FLOOR`] (`floor` relative to the solution; the BDF's is lower,
    /// [`share_floor`](super::share_floor)).
    pub(crate) fn newton_tolerance_above(&self, share: f64, floor: f64) -> f64 {
        self.newton_tolerance().max(floor / (self.rtol * share))
    }

    /// A Newton increment of [`ROUND_OFF`] of the solution in the norm of a step's share of the
    /// tolerance, `ROUND_OFF / (rtol · share)`: an increment below it is rounding, converged whatever
    /// its rate.
    pub(crate) fn round_off_at(&self, share: f64) -> f64 {
        ROUND_OFF / (self.rtol * share)
    }

    /// The tolerance of the simplified Newton iterations of the implicit methods (the BDF and the
    /// generalized-α method) in the weighted norm of the error test: `√rtol`, at most 0.03, and at least
    /// `10 ε / rtol` (what the increments can resolve).
    pub(crate) fn newton_tolerance(&self) -> f64 {
        (10.0 * f64::EPSILON / self.rtol).max(self.rtol.sqrt().min(0.03))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step's share is its fraction of the span, so that the shares of the steps of one span add up to
    /// 1 whatever their number; it is never above 1 nor below the rounding floor.
    #[test]
    fn the_shares_of_the_steps_of_one_span_add_up_to_one() {
        let tolerances = Tolerances { span: ToleranceSpan::Seconds(2.0), ..Tolerances::new(1e-8, 1e-8) };
        for n in [10, 333, 10_000] {
            let h = 2.0 / n as f64;
            let total: f64 = (0..n).map(|_| tolerances.step_share(h)).sum();
            assert!((total - 1.0).abs() < 1e-12, "{n} steps: {total}");
            assert_eq!(tolerances.error_power(h, 4), 3.0);
        }
        assert_eq!(tolerances.step_share(5.0), 1.0);
        assert_eq!(tolerances.error_power(5.0, 4), 4.0);
        let finest = Tolerances::new(Tolerances::FINEST, Tolerances::FINEST);
        assert_eq!(finest.step_share(1e-9), STEP_FLOOR / Tolerances::FINEST);
        assert_eq!(finest.error_power(1e-9, 4), 4.0);
        let per_step = Tolerances { span: ToleranceSpan::Step, ..Tolerances::default() };
        assert_eq!((per_step.step_share(1e-3), per_step.error_power(1e-3, 4)), (1.0, 4.0));
        assert_eq!((per_step.first_order_share(1e-3), per_step.first_order_error_power(1e-3)), (1.0, 2.0));
    }

    /// A first-order step's share is `√(h / span)`: `N` equal first-order steps over a span spend `√N`
    /// tolerances, and unequal ones no more (Cauchy–Schwarz).
    #[test]
    fn first_order_steps_spend_at_most_the_root_of_their_number() {
        let tolerances = Tolerances { span: ToleranceSpan::Seconds(2.0), ..Tolerances::new(1e-3, 1e-3) };
        for n in [4, 100, 1000] {
            let h = 2.0 / n as f64;
            let total: f64 = (0..n).map(|_| tolerances.first_order_share(h)).sum();
            assert!((total - (n as f64).sqrt()).abs() < 1e-9 * total, "{n} steps: {total}");
            assert_eq!(tolerances.first_order_error_power(h), 1.5);
            let uneven: f64 = (0..n).map(|i| tolerances.first_order_share(h * 2.0 * (i as f64 + 0.5) / n as f64)).sum();
            assert!(uneven <= (n as f64).sqrt(), "{n} uneven steps: {uneven}");
        }
    }

    /// Tolerances finer than the arithmetic allows are raised to the finest, and the message says which
    /// and to what; attainable ones pass unchanged and silently.
    #[test]
    fn tolerances_below_double_precision_are_raised_with_a_message() {
        let (same, message) = Tolerances::new(1e-12, 1e-6).attainable();
        assert_eq!((same, message), (Tolerances::new(1e-12, 1e-6), None));
        let (raised, message) = Tolerances::new(1e-15, 1e-6).attainable();
        assert_eq!((raised.rtol, raised.atol), (1e-12, 1e-6));
        let message = message.unwrap();
        assert!(message.contains("rtol 1e-15 raised to 1e-12") && !message.contains("atol"), "{message}");
        let (raised, message) = Tolerances::new(1e-16, 1e-14).attainable();
        assert_eq!((raised.rtol, raised.atol), (1e-12, 1e-12));
        assert!(message.unwrap().contains("atol 1e-14 raised to 1e-12"));
        assert_eq!(Tolerances::new(1e-6, 0.0).attainable(), (Tolerances::new(1e-6, 0.0), None));
    }
}
