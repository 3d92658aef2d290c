//! What ParaView output draws for a rigid body: a surface given by the model file's `shape` key (a
//! box, cylinder or sphere, or a mesh file in STL or OBJ), or, without one, a glyph of the body's frame.
//! Everything here is in the frame the shape was given in; the VTK writer moves it with the body.

mod obj;
mod primitives;
mod stl;

use std::path::Path;

use flexmb::math::{Mat3, Vec3};
use flexmb::model::BodyId;

pub use primitives::{cuboid, cylinder, sphere, CYLINDER_SEGMENTS, SPHERE_BANDS, SPHERE_SEGMENTS};

/// Points and cells to draw. A cell lists point indices: 1 is a vertex, 2 a line, 3 a triangle, 4 a
/// quadrilateral, more a polygon (surface cells in counter-clockwise order seen from outside).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMesh {
    /// The points, in the frame the shape was given in.
    pub points: Vec<Vec3>,
    /// The cells: point indices, see above.
    pub cells: Vec<Vec<usize>>,
}

impl SurfaceMesh {
    /// Every point `p` moved to `origin + rotation · scale · p`.
    #[must_use]
    pub fn placed(mut self, scale: f64, rotation: &Mat3, origin: &Vec3) -> Self {
        for p in &mut self.points {
            *p = origin + rotation * (scale * *p);
        }
        self
    }
}

/// What is drawn for one rigid body, in its body frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A surface from the `shape` key.
    Surface(SurfaceMesh),
    /// Three lines of length `size` from the body frame's origin along its x, y and z axes (no `shape`,
    /// or `shape = { frame = size }`).
    Frame {
        /// The axes' length (m).
        size: f64,
    },
}

impl Shape {
    /// The mesh to draw: the surface, or the frame glyph's three lines (cell `k` along axis `k`).
    pub fn mesh(&self) -> SurfaceMesh {
        match self {
            Shape::Surface(mesh) => mesh.clone(),
            Shape::Frame { size } => frame_glyph(*size),
        }
    }
}

/// The shape of one `[[body]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyShape {
    /// The body drawn.
    pub body: BodyId,
    /// What is drawn for it.
    pub shape: Shape,
}

/// The frame glyph: six points (the origin once per axis, so that each line has its own) and three
/// lines along x, y and z.
fn frame_glyph(size: f64) -> SurfaceMesh {
    let mut mesh = SurfaceMesh::default();
    for axis in 0..3 {
        let k = mesh.points.len();
        mesh.points.push(Vec3::zeros());
        mesh.points.push(size * Vec3::ith(axis, 1.0));
        mesh.cells.push(vec![k, k + 1]);
    }
    mesh
}

/// The default length of a frame glyph's axes: half the diagonal of the uniform box with the body's
/// mass and inertia, `½ √(6 tr(J)/m)` (the box of sides a, b, c has `tr(J) = m (a² + b² + c²)/6`).
pub fn frame_size(mass: f64, inertia: &Mat3) -> f64 {
    0.5 * (6.0 * inertia.trace() / mass).sqrt()
}

/// A problem in a mesh file: the 1-based line (of an ASCII file) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshFileError {
    /// The 1-based line of an ASCII file, if the problem is on one.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl MeshFileError {
    fn at(line: usize, message: impl Into<String>) -> Self {
        Self { line: Some(line), message: message.into() }
    }

    fn whole(message: impl Into<String>) -> Self {
        Self { line: None, message: message.into() }
    }
}

/// The three coordinates after `keyword` on line `line` of a text mesh file (OBJ `v`, STL `vertex`).
fn point<'a>(mut words: impl Iterator<Item = &'a str>, line: usize, keyword: &str) -> Result<Vec3, MeshFileError> {
    let mut p = Vec3::zeros();
    for k in 0..3 {
        let word = words.next().unwrap_or("");
        p[k] = word
            .parse()
            .map_err(|_| MeshFileError::at(line, format!("expected three numbers after `{keyword}`, got `{word}`")))?;
    }
    Ok(p)
}

/// The mesh file formats read, by extension.
pub const MESH_EXTENSIONS: &str = "`.stl` (ASCII or binary) or `.obj`";

/// Reads an STL (ASCII or binary) or OBJ file, chosen by its extension.
pub fn read_mesh_file(path: &Path) -> Result<SurfaceMesh, MeshFileError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let reader: fn(&[u8]) -> Result<SurfaceMesh, MeshFileError> = match extension.as_deref() {
        Some("stl") => stl::read_stl,
        Some("obj") => obj::read_obj,
        _ => return Err(MeshFileError::whole(format!("expected a mesh file ending in {MESH_EXTENSIONS}"))),
    };
    let bytes = flexmb_fem::input::read_file(path).map_err(|e| MeshFileError::whole(e.to_string()))?;
    let mesh = reader(&bytes)?;
    if mesh.cells.is_empty() {
        return Err(MeshFileError::whole("the file holds no faces"));
    }
    if let Some(p) = mesh.points.iter().find(|p| !p.iter().all(|x| x.is_finite())) {
        return Err(MeshFileError::whole(format!("a vertex is not finite: [{}, {}, {}]", p.x, p.y, p.z)));
    }
    Ok(mesh)
}
