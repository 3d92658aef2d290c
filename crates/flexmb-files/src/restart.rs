//! Restart files: a simulation's checkpoint ([`SimulationCheckpoint`]) saved as JSON at the end of a
//! run or at its interruption, and read back to resume the run (`flexmb run --save-state`,
//! `--resume`).
//!
//! A resumed run writes the output rows after the checkpoint's time only, so that the first part's
//! CSV followed by the second's (without its header) equals the CSV of one run; its JSON summary
//! holds the counters of the whole run (the checkpoint carries those of the first part).

use std::path::Path;
use std::sync::Arc;

use flexmb::analysis::{Simulation, SimulationCheckpoint, SimulationSettings};
use flexmb::Model;

use crate::results::ResultFileError;

/// Where a recorded run starts and whether its final state is saved.
#[derive(Clone, Copy, Debug, Default)]
pub struct Restart<'a> {
    /// Continue from the checkpoint in this file (written by [`save_checkpoint`]) instead of the
    /// model's initial state. It must be of the same model and method; the end time may be later
    /// than the checkpoint's time, not earlier.
    pub resume: Option<&'a Path>,
    /// Write the simulation's checkpoint to this file at the end of the run or at its interruption.
    /// Nothing is written after a failure: a failed simulation cannot be checkpointed.
    pub save_state: Option<&'a Path>,
    /// Pause the run at the first step at or after this time (s), as an interruption: steps are not
    /// shortened to land on it, so a run paused, saved and resumed makes the steps and outputs of one
    /// run to the end time, to round-off. (A run whose end time is the split time shortens its last step
    /// to land on it, and its continuation differs within the integration tolerance.)
    pub pause_at: Option<f64>,
}

/// Writes `checkpoint` to `path` as JSON.
pub fn save_checkpoint(path: &Path, checkpoint: &SimulationCheckpoint) -> Result<(), ResultFileError> {
    let text = serde_json::to_string(checkpoint).map_err(|e| ResultFileError(format!("cannot save the state to {}: {e}", path.display())))?;
    std::fs::write(path, text + "\n").map_err(|e| ResultFileError(format!("cannot write {}: {e}", path.display())))
}

/// Reads a checkpoint written by [`save_checkpoint`]; an unreadable file or one that is not a
/// checkpoint is an error naming `path`.
pub fn read_checkpoint(path: &Path) -> Result<SimulationCheckpoint, ResultFileError> {
    let text = std::fs::read_to_string(path).map_err(|e| ResultFileError(format!("cannot read {}: {e}", path.display())))?;
    serde_json::from_str(&text).map_err(|e| {
        ResultFileError(format!("{}: not a simulation checkpoint written by `flexmb run --save-state` ({e})", path.display()))
    })
}

/// A simulation resumed from the checkpoint in `file`, and the checkpoint's time; a checkpoint the
/// engine refuses (of another model or method) or one after the end time is an error naming `file`.
pub fn resume_simulation(model: &Arc<Model>, settings: &SimulationSettings, file: &Path) -> Result<(Simulation, f64), ResultFileError> {
    let checkpoint = read_checkpoint(file)?;
    if checkpoint.t > settings.t_end {
        return Err(ResultFileError(format!(
            "{}: the checkpoint is at t = {} s, after the end time {} s",
            file.display(),
            checkpoint.t,
            settings.t_end
        )));
    }
    let simulation = Simulation::resume(Arc::clone(model), *settings, &checkpoint)
        .map_err(|e| ResultFileError(format!("{}: {e}", file.display())))?;
    Ok((simulation, checkpoint.t))
}
