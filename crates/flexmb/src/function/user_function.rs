//! Laws supplied by the caller as code: a force law `f(t, measures)` ([`UserFunction`]) and a driver's
//! motion `f(t), f'(t), f''(t)` ([`UserMotion`]), each a closure with a name for messages — the
//! "user-written subroutine" of Adams (`USER(...)` with `ROUTINE=`) or the `ChFunction` a Chrono user
//! subclasses. A binding (the Python package) wraps a callable of its language in one.
//!
//! A law may fail (a Python exception): it returns `Err(message)`, the first failure is kept with its
//! time, every later evaluation gives NaN without calling the law again, and the simulation stops at
//! the step it is in with [`SimulationFailure::UserLaw`](crate::analysis::SimulationFailure::UserLaw)
//! naming the law, the time and the message. The failure belongs to the law (shared by the model's
//! copies): a new simulation clears it when it starts.

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use super::expression::MAX_VARIABLES;
use crate::model::MeasureId;

/// A force law: `(t, values of the measures it reads, in their order) → value`, or `Err(message)`.
pub type ForceLaw = dyn Fn(f64, &[f64]) -> Result<f64, String> + Send + Sync;

/// A driver's motion: `t → [f(t), f'(t), f''(t)]`, or `Err(message)`. The derivatives are the law's
/// own: the constraint's velocity and acceleration equations use them as given.
pub type MotionLaw = dyn Fn(f64) -> Result<[f64; 3], String> + Send + Sync;

/// The first failure of a user law.
#[derive(Clone, Debug, PartialEq)]
pub struct UserLawFailure {
    /// The law's name.
    pub law: String,
    /// Time of the evaluation that failed (s).
    pub t: f64,
    /// The law's message.
    pub message: String,
}

/// The first failure of one law, set once per simulation.
#[derive(Default)]
struct FailureRecord {
    failed: AtomicBool,
    first: Mutex<Option<UserLawFailure>>,
}

impl FailureRecord {
    /// `Ok(value)` as it is; an error kept (if the first) and NaN.
    fn take<T>(&self, law: &str, t: f64, result: Result<T, String>, nan: T) -> T {
        match result {
            Ok(value) => value,
            Err(message) => {
                if let Ok(mut first) = self.first.lock() {
                    if first.is_none() {
                        *first = Some(UserLawFailure { law: law.to_string(), t, message });
                    }
                }
                self.failed.store(true, Ordering::Release);
                nan
            }
        }
    }

    fn failed(&self) -> bool {
        self.failed.load(Ordering::Acquire)
    }

    fn first(&self) -> Option<UserLawFailure> {
        if !self.failed() {
            return None;
        }
        self.first.lock().ok().and_then(|f| f.clone())
    }

    fn clear(&self) {
        if let Ok(mut first) = self.first.lock() {
            *first = None;
        }
        self.failed.store(false, Ordering::Release);
    }
}

/// A named force law given as a closure of time and of the measures it reads (at most 16, as an
/// expression's variables). Put in a force element through [`Expression::user`](super::Expression::user).
///
/// ```
/// use std::sync::Arc;
/// use flexmb::function::{Expression, UserFunction};
/// use flexmb::model::MeasureId;
///
/// // A proportional-derivative controller on measures 0 (angle) and 1 (rate).
/// let law = UserFunction::new("pd", vec![MeasureId(0), MeasureId(1)], Arc::new(|_t, m: &[f64]| Ok(-50.0 * m[0] - 5.0 * m[1])))
///     .unwrap();
/// let torque = Expression::user(law);
/// assert_eq!(torque.eval(0.0, &[0.1, 2.0]), -15.0);
/// assert_eq!(torque.source(), "user law `pd`");
/// ```
#[derive(Clone)]
pub struct UserFunction {
    name: String,
    measures: Vec<MeasureId>,
    law: Arc<ForceLaw>,
    failure: Arc<FailureRecord>,
}

