//! A rigid body's `shape` → the [`Shape`] the ParaView output draws: a box, cylinder or sphere, a mesh
//! file (STL or OBJ, relative to the model file), or a frame glyph; placed in the body frame by
//! `origin` and `orientation`. Without `shape`, a frame glyph sized by the body's inertia.

use std::path::Path;

use flexmb::body::RigidBody;
use flexmb::math::{Mat3, Vec3};
use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::context::Context;
use super::orientation::orientation;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{CylinderSection, Name, Number, ShapeSection};
use crate::shape::{cuboid, cylinder, frame_size, read_mesh_file, sphere, Shape, SurfaceMesh, MESH_EXTENSIONS};

const KINDS: &str = "`box = [lx, ly, lz]`, `cylinder = { radius = r, length = l }`, `sphere = r`, \
                     `mesh = \"file.stl\"` (or .obj) or `frame = size`";

/// The shape of `body` from its `shape` table (at `key`), mesh paths relative to `base_dir`.
pub(crate) fn body_shape(
    ctx: &Context,
    section: Option<&Spanned<ShapeSection>>,
    key: &KeyPath,
    base_dir: &Path,
    body: &RigidBody,
) -> Result<Shape, ModelFileError> {
    let Some(section) = section else {
        return Ok(Shape::Frame { size: frame_size(body.mass, &body.inertia) });
    };
    let table = ShapeTable { ctx, s: section.get_ref(), key };
    table.check_one_kind(&section.span())?;
    let s = table.s;
    if let (Some(scale), None) = (&s.scale, &s.mesh) {
        return Err(ctx.invalid(&scale.span(), &key.key("scale"), "`scale` goes with `mesh` only"));
    }
    if let Some(size) = &s.frame {
        table.reject_placement("frame")?;
        return Ok(Shape::Frame { size: table.positive(size, &key.key("frame"), "the frame glyph's size", Quantity::Length)? });
    }
    let scale = match &s.scale {
        Some(scale) => table.positive(scale, &key.key("scale"), "the mesh's scale", Quantity::Factor)?,
        None => 1.0,
    };
    let mesh = if let Some(lengths) = &s.cuboid {
        cuboid(&table.lengths(lengths)?)
    } else if let Some(c) = &s.cylinder {
        table.cylinder(c)?
    } else if let Some(radius) = &s.sphere {
        sphere(table.positive(radius, &key.key("sphere"), "the sphere's radius", Quantity::Length)?)
    } else if let Some(file) = &s.mesh {
        table.mesh(file, base_dir)?
    } else {
        unreachable!("check_one_kind found one kind")
    };
    let (rotation, origin) = table.placement()?;
    Ok(Shape::Surface(mesh.placed(scale, &rotation, &origin)))
}

/// One `shape` table being built.
struct ShapeTable<'a> {
    ctx: &'a Context<'a>,
    s: &'a ShapeSection,
    key: &'a KeyPath,
}

impl ShapeTable<'_> {
    /// Exactly one of `box`, `cylinder`, `sphere`, `mesh`, `frame`.
    fn check_one_kind(&self, span: &std::ops::Range<usize>) -> Result<(), ModelFileError> {
        let s = self.s;
        let given = [s.cuboid.is_some(), s.cylinder.is_some(), s.sphere.is_some(), s.mesh.is_some(), s.frame.is_some()];
        match given.iter().filter(|g| **g).count() {
            1 => Ok(()),
            0 => Err(self.ctx.invalid(span, self.key, format!("the shape is not given; expected one of {KINDS}"))),
            _ => Err(self.ctx.invalid(span, self.key, format!("a shape is one of {KINDS}, and this one gives more"))),
        }
    }

    /// A frame glyph sits at the body frame: `origin` and `orientation` would not move it.
    fn reject_placement(&self, kind: &str) -> Result<(), ModelFileError> {
        let spans = [
            ("origin", self.s.origin.as_ref().map(Spanned::span)),
            ("orientation", self.s.orientation.as_ref().map(Spanned::span)),
        ];
        match spans.into_iter().find_map(|(name, span)| span.map(|span| (name, span))) {
            Some((name, span)) => Err(self.ctx.invalid(
                &span,
                &self.key.key(name),
                format!("`{name}` does not apply to `{kind}`: the frame glyph shows the body frame itself"),
            )),
            None => Ok(()),
        }
    }

    /// A positive `what`, of `quantity` (within its window).
    fn positive(&self, value: &Number, key: &KeyPath, what: &str, quantity: Quantity) -> Result<f64, ModelFileError> {
        let x = self.ctx.quantity(value, key, quantity)?;
        if x <= 0.0 {
            return Err(self.ctx.invalid(&value.span(), key, format!("{what} must be positive, got {x}")));
        }
        Ok(x)
    }

    /// `box = [lx, ly, lz]`, each positive.
    fn lengths(&self, lengths: &crate::model_file::schema::Vector) -> Result<Vec3, ModelFileError> {
        let key = self.key.key("box");
        self.ctx.numbers::<3>(lengths, &key, "the box's edge lengths [lx, ly, lz]")?;
        let mut out = Vec3::zeros();
        for (k, value) in lengths.get_ref().iter().enumerate() {
            out[k] = self.positive(value, &key.index(k), "a box's edge length", Quantity::Length)?;
        }
        Ok(out)
    }

    fn cylinder(&self, section: &Spanned<CylinderSection>) -> Result<SurfaceMesh, ModelFileError> {
        let key = self.key.key("cylinder");
        let c = section.get_ref();
        let radius = self.positive(&c.radius, &key.key("radius"), "the cylinder's radius", Quantity::Length)?;
        let length = self.positive(&c.length, &key.key("length"), "the cylinder's length", Quantity::Length)?;
        let axis = match &c.axis {
            Some(axis) => self.ctx.keyword(axis, &key.key("axis"), "axis", &[("x", 0), ("y", 1), ("z", 2)])?,
            None => 2,
        };
        Ok(cylinder(radius, length, axis))
    }

    /// `mesh = "file"`: an STL or OBJ file relative to the model file's directory.
    fn mesh(&self, file: &Name, base_dir: &Path) -> Result<SurfaceMesh, ModelFileError> {
        let key = self.key.key("mesh");
        let text = file.get_ref();
        if text.trim().is_empty() {
            return Err(self.ctx.invalid(
                &file.span(),
                &key,
                format!("expected the path of a mesh file, {MESH_EXTENSIONS}, got an empty string"),
            ));
        }
        let path = Path::new(text);
        let path = if path.is_absolute() { path.to_path_buf() } else { base_dir.join(path) };
        read_mesh_file(&path).map_err(|e| {
            let at = e.line.map_or(String::new(), |line| format!(":{line}"));
            self.ctx.invalid(&file.span(), &key, format!("mesh file {}{at}: {}", path.display(), e.message))
        })
    }

    /// `orientation` (default the body axes) and `origin` (default the body frame's origin).
    fn placement(&self) -> Result<(Mat3, Vec3), ModelFileError> {
        let rotation = match &self.s.orientation {
            Some(o) => orientation(self.ctx, o, &self.key.key("orientation"))?.rotation_matrix(),
            None => Mat3::identity(),
        };
        let origin = self.ctx.vector_or_zero(&self.s.origin, &self.key.key("origin"), Quantity::Length)?;
        Ok((rotation, origin))
    }
}
