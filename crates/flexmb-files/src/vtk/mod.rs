//! ParaView output: VTK XML unstructured grids (`.vtu`) written with `vtkio`, and `.pvd` time series of
//! them: the mode shapes of a flexible body and their animations (`flexmb modes --vtk`), and the
//! bodies and joints of a simulation run as it proceeds (`flexmb run --vtk`), and the modes of the
//! whole mechanism (`mechanism_mode`).

mod body_motion;
pub mod mechanism_mode;
mod mode_animation;
mod mode_shapes;
mod pvd;
mod run_parts;
mod run_series;

pub use mode_animation::{write_mode_animations, ModeAnimation, AMPLITUDE_FRACTION, FRAMES_PER_PERIOD};
pub use mode_shapes::write_mode_shapes;
pub use pvd::{PvdEntry, PvdFile};
pub use run_series::{RunSeries, SeriesTimes, SeriesWritten};

use std::path::Path;

use flexmb::math::Vec3;
use flexmb_fem::reduction::{BodyElement, FlexibleBody};
use vtkio::model::{
    Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

/// The undeformed mesh of a flexible body as VTK points and cells: beams as lines, shells as
/// triangles or quadrilaterals.
pub(crate) fn body_points_and_cells(body: &FlexibleBody) -> (Vec<f64>, Cells) {
    let points: Vec<f64> = body.nodes.iter().flat_map(|n| [n.position.x, n.position.y, n.position.z]).collect();
    (points, element_cells(&body.elements))
}

/// The cells of a flexible body's elements (node indices): beams as lines, shells as triangles or
/// quadrilaterals.
pub(crate) fn element_cells(elements: &[BodyElement]) -> Cells {
    cells(elements.iter().map(|e| e.nodes.as_slice()))
}

/// VTK cells from lists of point indices, typed by their length: 1 a vertex, 2 a line, 3 a triangle,
/// 4 a quadrilateral, more a polygon.
pub(crate) fn cells<'a>(lists: impl IntoIterator<Item = &'a [usize]>) -> Cells {
    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    let mut types = Vec::new();
    for list in lists {
        connectivity.extend(list.iter().map(|&n| n as u64));
        offsets.push(connectivity.len() as u64);
        types.push(match list.len() {
            1 => CellType::Vertex,
            2 => CellType::Line,
            3 => CellType::Triangle,
            4 => CellType::Quad,
            _ => CellType::Polygon,
        });
    }
    Cells { cell_verts: VertexNumbers::XML { connectivity, offsets }, types }
}

/// Points as VTK's flat coordinate list.
pub(crate) fn flat(points: &[Vec3]) -> Vec<f64> {
    points.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// A grid of `points` and `cells` with point and cell data.
pub(crate) fn piece(points: &[Vec3], cells: Cells, data: Attributes) -> UnstructuredGridPiece {
    UnstructuredGridPiece { points: flat(points).into(), cells, data }
}

/// Writes one unstructured grid to `path` (`.vtu`).
pub(crate) fn write_vtu(path: &Path, title: String, piece: UnstructuredGridPiece) -> Result<(), String> {
    let vtk = Vtk {
        version: Version::Auto,
        title,
        byte_order: ByteOrder::LittleEndian,
        data: DataSet::inline(piece),
        file_path: None,
    };
    vtk.export(path).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
