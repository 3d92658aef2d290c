//! STL files, ASCII or binary: triangles, three points each (STL shares no vertices).
//!
//! A binary file is an 80-byte header, a triangle count `n` (u32), then `n` records of 50 bytes: the
//! normal and three vertices (12 × f32, little-endian) and a 2-byte attribute. An ASCII file is
//! `solid … facet normal … outer loop vertex x y z … endloop endfacet … endsolid`. Some binary files
//! also begin with `solid`, so the size decides: a file of exactly `84 + 50 n` bytes is binary.
//!
//! Hand-written rather than `stl_io`: that crate says neither the line of a bad ASCII facet nor what
//! it found there in words a user can act on, reads ASCII coordinates as `f32` (these are `f64`),
//! and takes any file beginning with `solid ` for ASCII, so a binary file with such a header fails.

use flexmb::math::Vec3;

use super::{point, MeshFileError, SurfaceMesh};

const HEADER: usize = 80;
const RECORD: usize = 50;

/// Reads an STL file's bytes.
pub(super) fn read_stl(bytes: &[u8]) -> Result<SurfaceMesh, MeshFileError> {
    if is_binary(bytes) {
        return Ok(read_binary(bytes));
    }
    let text = std::str::from_utf8(bytes).map_err(|_| {
        MeshFileError::whole(format!(
            "neither a binary STL file ({} bytes, not 84 + 50 × its triangle count) nor ASCII text",
            bytes.len()
        ))
    })?;
    if !text.trim_start().starts_with("solid") {
        return Err(MeshFileError::at(1, "an ASCII STL file begins with `solid`"));
    }
    read_ascii(text)
}

fn is_binary(bytes: &[u8]) -> bool {
    let Some(count) = bytes.get(HEADER..HEADER + 4) else { return false };
    let n = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as usize;
    n.checked_mul(RECORD).and_then(|b| b.checked_add(HEADER + 4)) == Some(bytes.len())
}

fn read_binary(bytes: &[u8]) -> SurfaceMesh {
    let f32_at =
        |offset: usize| f32::from_le_bytes([bytes[offset], bytes[offset + 1], bytes[offset + 2], bytes[offset + 3]]);
    let mut mesh = SurfaceMesh::default();
    for record in (HEADER + 4..bytes.len()).step_by(RECORD) {
        let start = mesh.points.len();
        for vertex in 0..3 {
            let at = record + 12 + 12 * vertex;
            mesh.points.push(Vec3::new(f32_at(at).into(), f32_at(at + 4).into(), f32_at(at + 8).into()));
        }
        mesh.cells.push(vec![start, start + 1, start + 2]);
    }
    mesh
}

fn read_ascii(text: &str) -> Result<SurfaceMesh, MeshFileError> {
    let mut mesh = SurfaceMesh::default();
    // The points of the loop being read and the line it began on.
    let mut open: Option<(usize, usize)> = None;
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("outer") => open = Some((mesh.points.len(), number)),
            Some("vertex") => {
                if open.is_none() {
                    return Err(MeshFileError::at(number, "`vertex` outside `outer loop` … `endloop`"));
                }
                mesh.points.push(point(words, number, "vertex")?);
            }
            Some("endloop") => {
                let Some((start, _)) = open.take() else {
                    return Err(MeshFileError::at(number, "`endloop` without `outer loop`"));
                };
                let count = mesh.points.len() - start;
                if count < 3 {
                    return Err(MeshFileError::at(number, format!("a facet needs 3 vertices, this one has {count}")));
                }
                mesh.cells.push((start..mesh.points.len()).collect());
            }
            _ => {}
        }
    }
    match open {
        Some((_, line)) => Err(MeshFileError::at(line, "`outer loop` without `endloop`")),
        None => Ok(mesh),
    }
}


#[cfg(test)]
mod tests {
    use super::*;

    const TETRAHEDRON: &str = "solid t\n facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n   vertex 0 1 0\n   \
                               vertex 1 0 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   \
                               vertex 1 0 0\n   vertex 0 0 1\n  endloop\n endfacet\nendsolid t\n";

    #[test]
    fn ascii_facets_become_triangles() {
        let mesh = read_stl(TETRAHEDRON.as_bytes()).unwrap();
        assert_eq!(mesh.points.len(), 6);
        assert_eq!(mesh.cells, vec![vec![0, 1, 2], vec![3, 4, 5]]);
        assert_eq!(mesh.points[5], Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn binary_records_become_triangles_even_after_a_solid_header() {
        let mut bytes = b"solid but binary".to_vec();
        bytes.resize(HEADER, b' ');
        bytes.extend(1u32.to_le_bytes());
        for x in [0.0f32, 0.0, 1.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.5] {
            bytes.extend(x.to_le_bytes());
        }
        bytes.extend([0, 0]);
        let mesh = read_stl(&bytes).unwrap();
        assert_eq!(mesh.cells, vec![vec![0, 1, 2]]);
        assert_eq!(mesh.points[0], Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(mesh.points[2], Vec3::new(7.0, 8.0, 9.5));
    }

    #[test]
    fn a_bad_vertex_is_reported_at_its_line() {
        let text = TETRAHEDRON
            .replace("vertex 1 0 0\n  endloop\n endfacet\n facet", "vertex 1 x 0\n  endloop\n endfacet\n facet");
        let e = read_stl(text.as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(6));
        assert!(e.message.contains("`x`"), "{}", e.message);
    }
}