impl UserFunction {
    /// The law `name` reading `measures`; fails for more than 16 measures.
    pub fn new(name: impl Into<String>, measures: Vec<MeasureId>, law: Arc<ForceLaw>) -> Result<Self, String> {
        let name = name.into();
        if measures.len() > MAX_VARIABLES {
            return Err(format!("user law `{name}` reads {} measures; at most {MAX_VARIABLES} are allowed", measures.len()));
        }
        Ok(Self { name, measures, law, failure: Arc::default() })
    }

    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The measures it reads, in the order of the values it is given.
    pub fn measures(&self) -> &[MeasureId] {
        &self.measures
    }

    /// The law at `t` with `measures` the values of all the model's measures (NaN once it has failed).
    #[inline]
    pub fn eval(&self, t: f64, measures: &[f64]) -> f64 {
        if self.failure.failed() {
            return f64::NAN;
        }
        let mut values = [0.0; MAX_VARIABLES];
        for (slot, m) in values.iter_mut().zip(&self.measures) {
            *slot = measures.get(m.0).copied().unwrap_or(f64::NAN);
        }
        let result = (self.law)(t, &values[..self.measures.len()]);
        self.failure.take(&self.name, t, result, f64::NAN)
    }

    /// The first failure since the last [`clear_failure`](Self::clear_failure).
    pub fn failure(&self) -> Option<UserLawFailure> {
        self.failure.first()
    }

    /// Forgets a failure (a new simulation starts).
    pub fn clear_failure(&self) {
        self.failure.clear();
    }
}

impl fmt::Debug for UserFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("UserFunction").field("name", &self.name).field("measures", &self.measures).finish_non_exhaustive()
    }
}

/// A named driver motion given as a closure of time returning the value and its first two
/// derivatives. Put in a driver through [`TimeFunction::user`](super::TimeFunction::user).
#[derive(Clone)]
pub struct UserMotion {
    name: String,
    law: Arc<MotionLaw>,
    failure: Arc<FailureRecord>,
}

impl UserMotion {
    /// The motion `name`.
    pub fn new(name: impl Into<String>, law: Arc<MotionLaw>) -> Self {
        Self { name: name.into(), law, failure: Arc::default() }
    }

    /// The motion's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// `[f(t), f'(t), f''(t)]` (NaN once it has failed).
    #[inline]
    pub fn eval(&self, t: f64) -> [f64; 3] {
        if self.failure.failed() {
            return [f64::NAN; 3];
        }
        let result = (self.law)(t);
        self.failure.take(&self.name, t, result, [f64::NAN; 3])
    }

    /// The first failure since the last [`clear_failure`](Self::clear_failure).
    pub fn failure(&self) -> Option<UserLawFailure> {
        self.failure.first()
    }

    /// Forgets a failure (a new simulation starts).
    pub fn clear_failure(&self) {
        self.failure.clear();
    }
}

impl fmt::Debug for UserMotion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("UserMotion").field("name", &self.name).finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_failure_is_kept_and_later_evaluations_are_nan() {
        let law = UserFunction::new(
            "brake",
            vec![MeasureId(1)],
            Arc::new(|t, m: &[f64]| if t < 1.0 { Ok(2.0 * m[0]) } else { Err(format!("no brake at {t}")) }),
        )
        .unwrap();
        assert_eq!(law.eval(0.5, &[7.0, 3.0]), 6.0);
        assert!(law.failure().is_none());
        assert!(law.eval(1.5, &[7.0, 3.0]).is_nan());
        assert!(law.eval(0.5, &[7.0, 3.0]).is_nan());
        let failure = law.failure().unwrap();
        assert_eq!((failure.law.as_str(), failure.t, failure.message.as_str()), ("brake", 1.5, "no brake at 1.5"));
        law.clear_failure();
        assert_eq!(law.eval(0.5, &[7.0, 3.0]), 6.0);
    }

    #[test]
    fn a_motion_gives_its_own_derivatives() {
        let motion = UserMotion::new("crank", Arc::new(|t| Ok([t.sin(), t.cos(), -t.sin()])));
        assert_eq!(motion.eval(0.3), [0.3_f64.sin(), 0.3_f64.cos(), -0.3_f64.sin()]);
    }

    #[test]
    fn more_than_sixteen_measures_are_refused() {
        let err = UserFunction::new("wide", (0..17).map(MeasureId).collect(), Arc::new(|_, _: &[f64]| Ok(0.0))).unwrap_err();
        assert!(err.contains("reads 17 measures"), "{err}");
    }
}
