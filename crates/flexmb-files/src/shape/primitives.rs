//! Box, cylinder and sphere as surface meshes centred on their frame's origin. Each face has its own
//! points, so that ParaView shades the flat faces flat.

use std::f64::consts::{PI, TAU};

use flexmb::math::Vec3;

use super::SurfaceMesh;

/// Segments around a cylinder.
pub const CYLINDER_SEGMENTS: usize = 32;
/// Segments around a sphere (longitude).
pub const SPHERE_SEGMENTS: usize = 32;
/// Bands from pole to pole of a sphere (latitude).
pub const SPHERE_BANDS: usize = 16;

/// A box with edge lengths `lengths` along x, y, z: 24 points, 6 quadrilaterals.
pub fn cuboid(lengths: &Vec3) -> SurfaceMesh {
    let h = lengths / 2.0;
    let mut mesh = SurfaceMesh::default();
    // For each face normal n = ±e_k: the face's corners from the two other axes (i, j) with
    // e_i × e_j = e_k, in counter-clockwise order seen from outside.
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        for sign in [1.0, -1.0] {
            let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            let start = mesh.points.len();
            for (a, b) in corners {
                let mut p = Vec3::zeros();
                p[k] = sign * h[k];
                p[i] = a * h[i];
                p[j] = sign * b * h[j];
                mesh.points.push(p);
            }
            mesh.cells.push((start..start + 4).collect());
        }
    }
    mesh
}

/// A cylinder of `radius` and `length` along axis `axis` (0, 1, 2 for x, y, z), centred on the origin:
/// the side in quadrilaterals and the two end caps as polygons.
pub fn cylinder(radius: f64, length: f64, axis: usize) -> SurfaceMesh {
    let n = CYLINDER_SEGMENTS;
    // Built along z, then the coordinates are permuted cyclically (a proper rotation) onto `axis`.
    let ring = |z: f64| -> Vec<Vec3> {
        (0..n)
            .map(|s| {
                let angle = TAU * s as f64 / n as f64;
                Vec3::new(radius * angle.cos(), radius * angle.sin(), z)
            })
            .collect()
    };
    let (bottom, top) = (ring(-length / 2.0), ring(length / 2.0));
    let mut mesh = SurfaceMesh::default();
    mesh.points.extend(&bottom);
    mesh.points.extend(&top);
    for s in 0..n {
        let next = (s + 1) % n;
        mesh.cells.push(vec![s, next, n + next, n + s]);
    }
    let top_cap = mesh.points.len();
    mesh.points.extend(&top);
    mesh.cells.push((top_cap..top_cap + n).collect());
    let bottom_cap = mesh.points.len();
    mesh.points.extend(&bottom);
    mesh.cells.push((bottom_cap..bottom_cap + n).rev().collect());
    // p'[r] = p[(r + shift) % 3] puts z (index 2) at index `axis`.
    let shift = (5 - axis) % 3;
    for p in &mut mesh.points {
        let z_along_axis = Vec3::from_fn(|r, _| p[(r + shift) % 3]);
        *p = z_along_axis;
    }
    mesh
}

/// A sphere of `radius` centred on the origin: triangles at the poles, quadrilaterals between.
pub fn sphere(radius: f64) -> SurfaceMesh {
    let (n, bands) = (SPHERE_SEGMENTS, SPHERE_BANDS);
    let mut mesh = SurfaceMesh::default();
    mesh.points.push(Vec3::new(0.0, 0.0, radius));
    for band in 1..bands {
        let polar = PI * band as f64 / bands as f64;
        for s in 0..n {
            let angle = TAU * s as f64 / n as f64;
            mesh.points.push(radius * Vec3::new(polar.sin() * angle.cos(), polar.sin() * angle.sin(), polar.cos()));
        }
    }
    let south = mesh.points.len();
    mesh.points.push(Vec3::new(0.0, 0.0, -radius));
    // Point `s` of ring `r` (r = 0 … bands − 2).
    let at = |r: usize, s: usize| 1 + r * n + s % n;
    for s in 0..n {
        mesh.cells.push(vec![0, at(0, s), at(0, s + 1)]);
    }
    for r in 0..bands - 2 {
        for s in 0..n {
            mesh.cells.push(vec![at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1)]);
        }
    }
    for s in 0..n {
        mesh.cells.push(vec![at(bands - 2, s), south, at(bands - 2, s + 1)]);
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Σ` over cells of the signed volume of the tetrahedra (origin, fan triangles): the enclosed
    /// volume when every face points outwards.
    fn enclosed_volume(mesh: &SurfaceMesh) -> f64 {
        let mut volume = 0.0;
        for cell in &mesh.cells {
            let p0 = mesh.points[cell[0]];
            for w in cell[1..].windows(2) {
                volume += p0.dot(&mesh.points[w[0]].cross(&mesh.points[w[1]])) / 6.0;
            }
        }
        volume
    }

    #[test]
    fn a_box_has_its_volume_and_outward_faces() {
        let mesh = cuboid(&Vec3::new(0.2, 0.3, 0.5));
        assert_eq!((mesh.points.len(), mesh.cells.len()), (24, 6));
        assert!((enclosed_volume(&mesh) - 0.03).abs() < 1e-15);
        let max = mesh.points.iter().fold(Vec3::zeros(), |m, p| m.sup(&p.abs()));
        assert!((max - Vec3::new(0.1, 0.15, 0.25)).norm() < 1e-15);
    }

    #[test]
    fn a_cylinder_lies_along_its_axis_with_outward_faces() {
        let n = CYLINDER_SEGMENTS as f64;
        // The inscribed polygon's area: ½ n r² sin(2π/n).
        let volume = 0.5 * n * 0.1f64.powi(2) * (TAU / n).sin() * 0.4;
        for axis in 0..3 {
            let mesh = cylinder(0.1, 0.4, axis);
            assert_eq!((mesh.points.len(), mesh.cells.len()), (4 * CYLINDER_SEGMENTS, CYLINDER_SEGMENTS + 2));
            assert!((enclosed_volume(&mesh) - volume).abs() < 1e-15, "axis {axis}");
            for p in &mesh.points {
                assert!((p[axis].abs() - 0.2).abs() < 1e-15);
                let radial = (p.norm_squared() - p[axis] * p[axis]).sqrt();
                assert!((radial - 0.1).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn a_sphere_has_its_points_on_the_radius_and_outward_faces() {
        let mesh = sphere(0.5);
        assert_eq!(mesh.points.len(), 2 + (SPHERE_BANDS - 1) * SPHERE_SEGMENTS);
        assert_eq!(mesh.cells.len(), SPHERE_BANDS * SPHERE_SEGMENTS);
        assert!(mesh.points.iter().all(|p| (p.norm() - 0.5).abs() < 1e-15));
        let volume = enclosed_volume(&mesh);
        let exact = 4.0 / 3.0 * PI * 0.125;
        assert!(volume > 0.95 * exact && volume < exact, "{volume} vs {exact}");
    }
}
