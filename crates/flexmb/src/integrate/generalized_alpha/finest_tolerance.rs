//! The finest tolerance the generalized-α method keeps over the run's span, and the raise of a finer one.
//!
//! Over the run's span (error per unit step, [`ToleranceSpan::Run`]) a step of size `h` of a run of
//! length `T` may make `h / T` of the tolerance. The method's local error grows as `h³`, so its steps
//! shrink as `tol^(1/2)` and their number grows as `tol^(−1/2)`; no step, however, is held below what one
//! step resolves, 1e-13 of the solution (the share's floor `1e-13 / rtol`). Where the steps reach that
//! floor every tolerance asks the same steps, and the global error, about the floor times the number of
//! steps, stops falling. Measured over the run's span against Adams at 1e-12 (docs/accuracy.md,
//! *Generalized-α over the run's span*), E/tol at rtol = atol = 1e-7 and 1e-8: rigid pendulum 0.97 and
//! 1.3, A04 Bricard 1.4 and 2.3, A05 flyball governor 0.92 and 2.5, the 3-D slider-crank 1.0 and 8.2,
//! the A02 double four-bar through its ten singular positions 5.4 and 6.3, but Andrews' squeezer 4.5 and
//! 58 (its error about 5e-7 at every rtol from 1e-7 to 1e-9). With the floor 1e-12 of before, every
//! tolerance from 1e-8 to 1e-10 gave the same steps and the same error on each case (1e-7 to 1.2e-6
//! relative), and the four-bar was 12 tolerances off at 1e-7. So 1e-7 is the finest tolerance it keeps
//! on every case measured, and a finer one is raised to it with a warning; the BDF and the Adams method,
//! of higher order, keep finer ones.
//!
//! The raise applies where the promise is made: error control over the run's span, the default. A span
//! given explicitly (seconds, or `"step"`, each step the whole tolerance) or a fixed step takes the
//! tolerance as it is given: that is the way to ask the method for steps held that finely anyway.

use super::GeneralizedAlpha;
use crate::integrate::{GeneralizedAlphaConfig, ToleranceSpan, Tolerances};

impl GeneralizedAlpha {
    /// The finest relative and absolute tolerance the method keeps over the run's span: 1e-7 (module
    /// documentation).
    pub const FINEST_OVER_RUN: f64 = 1e-7;

    /// These tolerances with an `rtol` or `atol` below [`FINEST_OVER_RUN`](Self::FINEST_OVER_RUN) raised to
    /// it where the method keeps its promise over the run's span (error control, [`ToleranceSpan::Run`]),
    /// and, when one was raised, what and why, for a person. Any other span, and a fixed step, take them
    /// as given. A [`Simulation`](crate::analysis::Simulation) applies this at its start and reports the
    /// message as a warning; [`GeneralizedAlpha::new`] does not.
    pub fn attainable(tolerances: &Tolerances, config: &GeneralizedAlphaConfig) -> (Tolerances, Option<String>) {
        if config.fixed_step.is_some() || tolerances.span != ToleranceSpan::Run {
            return (*tolerances, None);
        }
        let (raised, what) = tolerances.raised_to(Self::FINEST_OVER_RUN);
        let message = what.map(|what| {
            format!(
                "tolerance finer than the generalized-α method keeps over the run: {what}; a second-order method's \
                 steps grow as tol^(-1/2), and below {finest:e} they reach what one step resolves (1e-13 of the \
                 solution) and its error no longer falls in proportion on every model; for a finer tolerance use \
                 the BDF or the Adams method, or give the tolerance span explicitly (tolerance_span = \"step\" or \
                 seconds) to take the tolerance as given",
                finest = Self::FINEST_OVER_RUN
            )
        });
        (raised, message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Over the run's span a tolerance below the finest is raised and the message says which and to what;
    /// at the finest, with another span or with a fixed step the tolerances are taken as given, silently.
    #[test]
    fn a_tolerance_finer_than_the_method_keeps_over_the_run_is_raised() {
        let config = GeneralizedAlphaConfig::default();
        let (raised, message) = GeneralizedAlpha::attainable(&Tolerances::new(1e-10, 1e-6), &config);
        assert_eq!((raised.rtol, raised.atol), (1e-7, 1e-6));
        let message = message.unwrap();
        assert!(message.contains("rtol 1e-10 raised to 1e-7") && !message.contains("atol"), "{message}");
        let finest = Tolerances::new(1e-7, 1e-7);
        assert_eq!(GeneralizedAlpha::attainable(&finest, &config), (finest, None));
        for span in [ToleranceSpan::Step, ToleranceSpan::Seconds(10.0)] {
            let given = Tolerances { span, ..Tolerances::new(1e-10, 1e-10) };
            assert_eq!(GeneralizedAlpha::attainable(&given, &config), (given, None), "{span:?}");
        }
        let fixed = GeneralizedAlphaConfig { fixed_step: Some(1e-3), ..config };
        let given = Tolerances::new(1e-10, 1e-10);
        assert_eq!(GeneralizedAlpha::attainable(&given, &fixed), (given, None));
    }
}
