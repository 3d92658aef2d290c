//! The blocks of a run's ParaView series, each turned into a VTK grid at an output time:
//!
//! - a flexible body: its FE mesh at the deformed node positions `R + A (s̄ + Ψ a)`, with point data
//!   `node` (the FE node label), `displacement` (from the first frame, t = 0), `elastic_displacement`
//!   (`A Ψ a`: the deformation alone, global components) and `velocity`; and when its table asks for
//!   stresses, `von_mises` and `stress` (the tensor `A (Σ aⱼ σⱼ) Aᵀ`, global components, at the
//!   node's point of largest von Mises stress; see [`body_stress`](crate::body_stress));
//! - a rigid body: its shape (or frame glyph) moved with the body, with `displacement` and `velocity`,
//!   and for a frame glyph the cell data `axis` (0, 1, 2 for the body's x, y, z axis);
//! - a joint (not a driver, which repeats its joint's markers): a vertex at each of its two markers,
//!   with `marker` (0 for marker i, 1 for marker j) and `velocity`.

use flexmb::joint::JointKind;
use flexmb::math::Vec3;
use flexmb::model::{BodyId, MarkerId};
use flexmb::Model;
use vtkio::model::{Attribute, Attributes, Cells, UnstructuredGridPiece};

use crate::body_stress::BodyStress;
use super::body_motion::{marker_motion, BodyMotion, PointMotion};
use super::pvd::file_safe;
use super::{cells, element_cells, piece};
use crate::model_file::LoadedModel;
use crate::shape::{frame_size, Shape};

/// One block of the series.
pub(crate) struct Part {
    /// The block's name in ParaView: the body's or joint's name.
    pub name: String,
    /// The stem of its files, unique within the series.
    pub file_stem: String,
    kind: PartKind,
    /// The point positions of the first frame, from which `displacement` is measured.
    initial: Option<Vec<Vec3>>,
}

enum PartKind {
    Flexible { body: BodyId, labels: Vec<u64>, cells: Cells, stress: Option<BodyStress> },
    Rigid { body: BodyId, points: Vec<Vec3>, cells: Cells, frame_glyph: bool },
    Joint { markers: [MarkerId; 2] },
}

/// The rigid bodies, the flexible bodies, then the joints of a model.
pub(crate) fn parts(loaded: &LoadedModel) -> Vec<Part> {
    let model = &loaded.model;
    let mut parts = Vec::new();
    for s in &loaded.shapes {
        let mesh = s.shape.mesh();
        let cells = cells(mesh.cells.iter().map(Vec::as_slice));
        let frame_glyph = matches!(s.shape, Shape::Frame { .. });
        let kind = PartKind::Rigid { body: s.body, points: mesh.points, cells, frame_glyph };
        parts.push(Part::new(&model.bodies()[s.body.0].name, "body", kind, &parts));
    }
    for f in &loaded.flexible_bodies {
        let labels = model.modal_body(f.body).map_or_else(Vec::new, |m| m.nodes.iter().map(|n| n.label).collect());
        let kind = PartKind::Flexible { body: f.body, labels, cells: element_cells(&f.elements), stress: BodyStress::new(f) };
        parts.push(Part::new(&f.name, "body", kind, &parts));
    }
    push_joints(model, &mut parts);
    parts
}

/// The parts of a model alone, without its file's drawing (for a [`Model`] built in code): each rigid
/// body as the glyph of its frame (sized by its inertia, as a `[[body]]` without `shape` is drawn), each
/// flexible body as a vertex at each of its nodes (the elements are the file's), then the joints.
pub(crate) fn model_parts(model: &Model) -> Vec<Part> {
    let mut parts = Vec::new();
    for (k, body) in model.bodies().iter().enumerate() {
        let id = BodyId(k);
        let kind = match model.modal_body(id) {
            Some(modal) => {
                let labels = modal.nodes.iter().map(|n| n.label).collect();
                let vertices: Vec<[usize; 1]> = (0..modal.nodes.len()).map(|n| [n]).collect();
                PartKind::Flexible { body: id, labels, cells: cells(vertices.iter().map(|v| v.as_slice())), stress: None }
            }
            None => {
                let mesh = Shape::Frame { size: frame_size(body.mass, &body.inertia) }.mesh();
                let cells = cells(mesh.cells.iter().map(Vec::as_slice));
                PartKind::Rigid { body: id, points: mesh.points, cells, frame_glyph: true }
            }
        };
        parts.push(Part::new(&body.name, "body", kind, &parts));
    }
    push_joints(model, &mut parts);
    parts
}

/// A part for each joint that is not a driver (a driver repeats its joint's markers).
fn push_joints(model: &Model, parts: &mut Vec<Part>) {
    for joint in model.joints() {
        if matches!(joint.kind, JointKind::AngleDriver { .. } | JointKind::DisplacementDriver { .. }) {
            continue;
        }
        let kind = PartKind::Joint { markers: [joint.marker_i, joint.marker_j] };
        parts.push(Part::new(&joint.name, "joint", kind, parts));
    }
}

