//! Ctrl-C during native work: the step loop runs without the GIL, and every 50 ms of it the GIL is
//! taken back for a moment to let Python run its signal handlers (`Python::check_signals`). The
//! exception a handler raises (`KeyboardInterrupt` for Ctrl-C) stops the run after its current step,
//! as SIGINT stops `flexmb run`, and is raised once the run has returned.

use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

use pyo3::{PyErr, Python};

/// How often the step loop lets Python handle its signals.
const SIGNAL_CHECK_INTERVAL: Duration = Duration::from_millis(50);

/// The interruption hook of one run: asked after every accepted step, it answers with a reason once a
/// Python signal handler has raised.
pub struct SignalWatch {
    last_check: Cell<Instant>,
    raised: RefCell<Option<PyErr>>,
}

impl SignalWatch {
    /// A watch whose first check comes one interval from now.
    pub fn new() -> Self {
        Self { last_check: Cell::new(Instant::now()), raised: RefCell::new(None) }
    }

    /// The reason to stop, if a signal handler raised since the last check (the hook of
    /// `Simulation::run` and `advance_to_interruptible`).
    pub fn interrupted(&self) -> Option<String> {
        if self.raised.borrow().is_some() {
            return Some("SIGINT".to_string());
        }
        if self.last_check.get().elapsed() < SIGNAL_CHECK_INTERVAL {
            return None;
        }
        self.last_check.set(Instant::now());
        Python::attach(|py| {
            let error = py.check_signals().err()?;
            let reason = if error.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
                "SIGINT".to_string()
            } else {
                format!("a Python signal handler raised {}", error.value(py))
            };
            *self.raised.borrow_mut() = Some(error);
            Some(reason)
        })
    }

    /// The exception a signal handler raised, if one did.
    pub fn into_raised(self) -> Option<PyErr> {
        self.raised.into_inner()
    }
}
