//! The finest tolerance the BDF keeps over the run's span, and the raise of a finer one.
//!
//! Over the run's span (error per unit step, [`ToleranceSpan::Run`]) a step of size `h` of a run of length
//! `T` may make `h / T` of the tolerance, but no step is held below what one step resolves: the floor
//! under a step's share, three times the measured noise of the error estimate, 1.5e-14 to 1e-13 of the
//! solution (`noise_floor.rs`). At 1e-10 the steps of every benchmark of docs/accuracy.md are held to that
//! floor (the 3-D slider-crank's 29,501 steps over 5 s, all of them), so a finer tolerance asks the same
//! steps, and the global error, about the floor times the number of steps, stops falling. Finer asks
//! only let more of the estimates pass as rounding where the constraint Jacobian's condition number
//! dips (the slider-crank's 25, Andrews' squeezer's 147 to 204), whose allowance does not shrink with
//! the tolerance. Measured over the run's span against Adams at 1e-12 (`python3
//! docs/accuracy/work_precision.py --integrators bdf --tolerances 1e-10,1e-11,1e-12 --tolerance-span
//! run`), the global error at 1e-10, 1e-11, 1e-12: slider-crank 2.6e-9, 2.4e-8, 4.8e-8; Andrews'
//! squeezer 3.9e-10, 1.4e-9, 1.1e-9; heavy top 4.0e-11, 4.4e-11, 4.0e-11; flyball governor 1.6e-10,
//! 1.5e-10, 1.5e-10; Bricard 3.2e-11, 1.4e-11, 1.3e-11; rigid pendulum 7.9e-12, 4.6e-12, 4.7e-12. So
//! 1e-10 is the finest tolerance worth asking of the BDF over the run, and a finer one is raised to it
//! with a warning; the Adams method, of orders up to 12, keeps 1e-12 on those cases.
//!
//! The raise applies where the promise is made: error control over the run's span, the default. A span
//! given explicitly (seconds, or `"step"`, each step the whole tolerance) takes the tolerance as given.

use super::{Bdf, ToleranceSpan, Tolerances};

impl Bdf {
    /// The finest relative and absolute tolerance the BDF is asked for over the run's span: 1e-10
    /// (module documentation).
    pub const FINEST_OVER_RUN: f64 = 1e-10;

    /// These tolerances with an `rtol` or `atol` below [`FINEST_OVER_RUN`](Self::FINEST_OVER_RUN) raised to
    /// it over the run's span ([`ToleranceSpan::Run`]), and, when one was raised, what and why, for a
    /// person. Any other span takes them as given. A [`Simulation`](crate::analysis::Simulation) applies
    /// this at its start and reports the message as a warning; [`Bdf::new`] does not.
    pub fn attainable(tolerances: &Tolerances) -> (Tolerances, Option<String>) {
        if tolerances.span != ToleranceSpan::Run {
            return (*tolerances, None);
        }
        let (raised, what) = tolerances.raised_to(Self::FINEST_OVER_RUN);
        let message = what.map(|what| {
            format!(
                "tolerance finer than the BDF keeps over the run: {what}; below {finest:e} its steps are held to \
                 what one step resolves (a few 1e-14 of the solution), so a finer tolerance asks the same steps and \
                 its error no longer falls (on the benchmarks of docs/accuracy.md it is that of {finest:e} or larger); \
                 for a finer tolerance use the Adams method (integrator = \"adams\"), or give the tolerance span \
                 explicitly (tolerance_span = \"step\" or seconds) to take the tolerance as given",
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
    /// at the finest, and with another span, the tolerances are taken as given, silently.
    #[test]
    fn a_tolerance_finer_than_the_bdf_keeps_over_the_run_is_raised() {
        let (raised, message) = Bdf::attainable(&Tolerances::new(1e-12, 1e-6));
        assert_eq!((raised.rtol, raised.atol), (1e-10, 1e-6));
        let message = message.unwrap();
        assert!(message.contains("rtol 1e-12 raised to 1e-10") && !message.contains("atol"), "{message}");
        let finest = Tolerances::new(1e-10, 1e-10);
        assert_eq!(Bdf::attainable(&finest), (finest, None));
        for span in [ToleranceSpan::Step, ToleranceSpan::Seconds(10.0)] {
            let given = Tolerances { span, ..Tolerances::new(1e-12, 1e-12) };
            assert_eq!(Bdf::attainable(&given), (given, None), "{span:?}");
        }
    }
}
