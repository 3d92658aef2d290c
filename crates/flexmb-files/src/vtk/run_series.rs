//! `flexmb run --vtk DIR`: a ParaView time series written as the run proceeds. `DIR/STEM.pvd` indexes
//! one `.vtu` file per block and frame in `DIR/STEM/` (STEM the model file's stem): the blocks are the
//! bodies and joints (see [`run_parts`](super::run_parts)), named in the `.pvd` so that ParaView shows
//! a multiblock with the bodies' and joints' names. Frames are taken at the output times that are
//! multiples of the frame interval (`--vtk-step`, `[simulation] vtk_step`, else every output time);
//! the `.pvd` is complete after each frame, so a run that fails or is interrupted leaves a series that
//! ParaView opens up to its last frame.

use std::path::{Path, PathBuf};

use flexmb::analysis::OutputFrame;
use flexmb::Model;

use super::pvd::{PvdEntry, PvdFile};
use super::run_parts::{parts, Part};
use super::write_vtu;
use crate::model_file::LoadedModel;

/// A run's ParaView series being written.
pub struct RunSeries<'a> {
    model: &'a Model,
    /// The directory of the `.pvd` file.
    dir: PathBuf,
    /// The folder of the `.vtu` files, relative to `dir`.
    folder: String,
    pvd: PvdFile,
    parts: Vec<Part>,
    /// Interval between frames (s), a whole multiple of `output_step`.
    step: f64,
    output_step: f64,
    frames: usize,
    /// The first write that failed; no frame is written after it.
    error: Option<String>,
}

/// What a finished series wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct SeriesWritten {
    /// The `.pvd` file.
    pub pvd: PathBuf,
    /// Frames written.
    pub frames: usize,
    /// Blocks per frame: bodies and joints.
    pub blocks: usize,
}

/// When a run's ParaView frames are taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeriesTimes {
    /// Interval between frames (s; `None`: the output step), a whole multiple of `output_step`.
    pub step: Option<f64>,
    /// Interval between output times (s).
    pub output_step: f64,
    /// The run's end time (s).
    pub t_end: f64,
}

impl<'a> RunSeries<'a> {
    /// Starts `DIR/STEM.pvd` for the model `loaded`, with frames at `times`, of which there may be no
    /// more than `max_frames`. The `.vtu` files an earlier run left in `DIR/STEM/` are removed.
    pub fn create(
        dir: &Path,
        stem: &str,
        loaded: &'a LoadedModel,
        times: SeriesTimes,
        max_frames: u64,
    ) -> Result<Self, String> {
        let output_step = times.output_step;
        let step = frame_step(times.step, output_step)?;
        crate::output_limits::check_vtk_frames(times.t_end, step, max_frames)?;
        let folder = dir.join(stem);
        std::fs::create_dir_all(&folder).map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
        remove_old_frames(&folder)?;
        let pvd_path = dir.join(format!("{stem}.pvd"));
        let pvd = PvdFile::create(&pvd_path).map_err(|e| format!("cannot write {}: {e}", pvd_path.display()))?;
        Ok(Self {
            model: &loaded.model,
            dir: dir.to_path_buf(),
            folder: stem.to_string(),
            pvd,
            parts: parts(loaded),
            step,
            output_step,
            frames: 0,
            error: None,
        })
    }

    /// Writes a frame if `frame.t` is a frame time; a failure is kept for [`finish`](Self::finish).
    pub fn observe(&mut self, frame: &OutputFrame) {
        if self.error.is_some() || !self.is_frame_time(frame.t) {
            return;
        }
        if let Err(e) = self.write_frame(frame) {
            self.error = Some(e);
        }
    }

    /// What was written, or the first write that failed.
    pub fn finish(self) -> Result<SeriesWritten, String> {
        match self.error {
            Some(e) => Err(e),
            None => {
                Ok(SeriesWritten { pvd: self.pvd.path().to_path_buf(), frames: self.frames, blocks: self.parts.len() })
            }
        }
    }

    /// Whether `t` is a whole multiple of the frame interval (to within a millionth of an output step).
    fn is_frame_time(&self, t: f64) -> bool {
        (t - (t / self.step).round() * self.step).abs() <= 1e-6 * self.output_step
    }

    /// Every block's `.vtu` file, then their entries in the `.pvd`.
    fn write_frame(&mut self, frame: &OutputFrame) -> Result<(), String> {
        let mut files = Vec::with_capacity(self.parts.len());
        for part in &mut self.parts {
            let file = format!("{}/{}_{:06}.vtu", self.folder, part.file_stem, self.frames);
            let piece = part.piece(self.model, frame.q, frame.v);
            let title = format!("{}: {} at t = {} s", self.model.name(), part.name, frame.t);
            write_vtu(&self.dir.join(&file), title, piece)?;
            files.push(file);
        }
        let entries: Vec<PvdEntry> = self
            .parts
            .iter()
            .zip(&files)
            .enumerate()
            .map(|(k, (part, file))| PvdEntry { time: frame.t, part: k, name: &part.name, file })
            .collect();
        self.pvd.append(&entries).map_err(|e| format!("cannot write {}: {e}", self.pvd.path().display()))?;
        self.frames += 1;
        Ok(())
    }
}

/// The frame interval: `step`, else `output_step`; a whole multiple of `output_step`.
fn frame_step(step: Option<f64>, output_step: f64) -> Result<f64, String> {
    let Some(step) = step else { return Ok(output_step) };
    let what = "the interval between ParaView frames (--vtk-step, or vtk_step in [simulation])";
    if !(step > 0.0 && step.is_finite()) {
        return Err(format!("{what} must be a positive number, got {step}"));
    }
    let n = (step / output_step).round();
    if n < 1.0 || (step - n * output_step).abs() > 1e-6 * output_step {
        return Err(format!(
            "{what} must be a whole multiple of the output step {output_step} s, since frames are written at \
             output times; got {step} s"
        ));
    }
    Ok(n * output_step)
}

/// Removes the `.vtu` files in `folder`.
pub(super) fn remove_old_frames(folder: &Path) -> Result<(), String> {
    let entries = std::fs::read_dir(folder).map_err(|e| format!("cannot read {}: {e}", folder.display()))?;
    for entry in entries.flatten() {
        let path = entry.path();
        if path.extension().is_some_and(|e| e == "vtu") {
            std::fs::remove_file(&path).map_err(|e| format!("cannot remove {}: {e}", path.display()))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::frame_step;

    #[test]
    fn the_frame_step_is_a_whole_multiple_of_the_output_step() {
        assert_eq!(frame_step(None, 0.002), Ok(0.002));
        assert!((frame_step(Some(0.01), 0.002).unwrap() - 0.01).abs() < 1e-15);
        for bad in [0.003, 0.001, 0.0, -0.01, f64::NAN] {
            let e = frame_step(Some(bad), 0.002).unwrap_err();
            assert!(e.contains("--vtk-step"), "{e}");
        }
    }
}
