//! Wavefront OBJ files: vertices (`v x y z`) and faces (`f i j k …`, 1-based indices, negative ones
//! counting back from the last vertex, each optionally `i/t/n`). Everything else (normals, texture
//! coordinates, groups, materials, lines) is skipped.
//!
//! Hand-written rather than `tobj`: its errors carry neither line nor index (`face vertex index out of
//! bounds`), where ours name the line and the vertex (`…obj:3: the face refers to vertex 7, but 2
//! vertices are defined before it`, which the model-file tests require), and it stores `f32` unless a
//! feature changes that for every user. Polygons stay polygons: ParaView draws them as they are.

use super::{point, MeshFileError, SurfaceMesh};

/// Reads an OBJ file's bytes.
pub(super) fn read_obj(bytes: &[u8]) -> Result<SurfaceMesh, MeshFileError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| MeshFileError::whole("an OBJ file is text, and this one is not UTF-8"))?;
    let mut mesh = SurfaceMesh::default();
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => mesh.points.push(point(words, number, "v")?),
            Some("f") => {
                let face = words.map(|w| vertex_index(w, mesh.points.len(), number)).collect::<Result<Vec<_>, _>>()?;
                if face.len() < 3 {
                    return Err(MeshFileError::at(
                        number,
                        format!("a face needs 3 or more vertices, got {}", face.len()),
                    ));
                }
                mesh.cells.push(face);
            }
            _ => {}
        }
    }
    Ok(mesh)
}


/// The 0-based index of a face's vertex reference (`i`, `i/t`, `i//n`, `i/t/n`; `-1` is the last vertex
/// so far), checked against the `count` vertices read so far.
fn vertex_index(word: &str, count: usize, line: usize) -> Result<usize, MeshFileError> {
    let text = word.split('/').next().unwrap_or("");
    let k: i64 = text
        .parse()
        .map_err(|_| MeshFileError::at(line, format!("expected a vertex number in the face, got `{word}`")))?;
    let index = if k < 0 { count as i64 + k } else { k - 1 };
    if k == 0 || index < 0 || index >= count as i64 {
        return Err(MeshFileError::at(
            line,
            format!("the face refers to vertex {k}, but {count} vertices are defined before it"),
        ));
    }
    Ok(index as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_keep_their_vertices_and_order() {
        let text = "# a square and a triangle\no square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n\
                    f 1//1 2//1 3//1 4//1\nf -4/1 -3/2 -1/3\n";
        let mesh = read_obj(text.as_bytes()).unwrap();
        assert_eq!(mesh.points.len(), 4);
        assert_eq!(mesh.cells, vec![vec![0, 1, 2, 3], vec![0, 1, 3]]);
    }

    #[test]
    fn a_face_before_its_vertices_is_reported_at_its_line() {
        let e = read_obj(b"v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n").unwrap_err();
        assert_eq!(e.line, Some(3));
        assert!(e.message.contains("vertex 3, but 2 vertices"), "{}", e.message);
    }
}
