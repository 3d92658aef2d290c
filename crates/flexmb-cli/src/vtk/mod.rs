//! ParaView output: VTK XML unstructured grids (`.vtu`) of flexible bodies, written with `vtkio`.

mod mode_shapes;

pub use mode_shapes::write_mode_shapes;

use flexmb_fem::reduction::FlexibleBody;
use vtkio::model::{CellType, Cells, VertexNumbers};

/// The undeformed mesh of a flexible body as VTK points and cells: beams as lines, shells as
/// triangles or quadrilaterals.
pub(crate) fn body_points_and_cells(body: &FlexibleBody) -> (Vec<f64>, Cells) {
    let points: Vec<f64> = body.nodes.iter().flat_map(|n| [n.position.x, n.position.y, n.position.z]).collect();
    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    let mut types = Vec::new();
    for element in &body.elements {
        connectivity.extend(element.nodes.iter().map(|&n| n as u64));
        offsets.push(connectivity.len() as u64);
        types.push(match (element.kind.as_str(), element.nodes.len()) {
            ("beam", _) => CellType::Line,
            (_, 3) => CellType::Triangle,
            _ => CellType::Quad,
        });
    }
    (points, Cells { cell_verts: VertexNumbers::XML { connectivity, offsets }, types })
}
