//! The mode shapes of a flexible body for ParaView: one `.vtu` file of the undeformed mesh with, per
//! mode, its translation and rotation at every node as point vectors (named by mode label and
//! frequency), and the lumped nodal masses. In ParaView, *Warp By Vector* on a mode's translation
//! shows the shape.

use std::path::{Path, PathBuf};

use flexmb_fem::reduction::FlexibleBody;
use vtkio::model::{Attribute, Attributes, UnstructuredGridPiece};

use super::{body_points_and_cells, write_vtu};

/// The name of mode `j`'s point vectors: `N1 translation (8.346 Hz)`, `S2 rotation`.
pub fn mode_array_name(body: &FlexibleBody, j: usize, what: &str) -> String {
    let mode = &body.modes[j];
    match mode.frequency_hz {
        Some(f) => format!("{} {what} ({f:.4} Hz)", mode.label),
        None => format!("{} {what}", mode.label),
    }
}

/// Writes `DIR/NAME_modes.vtu` and returns its path.
pub fn write_mode_shapes(body: &FlexibleBody, dir: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let path = dir.join(format!("{}_modes.vtu", body.name));
    let (points, cells) = body_points_and_cells(body);
    let mut point_data =
        vec![Attribute::scalars("mass", 1).with_data(body.nodes.iter().map(|n| n.mass).collect::<Vec<f64>>())];
    for (j, shape) in body.shapes.iter().enumerate() {
        let translation: Vec<f64> = shape.translation.iter().flatten().copied().collect();
        let rotation: Vec<f64> = shape.rotation.iter().flatten().copied().collect();
        point_data.push(Attribute::vectors(mode_array_name(body, j, "translation")).with_data(translation));
        point_data.push(Attribute::vectors(mode_array_name(body, j, "rotation")).with_data(rotation));
    }
    let piece = UnstructuredGridPiece {
        points: points.into(),
        cells,
        data: Attributes { point: point_data, cell: Vec::new() },
    };
    write_vtu(&path, format!("{}: mode shapes ({})", body.name, body.mode_set), piece)?;
    Ok(path)
}
