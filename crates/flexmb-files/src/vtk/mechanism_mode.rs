//! The animation of one mode of the whole mechanism for ParaView: a `.pvd` series over one period,
//! [`FRAMES_PER_PERIOD`] frames at the phases `φ_k = 2πk/N`, of every body and joint drawn as a run's
//! series draws them (`run_parts`), each frame at the positions
//!
//! ```text
//! q_k = q ⊕ c Re((ψ_re + i ψ_im) e^{iφ_k}) = displaced_positions(q, c (ψ_re cos φ_k − ψ_im sin φ_k))
//! ```
//!
//! with `q` the operating point and `ψ` the mode in velocity coordinates (per body a translation, a
//! rotation vector in body axes and the modal coordinates, as
//! [`flexmb::analysis::displaced_positions`] takes them). A real shape swings
//! through `q` and back; a complex one (a gyroscopic mode) carries each point round an ellipse, in the
//! sense of its whirl. The series' time is the fraction of the period, `k/N`, as in
//! [`write_mode_animations`](super::write_mode_animations), so that several modes play side by side.
//!
//! Point data as in a run's series, except that `displacement` is measured from the point's position
//! at `q` (not from the first frame) and `velocity` is zero (the operating point's motion is not drawn).
//!
//! The scale `c` makes the largest displacement of any point drawn over the period, to first order,
//! [`AMPLITUDE_FRACTION`] of the mechanism's size (the diagonal of the box around the points drawn at
//! `q`), as a single body's mode animation does. A shape that moves no point drawn gets
//! `c = AMPLITUDE_FRACTION / max |ψ_k|`; a zero shape `c = 0`, every frame at `q`.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use flexmb::analysis::displaced_positions;
use flexmb::math::Vec3;
use flexmb::Model;

use super::pvd::{file_safe, PvdEntry, PvdFile};
use super::run_parts::{model_parts, parts, Part};
use super::run_series::remove_old_frames;
use super::{write_vtu, AMPLITUDE_FRACTION, FRAMES_PER_PERIOD};
use crate::model_file::LoadedModel;

/// What a mechanism's mode animation wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct MechanismModeAnimation {
    /// The `.pvd` file: `DIR/MODEL_mode_LABEL.pvd`, its frames in `DIR/MODEL_mode_LABEL/`.
    pub pvd: PathBuf,
    /// `c`: frame `k` is at `q ⊕ c Re(ψ e^{2πik/N})`.
    pub scale: f64,
    /// Frames over the period.
    pub frames: usize,
    /// Blocks per frame: bodies and joints.
    pub blocks: usize,
}

/// A mode of the mechanism at its operating point.
#[derive(Clone, Copy)]
struct MechanismMode<'a> {
    q: &'a [f64],
    shape_re: &'a [f64],
    shape_im: &'a [f64],
}

/// Writes the animation of the mode `shape_re + i shape_im` (velocity coordinates) of `model` about the
/// positions `q`, labelled `label`, into `dir`: the `.pvd` file, the scale and the counts. Rigid
/// bodies are drawn as their frames' glyphs and flexible bodies as their nodes, which is all a
/// [`Model`] knows of their drawing; [`loaded_mechanism_mode_animation`] draws a model file's shapes
/// and meshes.
pub fn mechanism_mode_animation(
    model: &Model,
    q: &[f64],
    shape_re: &[f64],
    shape_im: &[f64],
    label: &str,
    dir: &Path,
) -> Result<MechanismModeAnimation, String> {
    animate(model, model_parts(model), MechanismMode { q, shape_re, shape_im }, label, dir)
}

/// The animation of a model read from a file, drawn as `flexmb run --vtk` draws it: rigid bodies by
/// their `shape`, flexible bodies by their FE meshes deformed.
pub fn loaded_mechanism_mode_animation(
    loaded: &LoadedModel,
    q: &[f64],
    shape_re: &[f64],
    shape_im: &[f64],
    label: &str,
    dir: &Path,
) -> Result<MechanismModeAnimation, String> {
    animate(&loaded.model, parts(loaded), MechanismMode { q, shape_re, shape_im }, label, dir)
}

