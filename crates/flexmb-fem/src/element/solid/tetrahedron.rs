//! The tetrahedron `ξ, η, ζ ≥ 0, ξ + η + ζ ≤ 1` in volume coordinates `L = (1 − ξ − η − ζ, ξ, η, ζ)`:
//! the 4-node linear and the 10-node quadratic shape functions, nodes in the Abaqus/CalculiX order —
//! corners 1–4 (node 4 on the side from which 1-2-3 turn counter-clockwise), mid-edge nodes 5–10 on
//! the edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4.

use nalgebra::Vector3;

use super::isoparametric::ShapeFunctions;

/// Natural coordinates of the 10 nodes (the first 4 are the corners).
pub(super) const NODES: [[f64; 3]; 10] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];

/// The corners joined by the mid-edge nodes 5–10.
const EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// Volume of the reference tetrahedron.
pub(super) const REFERENCE_VOLUME: f64 = 1.0 / 6.0;

/// The volume coordinates and their (constant) natural derivatives.
fn volume_coordinates(x: [f64; 3]) -> ([f64; 4], [Vector3<f64>; 4]) {
    (
        [1.0 - x[0] - x[1] - x[2], x[0], x[1], x[2]],
        [Vector3::new(-1.0, -1.0, -1.0), Vector3::x(), Vector3::y(), Vector3::z()],
    )
}

/// The linear shape functions `Nₐ = Lₐ` of the 4-node tetrahedron.
pub(super) fn linear(x: [f64; 3]) -> ShapeFunctions {
    let (l, dl) = volume_coordinates(x);
    ShapeFunctions { values: l.to_vec(), derivatives: dl.to_vec() }
}

/// The quadratic shape functions of the 10-node tetrahedron: `Lₐ (2Lₐ − 1)` at the corners,
/// `4 Lₐ L_b` at the mid-edge nodes.
pub(super) fn quadratic(x: [f64; 3]) -> ShapeFunctions {
    let (l, dl) = volume_coordinates(x);
    let mut values: Vec<f64> = l.iter().map(|&la| la * (2.0 * la - 1.0)).collect();
    let mut derivatives: Vec<Vector3<f64>> = (0..4).map(|a| dl[a] * (4.0 * l[a] - 1.0)).collect();
    for (a, b) in EDGES {
        values.push(4.0 * l[a] * l[b]);
        derivatives.push((dl[a] * l[b] + dl[b] * l[a]) * 4.0);
    }
    ShapeFunctions { values, derivatives }
}
