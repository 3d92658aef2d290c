//! Mode animations for ParaView: per mode, a `.pvd` series of the body oscillating in that mode over one
//! period, `FRAMES_PER_PERIOD` frames with the node positions `s̄ + c sin(2π k/N) ψ` (`ψ` the mode's
//! translation). The scale `c` makes the largest displacement `AMPLITUDE_FRACTION` of the body's size
//! (the diagonal of the box around its nodes). The series' time is the fraction of the period,
//! `k/N`, the same for every mode, so that several modes play side by side.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use flexmb::math::Vec3;
use flexmb_fem::reduction::FlexibleBody;
use vtkio::model::{Attribute, Attributes};

use super::pvd::{file_safe, PvdEntry, PvdFile};
use super::{element_cells, piece, write_vtu};

/// Frames over one period of a mode.
pub const FRAMES_PER_PERIOD: usize = 24;
/// The largest displacement of an animated mode, as a fraction of the body's size.
pub const AMPLITUDE_FRACTION: f64 = 0.1;

/// One mode's animation.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeAnimation {
    /// The mode's label (`N1`, `O2`, …).
    pub label: String,
    pub pvd: PathBuf,
    /// `c`: the displacement is `c sin(2π k/N)` times the mode's translation.
    pub scale: f64,
}

/// Writes `DIR/NAME_mode_LABEL.pvd` with its frames in `DIR/NAME_mode_LABEL/` for every mode.
pub fn write_mode_animations(body: &FlexibleBody, dir: &Path) -> Result<Vec<ModeAnimation>, String> {
    let size = body_size(body);
    (0..body.shapes.len()).map(|j| write_mode_animation(body, j, size, dir)).collect()
}

fn write_mode_animation(body: &FlexibleBody, j: usize, size: f64, dir: &Path) -> Result<ModeAnimation, String> {
    let label = body.modes[j].label.clone();
    let stem = format!("{}_mode_{}", file_safe(&body.name), file_safe(&label));
    let folder = dir.join(&stem);
    std::fs::create_dir_all(&folder).map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
    let shape: Vec<Vec3> = body.shapes[j].translation.iter().map(|t| Vec3::from(*t)).collect();
    let largest = shape.iter().map(Vec3::norm).fold(0.0, f64::max);
    let scale = if largest > 0.0 { AMPLITUDE_FRACTION * size / largest } else { 0.0 };
    let name = super::mode_shapes::mode_array_name(body, j, "mode");
    let pvd_path = dir.join(format!("{stem}.pvd"));
    let mut pvd = PvdFile::create(&pvd_path).map_err(|e| format!("cannot write {}: {e}", pvd_path.display()))?;
    let labels: Vec<u64> = body.nodes.iter().map(|n| n.label).collect();
    let mut entries = Vec::with_capacity(FRAMES_PER_PERIOD);
    for k in 0..FRAMES_PER_PERIOD {
        let phase = k as f64 / FRAMES_PER_PERIOD as f64;
        let amplitude = scale * (TAU * phase).sin();
        let displacement: Vec<Vec3> = shape.iter().map(|psi| amplitude * psi).collect();
        let points: Vec<Vec3> = body.nodes.iter().zip(&displacement).map(|(n, u)| n.position + u).collect();
        let data = vec![
            Attribute::scalars("node", 1).with_data(labels.clone()),
            Attribute::vectors("displacement").with_data(super::flat(&displacement)),
        ];
        let file = format!("{stem}/frame_{k:02}.vtu");
        let grid = piece(&points, element_cells(&body.elements), Attributes { point: data, cell: Vec::new() });
        write_vtu(&dir.join(&file), format!("{}: {name}, phase {phase}", body.name), grid)?;
        entries.push((phase, file));
    }
    let entries: Vec<PvdEntry> =
        entries.iter().map(|(phase, file)| PvdEntry { time: *phase, part: 0, name: &name, file }).collect();
    pvd.append(&entries).map_err(|e| format!("cannot write {}: {e}", pvd_path.display()))?;
    Ok(ModeAnimation { label, pvd: pvd_path, scale })
}

/// The diagonal of the box around the body's nodes.
fn body_size(body: &FlexibleBody) -> f64 {
    let Some(first) = body.nodes.first() else { return 0.0 };
    let (low, high) = body
        .nodes
        .iter()
        .fold((first.position, first.position), |(low, high), n| (low.inf(&n.position), high.sup(&n.position)));
    (high - low).norm()
}
