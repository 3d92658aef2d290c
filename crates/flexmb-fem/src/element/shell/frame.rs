//! The element frame of a flat shell: the plane the element is formed in, its local axes, and the
//! nodes' positions in that plane.
//!
//! - **Triangle:** x along side 1→2, z along (p₂ − p₁) × (p₃ − p₁), y = z × x.
//! - **Quadrilateral:** z along the cross product of the diagonals, (p₃ − p₁) × (p₄ − p₂); the mean
//!   plane is the plane normal to z through the centroid of the four nodes. Both diagonals are
//!   parallel to it, so the nodes lie at heights ±h from it, alternately. Each node is projected
//!   onto the plane; x is side 1→2 projected, y = z × x.
//!
//! The **warp** of a quadrilateral is h divided by the mean length of its diagonals. A warp up to
//! [`WARP_TOLERANCE`] = 0.05 is accepted: the element is formed flat in the mean plane, and each
//! node is joined to its projection by a rigid link, `u_projection = u + θ × (projection − node)`
//! (the rigid-offset warping correction of flat shell elements, MacNeal, *Finite Elements: Their
//! Design and Performance*, 1994), so that rigid motions of the true nodes stay strain-free. A
//! larger warp is an error ([`ElementError::Warped`]), a flat facet then being a poor model of the
//! surface. For scale: squares of side a at 45° to the generators of a cylinder of radius R have a
//! warp of about 0.09 a / R, so 0.05 admits facets up to about R / 2.

use nalgebra::{Matrix3, Vector2, Vector3};

use crate::element::ElementError;

/// The largest warp of a quadrilateral (distance of the nodes from the mean plane over the mean
/// length of the diagonals) accepted.
pub const WARP_TOLERANCE: f64 = 0.05;

/// A shape is degenerate when an area (a triangle's, a quadrilateral's corner parallelograms) is
/// below this fraction of the square of its length scale.
const DEGENERATE: f64 = 1e-10;

/// The local frame of a flat shell element.
#[derive(Clone, Debug)]
pub(super) struct ElementFrame {
    /// The direction matrix Λ: its rows are the local x, y, z axes in body components, so that local
    /// components are Λ times body components.
    pub axes: Matrix3<f64>,
    /// The nodes (projected onto the element plane) in local x, y, origin at the nodes' centroid.
    pub plane: Vec<Vector2<f64>>,
    /// From each node to its projection onto the element plane, in body components (zero for a
    /// triangle or a flat quadrilateral).
    pub offsets: Vec<Vector3<f64>>,
    /// The area of the element in its plane.
    pub area: f64,
}

impl ElementFrame {
    /// The frame of a triangle (3 points) or a quadrilateral (4 points, in order around it).
    pub(super) fn new(points: &[Vector3<f64>]) -> Result<Self, ElementError> {
        if points.iter().any(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(ElementError::DegenerateShape);
        }
        match points.len() {
            3 => Self::triangle(points),
            4 => Self::quadrilateral(points),
            found => Err(ElementError::NodeCount {
                kind: "shell",
                expected: "3 or 4",
                found,
            }),
        }
    }

    fn triangle(p: &[Vector3<f64>]) -> Result<Self, ElementError> {
        let side = p[1] - p[0];
        let normal = side.cross(&(p[2] - p[0]));
        let longest = (0..3)
            .map(|i| (p[(i + 1) % 3] - p[i]).norm_squared())
            .fold(0.0, f64::max);
        if normal.norm() <= DEGENERATE * longest {
            return Err(ElementError::DegenerateShape);
        }
        let z = normal.normalize();
        let x = side.normalize();
        let axes = Self::axes(x, z);
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        Ok(Self {
            plane: p.iter().map(|q| (axes * (q - centroid)).xy()).collect(),
            offsets: vec![Vector3::zeros(); 3],
            area: 0.5 * normal.norm(),
            axes,
        })
    }

    fn quadrilateral(p: &[Vector3<f64>]) -> Result<Self, ElementError> {
        let (d1, d2) = (p[2] - p[0], p[3] - p[1]);
        let normal = d1.cross(&d2);
        let size = 0.5 * (d1.norm() + d2.norm());
        if normal.norm() <= DEGENERATE * d1.norm() * d2.norm() {
            return Err(ElementError::DegenerateShape);
        }
        let z = normal.normalize();
        let centroid = (p[0] + p[1] + p[2] + p[3]) / 4.0;
        let heights: Vec<f64> = p.iter().map(|q| (q - centroid).dot(&z)).collect();
        let warp = heights.iter().fold(0.0, |m: f64, h| m.max(h.abs())) / size;
        if warp > WARP_TOLERANCE {
            return Err(ElementError::Warped { warp });
        }
        let side = p[1] - p[0];
        let side = side - z * z.dot(&side);
        if side.norm() <= DEGENERATE.sqrt() * size {
            return Err(ElementError::DegenerateShape);
        }
        let axes = Self::axes(side.normalize(), z);
        let plane: Vec<Vector2<f64>> = p.iter().map(|q| (axes * (q - centroid)).xy()).collect();
        // Every corner must turn the same way (about +z): a convex quadrilateral, whose bilinear map
        // has a positive Jacobian everywhere.
        for i in 0..4 {
            let to_next = plane[(i + 1) % 4] - plane[i];
            let to_previous = plane[(i + 3) % 4] - plane[i];
            if to_next.perp(&to_previous) <= DEGENERATE * size * size {
                return Err(ElementError::DegenerateShape);
            }
        }
        Ok(Self {
            plane,
            offsets: heights.iter().map(|h| -z * *h).collect(),
            area: 0.5 * normal.norm(),
            axes,
        })
    }

    /// Λ from the unit x and z axes.
    fn axes(x: Vector3<f64>, z: Vector3<f64>) -> Matrix3<f64> {
        let y = z.cross(&x);
        Matrix3::from_rows(&[x.transpose(), y.transpose(), z.transpose()])
    }
}
