//! The span of simulated time whose steps together may make an error of the tolerance (error per unit
//! step, docs/accuracy.md).

/// Over which span of simulated time the local errors of the steps may add up to the tolerance
/// ([`Tolerances::span`](super::Tolerances::span)). A step of size `h` is held to the share `h / span`
/// of the tolerance (error per unit step, Shampine, *Numerical Solution of Ordinary Differential
/// Equations*, 1994, §1.5), so that the local errors of the steps of one span add up to at most the
/// tolerance however many steps it takes, and the global error falls in proportion to the tolerance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ToleranceSpan {
    /// The length of the run, `t_end`: the local errors of the whole run add up to at most
    /// the tolerance, so that the global error over the run is a small multiple of it however long the
    /// run (on the peer models 0.02 to 4.4 tolerances from 1e-3 to 1e-8, docs/accuracy.md). A
    /// [`Simulation`](crate::analysis::Simulation) makes it its `t_end` (a resumed one, the resumed run's
    /// `t_end`); a method started directly, which knows no run, takes 1 s. The default.
    #[default]
    Run,
    /// A fixed span (s, positive): the global error grows with the number of spans in the run
    /// (`tolerance_span = 1`: the 3-D slider-crank over 5 s 13 to 20 tolerances).
    Seconds(f64),
    /// Each step may make the whole tolerance (the classical error per step, DASSL's and STEP's test):
    /// the global error grows with the number of steps, and that number grows as the tolerance falls
    /// (the 3-D slider-crank over 5 s 360 to 6,500 tolerances).
    Step,
}

/// A method started directly, outside a run, takes the span [`ToleranceSpan::Run`] to be this (s).
const SPAN_WITHOUT_RUN: f64 = 1.0;

impl ToleranceSpan {
    /// This span with [`Run`](Self::Run) made the run's length `length` (s).
    pub fn over_run(self, length: f64) -> Self {
        match self {
            Self::Run => Self::Seconds(length),
            other => other,
        }
    }

    /// The span in seconds: infinite for [`Step`](Self::Step), 1 s for [`Run`](Self::Run) not made a
    /// run's length ([`over_run`](Self::over_run)).
    pub fn seconds(self) -> f64 {
        match self {
            Self::Run => SPAN_WITHOUT_RUN,
            Self::Seconds(span) => span,
            Self::Step => f64::INFINITY,
        }
    }

    /// Checks that a fixed span is a positive number.
    pub(crate) fn validate(self) -> Result<(), String> {
        match self {
            Self::Seconds(span) if span.is_nan() || span <= 0.0 => Err(format!(
                "the tolerance span must be a positive number of seconds, got {span}"
            )),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The run's span becomes the run's length; fixed spans and the span of one step stay what they are;
    /// the default is the run's span.
    #[test]
    fn the_runs_span_is_its_length() {
        assert_eq!(ToleranceSpan::default(), ToleranceSpan::Run);
        assert_eq!(ToleranceSpan::Run.over_run(5.0), ToleranceSpan::Seconds(5.0));
        assert_eq!(ToleranceSpan::Seconds(1.0).over_run(5.0), ToleranceSpan::Seconds(1.0));
        assert_eq!(ToleranceSpan::Step.over_run(5.0).seconds(), f64::INFINITY);
        assert_eq!(ToleranceSpan::Run.seconds(), 1.0);
        assert!(ToleranceSpan::Seconds(0.0).validate().is_err() && ToleranceSpan::Seconds(f64::NAN).validate().is_err());
        assert!(ToleranceSpan::Seconds(f64::INFINITY).validate().is_ok());
    }
}
