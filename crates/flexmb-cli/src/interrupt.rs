//! SIGINT (Ctrl-C) and SIGTERM during `flexmb run`: the first one asks the simulation to stop after its
//! current step, so that the CSV ends on a whole row, the JSON summary is written with what the run
//! did, and the ParaView series is closed; a second one ends the program at once (the signal's
//! default action). Caught with `signal-hook`'s flag handlers, which only store to atomics.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use signal_hook::consts::signal::{SIGINT, SIGPIPE, SIGTERM};

/// Makes a closed standard output (`flexmb check M | head`) end the program as it ends other Unix tools,
/// by SIGPIPE's default action, instead of a panic ("failed printing to stdout: Broken pipe") at the next
/// line printed: the Rust runtime ignores SIGPIPE, and the handler registered here performs the
/// default action when it arrives. Writing files raises no SIGPIPE.
pub fn end_on_closed_pipe() -> std::io::Result<()> {
    signal_hook::flag::register_conditional_default(SIGPIPE, Arc::new(AtomicBool::new(true)))?;
    Ok(())
}

/// A termination signal that stopped a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signal {
    Interrupt,
    Terminate,
}

impl Signal {
    /// `SIGINT` or `SIGTERM`.
    pub fn name(self) -> &'static str {
        match self {
            Signal::Interrupt => "SIGINT",
            Signal::Terminate => "SIGTERM",
        }
    }

    /// The conventional exit status of a program ended by the signal: 128 + its number (130, 143).
    pub fn exit_status(self) -> u8 {
        match self {
            Signal::Interrupt => 128 + SIGINT as u8,
            Signal::Terminate => 128 + SIGTERM as u8,
        }
    }
}

/// Whether SIGINT or SIGTERM has arrived since [`StopSignal::catch`].
#[derive(Clone, Debug)]
pub struct StopSignal {
    /// The number of the last signal that arrived, 0 before any.
    received: Arc<AtomicUsize>,
}

impl StopSignal {
    /// Catches SIGINT and SIGTERM from now on, for the rest of the process.
    pub fn catch() -> std::io::Result<Self> {
        let received = Arc::new(AtomicUsize::new(0));
        let armed = Arc::new(AtomicBool::new(false));
        for signal in [SIGINT, SIGTERM] {
            // The default action first: it runs only once `armed` is set, i.e. on a second signal.
            signal_hook::flag::register_conditional_default(signal, Arc::clone(&armed))?;
            signal_hook::flag::register_usize(signal, Arc::clone(&received), signal as usize)?;
            signal_hook::flag::register(signal, Arc::clone(&armed))?;
        }
        Ok(Self { received })
    }

    /// The signal that arrived, if any.
    pub fn received(&self) -> Option<Signal> {
        match self.received.load(Ordering::SeqCst) {
            s if s == SIGINT as usize => Some(Signal::Interrupt),
            s if s == SIGTERM as usize => Some(Signal::Terminate),
            _ => None,
        }
    }
}
