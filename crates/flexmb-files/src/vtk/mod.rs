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
/// quadrilaterals, solids as VTK's (quadratic) tetrahedra, wedges and hexahedra.
pub(crate) fn element_cells(elements: &[BodyElement]) -> Cells {
    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    let mut types = Vec::new();
    for e in elements {
        let (kind, order) = solid_cell(&e.kind).unwrap_or((None, None));
        match order {
            Some(order) => connectivity.extend(order.iter().map(|&k| e.nodes[k] as u64)),
            None => connectivity.extend(e.nodes.iter().map(|&n| n as u64)),
        }
        offsets.push(connectivity.len() as u64);
        types.push(kind.unwrap_or_else(|| cell_type(e.nodes.len())));
    }
    Cells { cell_verts: VertexNumbers::XML { connectivity, offsets }, types }
}

/// The VTK cell of a solid element type and, where VTK numbers the nodes otherwise than Abaqus, the
/// Abaqus index of each VTK node: VTK's wedges turn their first triangle the other way.
fn solid_cell(kind: &str) -> Option<(Option<CellType>, Option<&'static [usize]>)> {
    const WEDGE: [usize; 6] = [0, 2, 1, 3, 5, 4];
    const QUADRATIC_WEDGE: [usize; 15] = [0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13];
    Some(match kind {
        "C3D4" => (Some(CellType::Tetra), None),
        "C3D10" => (Some(CellType::QuadraticTetra), None),
        "C3D6" => (Some(CellType::Wedge), Some(&WEDGE[..])),
        "C3D15" => (Some(CellType::QuadraticWedge), Some(&QUADRATIC_WEDGE[..])),
        "C3D8" | "C3D8I" => (Some(CellType::Hexahedron), None),
        "C3D20" | "C3D20R" => (Some(CellType::QuadraticHexahedron), None),
        _ => return None,
    })
}

/// The VTK cell of a list of `count` points: 1 a vertex, 2 a line, 3 a triangle, 4 a quadrilateral,
/// more a polygon.
fn cell_type(count: usize) -> CellType {
    match count {
        1 => CellType::Vertex,
        2 => CellType::Line,
        3 => CellType::Triangle,
        4 => CellType::Quad,
        _ => CellType::Polygon,
    }
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
        types.push(cell_type(list.len()));
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