fn animate(
    model: &Model,
    mut parts: Vec<Part>,
    mode: MechanismMode,
    label: &str,
    dir: &Path,
) -> Result<MechanismModeAnimation, String> {
    check_sizes(model, mode, label)?;
    let scale = animation_scale(model, &parts, mode);
    let stem = format!("{}_mode_{}", file_safe(model.name()), file_safe(label));
    let folder = dir.join(&stem);
    std::fs::create_dir_all(&folder).map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
    remove_old_frames(&folder)?;
    let pvd_path = dir.join(format!("{stem}.pvd"));
    let mut pvd = PvdFile::create(&pvd_path).map_err(|e| format!("cannot write {}: {e}", pvd_path.display()))?;
    for part in &mut parts {
        part.measure_displacement_from(model, mode.q);
    }
    let at_rest = vec![0.0; model.layout().nv];
    for k in 0..FRAMES_PER_PERIOD {
        let phase = k as f64 / FRAMES_PER_PERIOD as f64;
        let q_k =
            displaced_positions(model, mode.q, &displacement(mode, scale, TAU * phase)).map_err(|e| e.to_string())?;
        let mut files = Vec::with_capacity(parts.len());
        for part in &mut parts {
            let file = format!("{stem}/{}_{k:02}.vtu", part.file_stem);
            let title = format!("{}: mode {label}, {} at phase {phase} of its period", model.name(), part.name);
            write_vtu(&dir.join(&file), title, part.piece(model, &q_k, &at_rest))?;
            files.push(file);
        }
        let entries: Vec<PvdEntry> = parts
            .iter()
            .zip(&files)
            .enumerate()
            .map(|(j, (part, file))| PvdEntry { time: phase, part: j, name: &part.name, file })
            .collect();
        pvd.append(&entries).map_err(|e| format!("cannot write {}: {e}", pvd_path.display()))?;
    }
    Ok(MechanismModeAnimation { pvd: pvd_path, scale, frames: FRAMES_PER_PERIOD, blocks: parts.len() })
}

/// `c Re((ψ_re + i ψ_im) e^{iφ}) = c (ψ_re cos φ − ψ_im sin φ)`.
fn displacement(mode: MechanismMode, scale: f64, phi: f64) -> Vec<f64> {
    let (cos, sin) = (phi.cos(), phi.sin());
    mode.shape_re.iter().zip(mode.shape_im).map(|(re, im)| scale * (re * cos - im * sin)).collect()
}

/// An error, naming the mode, unless the operating point has the model's position size, both parts of
/// the shape its velocity size, and every entry of the shape is finite.
fn check_sizes(model: &Model, mode: MechanismMode, label: &str) -> Result<(), String> {
    let (nq, nv) = (model.layout().nq, model.layout().nv);
    if mode.q.len() != nq {
        return Err(format!("mode {label}: the operating point has {} positions; the model has {nq}", mode.q.len()));
    }
    for (part, values) in [("real", mode.shape_re), ("imaginary", mode.shape_im)] {
        if values.len() != nv {
            return Err(format!(
                "mode {label}: the {part} part of the shape has {} entries; the model has {nv} velocity coordinates",
                values.len()
            ));
        }
        if let Some(k) = values.iter().position(|x| !x.is_finite()) {
            return Err(format!("mode {label}: entry {k} of the {part} part of the shape is {}", values[k]));
        }
    }
    Ok(())
}

/// `c` (see the module's documentation).
fn animation_scale(model: &Model, parts: &[Part], mode: MechanismMode) -> f64 {
    let largest_entry = mode.shape_re.iter().chain(mode.shape_im).fold(0.0, |m: f64, x| m.max(x.abs()));
    if largest_entry == 0.0 {
        return 0.0;
    }
    let at_rest = vec![0.0; model.layout().nv];
    let mut size_box: Option<(Vec3, Vec3)> = None;
    let mut largest: f64 = 0.0;
    for part in parts {
        let points = part.motions(model, mode.q, &at_rest);
        // The first-order displacement of each point along ψ_re and ψ_im: its velocity for v = ψ.
        let along_re = part.motions(model, mode.q, mode.shape_re);
        let along_im = part.motions(model, mode.q, mode.shape_im);
        for ((p, re), im) in points.iter().zip(&along_re).zip(&along_im) {
            let (low, high) = size_box.get_or_insert((p.position, p.position));
            (*low, *high) = (low.inf(&p.position), high.sup(&p.position));
            for k in 0..FRAMES_PER_PERIOD {
                let phi = TAU * k as f64 / FRAMES_PER_PERIOD as f64;
                largest = largest.max((re.velocity * phi.cos() - im.velocity * phi.sin()).norm());
            }
        }
    }
    let size = size_box.map_or(0.0, |(low, high)| (high - low).norm());
    let size = if size > 0.0 { size } else { 1.0 };
    if largest > 1e-12 * largest_entry * size {
        AMPLITUDE_FRACTION * size / largest
    } else {
        AMPLITUDE_FRACTION / largest_entry
    }
}