impl Part {
    /// A part named `name`, its file stem `<prefix>_<name>` made unique among `earlier`.
    fn new(name: &str, prefix: &str, kind: PartKind, earlier: &[Part]) -> Self {
        let mut file_stem = format!("{prefix}_{}", file_safe(name));
        if earlier.iter().any(|p| p.file_stem == file_stem) {
            file_stem = format!("{file_stem}_{}", earlier.len());
        }
        Self { name: name.to_string(), file_stem, kind, initial: None }
    }

    /// The block at the state `q`, `v`.
    pub(crate) fn piece(&mut self, model: &Model, q: &[f64], v: &[f64]) -> UnstructuredGridPiece {
        let points = self.motions(model, q, v);
        let Part { kind, initial, .. } = self;
        match kind {
            PartKind::Flexible { labels, cells, stress, .. } => {
                let mut piece = flexible_piece(&points, labels, cells, initial);
                if let Some(stress) = stress {
                    stress.evaluate(model, q);
                    piece.data.point.extend(stress_attributes(stress));
                }
                piece
            }
            PartKind::Rigid { cells, frame_glyph, .. } => rigid_piece(&points, cells, *frame_glyph, initial),
            PartKind::Joint { .. } => joint_piece(&points),
        }
    }

    /// `displacement` measured from the block's points at `q` from now on (instead of from its first
    /// frame).
    pub(crate) fn measure_displacement_from(&mut self, model: &Model, q: &[f64]) {
        let v = vec![0.0; model.layout().nv];
        self.initial = Some(positions(&self.motions(model, q, &v)));
    }

    /// Where the block's points are and how they move at the state `q`, `v`.
    pub(crate) fn motions(&self, model: &Model, q: &[f64], v: &[f64]) -> Vec<PointMotion> {
        match &self.kind {
            PartKind::Flexible { body, .. } => {
                let motion = BodyMotion::of(model, *body, q, v);
                let nodes = model.modal_body(*body).map_or(&[][..], |m| m.nodes.as_slice());
                nodes.iter().map(|n| motion.node(n)).collect()
            }
            PartKind::Rigid { body, points, .. } => {
                let motion = BodyMotion::of(model, *body, q, v);
                points.iter().map(|p| motion.point(p)).collect()
            }
            PartKind::Joint { markers } => markers.iter().map(|&m| marker_motion(model, m, q, v)).collect(),
        }
    }
}

fn flexible_piece(
    points: &[PointMotion],
    labels: &[u64],
    cells: &Cells,
    initial: &mut Option<Vec<Vec3>>,
) -> UnstructuredGridPiece {
    let data = vec![
        Attribute::scalars("node", 1).with_data(labels.to_vec()),
        displacement(initial, points),
        vectors("elastic_displacement", points.iter().map(|p| p.elastic)),
        vectors("velocity", points.iter().map(|p| p.velocity)),
    ];
    piece(&positions(points), cells.clone(), Attributes { point: data, cell: Vec::new() })
}

fn rigid_piece(
    points: &[PointMotion],
    cells: &Cells,
    frame_glyph: bool,
    initial: &mut Option<Vec<Vec3>>,
) -> UnstructuredGridPiece {
    let data = vec![displacement(initial, points), vectors("velocity", points.iter().map(|p| p.velocity))];
    let cell = match frame_glyph {
        true => vec![Attribute::scalars("axis", 1).with_data(vec![0i32, 1, 2])],
        false => Vec::new(),
    };
    piece(&positions(points), cells.clone(), Attributes { point: data, cell })
}

/// A joint's two marker points, `marker` 0 (i) and 1 (j).
fn joint_piece(points: &[PointMotion]) -> UnstructuredGridPiece {
    let data = vec![
        Attribute::scalars("marker", 1).with_data(vec![0i32, 1]),
        vectors("velocity", points.iter().map(|p| p.velocity)),
    ];
    piece(&positions(points), cells([&[0][..], &[1][..]]), Attributes { point: data, cell: Vec::new() })
}

/// `displacement`: each point's position less its position in the first frame (`initial`, set then).
fn displacement(initial: &mut Option<Vec<Vec3>>, points: &[PointMotion]) -> Attribute {
    let now = positions(points);
    let initial = initial.get_or_insert_with(|| now.clone());
    vectors("displacement", now.iter().zip(initial.iter()).map(|(p, p0)| p - p0))
}

fn positions(points: &[PointMotion]) -> Vec<Vec3> {
    points.iter().map(|p| p.position).collect()
}

/// `von_mises` and `stress` (9 components, row by row) at each node.
fn stress_attributes(stress: &BodyStress) -> [Attribute; 2] {
    let tensors: Vec<f64> =
        stress.node_stress.iter().flat_map(|s| [s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2]]).collect();
    [
        Attribute::scalars("von_mises", 1).with_data(stress.node_von_mises.clone()),
        Attribute::tensors("stress").with_data(tensors),
    ]
}

/// A point vector array.
fn vectors(name: &str, values: impl Iterator<Item = Vec3>) -> Attribute {
    Attribute::vectors(name).with_data(values.flat_map(|x| [x.x, x.y, x.z]).collect::<Vec<f64>>())
}
