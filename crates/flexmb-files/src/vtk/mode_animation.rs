//! Mode animations for ParaView: per mode, a `.pvd` series of the body oscillating in that mode over one
//! period, `FRAMES_PER_PERIOD` frames with the node positions `s̄ + c sin(2π k/N) ψ` and the point data
//! `displacement` (`c sin(2π k/N) ψ`) and `rotation` (`c sin(2π k/N) θ`), `ψ` and `θ` the mode's
//! translation and rotation. The scale `c` makes the largest displacement `AMPLITUDE_FRACTION` of the
//! body's size (the diagonal of the box around its nodes); for a mode that moves the nodes only by
//! turning them (the torsion of a beam about its nodes' line), the largest rotation `AMPLITUDE_FRACTION`
//! rad. The series' time is the fraction of the period, `k/N`, the same for every mode, so that several
//! modes play side by side.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use flexmb::math::Vec3;
use flexmb_fem::reduction::FlexibleBody;
use vtkio::model::{Attribute, Attributes};

use super::pvd::{file_safe, PvdEntry, PvdFile};
use super::{element_cells, flat, piece, write_vtu};

/// Frames over one period of a mode.
pub const FRAMES_PER_PERIOD: usize = 24;
/// The largest displacement of an animated mode, as a fraction of the body's size (or its largest
/// rotation in rad, for a rotation-only mode).
pub const AMPLITUDE_FRACTION: f64 = 0.1;
/// A mode whose largest translation is below this fraction of its largest rotation times the body's
/// size is a rotation-only mode: its translations are round-off.
const ROTATION_ONLY: f64 = 1e-6;

/// One mode's animation.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeAnimation {
    /// The mode's label (`N1`, `O2`, …).
    pub label: String,
    /// The animation's `.pvd` file.
    pub pvd: PathBuf,
    /// `c`: the displacement is `c sin(2π k/N)` times the mode's translation.
    pub scale: f64,
    /// The mode turns the nodes without moving them; `c` is set by the largest rotation.
    pub rotation_only: bool,
}

/// A mode's translation and rotation at every node.
struct Shape {
    translation: Vec<Vec3>,
    rotation: Vec<Vec3>,
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
    let vectors = |v: &[[f64; 3]]| v.iter().map(|x| Vec3::from(*x)).collect();
    let shape =
        Shape { translation: vectors(&body.shapes[j].translation), rotation: vectors(&body.shapes[j].rotation) };
    let (scale, rotation_only) = animation_scale(&shape, size);
    let mut files = Vec::with_capacity(FRAMES_PER_PERIOD);
    for k in 0..FRAMES_PER_PERIOD {
        let phase = k as f64 / FRAMES_PER_PERIOD as f64;
        let file = format!("{stem}/frame_{k:02}.vtu");
        write_frame(body, &shape, scale * (TAU * phase).sin(), &dir.join(&file), phase)?;
        files.push((phase, file));
    }
    let name = super::mode_shapes::mode_array_name(body, j, "mode");
    let pvd_path = dir.join(format!("{stem}.pvd"));
    let entries: Vec<PvdEntry> =
        files.iter().map(|(phase, file)| PvdEntry { time: *phase, part: 0, name: &name, file }).collect();
    let mut pvd = PvdFile::create(&pvd_path).map_err(|e| format!("cannot write {}: {e}", pvd_path.display()))?;
    pvd.append(&entries).map_err(|e| format!("cannot write {}: {e}", pvd_path.display()))?;
    Ok(ModeAnimation { label, pvd: pvd_path, scale, rotation_only })
}

/// `c` and whether the mode is rotation-only (see the module's documentation).
fn animation_scale(shape: &Shape, size: f64) -> (f64, bool) {
    let largest = |v: &[Vec3]| v.iter().map(Vec3::norm).fold(0.0, f64::max);
    let (translation, rotation) = (largest(&shape.translation), largest(&shape.rotation));
    if translation > ROTATION_ONLY * rotation * size && translation > 0.0 {
        (AMPLITUDE_FRACTION * size / translation, false)
    } else if rotation > 0.0 {
        (AMPLITUDE_FRACTION / rotation, true)
    } else {
        (0.0, false)
    }
}

/// One frame: the nodes displaced by `amplitude` times the mode.
fn write_frame(body: &FlexibleBody, shape: &Shape, amplitude: f64, path: &Path, phase: f64) -> Result<(), String> {
    let displacement: Vec<Vec3> = shape.translation.iter().map(|psi| amplitude * psi).collect();
    let rotation: Vec<Vec3> = shape.rotation.iter().map(|theta| amplitude * theta).collect();
    let points: Vec<Vec3> = body.nodes.iter().zip(&displacement).map(|(n, u)| n.position + u).collect();
    let data = vec![
        Attribute::scalars("node", 1).with_data(body.nodes.iter().map(|n| n.label).collect::<Vec<u64>>()),
        Attribute::vectors("displacement").with_data(flat(&displacement)),
        Attribute::vectors("rotation").with_data(flat(&rotation)),
    ];
    let grid = piece(&points, element_cells(&body.elements), Attributes { point: data, cell: Vec::new() });
    write_vtu(path, format!("{}: mode shape at phase {phase} of its period", body.name), grid)
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
