//! The wedge (triangular prism): the triangle `ξ, η ≥ 0, ξ + η ≤ 1` in area coordinates
//! `L = (1 − ξ − η, ξ, η)` swept along `ζ ∈ [-1, 1]`; the 6-node linear and 15-node quadratic shape
//! functions, nodes in the Abaqus/CalculiX order — corners 1–3 on ζ = −1 and 4–6 on ζ = +1,
//! mid-edge nodes 7–9 on 1-2, 2-3, 3-1, 10–12 on 4-5, 5-6, 6-4 and 13–15 on 1-4, 2-5, 3-6.

use nalgebra::Vector3;

use super::isoparametric::ShapeFunctions;

/// Natural coordinates of the 15 nodes (the first 6 are the corners).
pub(super) const NODES: [[f64; 3]; 15] = [
    [0.0, 0.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [0.5, 0.0, -1.0],
    [0.5, 0.5, -1.0],
    [0.0, 0.5, -1.0],
    [0.5, 0.0, 1.0],
    [0.5, 0.5, 1.0],
    [0.0, 0.5, 1.0],
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// The triangle corners joined by the mid-edge nodes of a face.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// Volume of the reference wedge.
pub(super) const REFERENCE_VOLUME: f64 = 1.0;

/// Area coordinates and their natural derivatives (ζ component zero).
fn area_coordinates(x: [f64; 3]) -> ([f64; 3], [Vector3<f64>; 3]) {
    ([1.0 - x[0] - x[1], x[0], x[1]], [Vector3::new(-1.0, -1.0, 0.0), Vector3::x(), Vector3::y()])
}

/// The linear shape functions `Lₐ (1 ∓ ζ) / 2` of the 6-node wedge.
pub(super) fn linear(x: [f64; 3]) -> ShapeFunctions {
    let (l, dl) = area_coordinates(x);
    let mut values = Vec::with_capacity(6);
    let mut derivatives = Vec::with_capacity(6);
    for side in [-1.0, 1.0] {
        let h = (1.0 + side * x[2]) / 2.0;
        for a in 0..3 {
            values.push(l[a] * h);
            derivatives.push(dl[a] * h + Vector3::z() * (l[a] * side / 2.0));
        }
    }
    ShapeFunctions { values, derivatives }
}

/// The quadratic shape functions of the 15-node wedge: at a corner
/// `Lₐ ((2Lₐ − 1)(1 ∓ ζ) − (1 − ζ²)) / 2`, at a mid-edge node of a face `2 Lₐ L_b (1 ∓ ζ)`, at a
/// mid-edge node between the faces `Lₐ (1 − ζ²)`.
pub(super) fn quadratic(x: [f64; 3]) -> ShapeFunctions {
    let (l, dl) = area_coordinates(x);
    let z = x[2];
    let bubble = 1.0 - z * z;
    let mut values = Vec::with_capacity(15);
    let mut derivatives = Vec::with_capacity(15);
    for side in [-1.0, 1.0] {
        let h = 1.0 + side * z;
        for a in 0..3 {
            let c = (2.0 * l[a] - 1.0) * h - bubble;
            values.push(l[a] * c / 2.0);
            let in_plane = dl[a] * ((4.0 * l[a] - 1.0) * h - bubble) / 2.0;
            derivatives.push(in_plane + Vector3::z() * (l[a] * ((2.0 * l[a] - 1.0) * side + 2.0 * z) / 2.0));
        }
    }
    for side in [-1.0, 1.0] {
        let h = 1.0 + side * z;
        for (a, b) in EDGES {
            values.push(2.0 * l[a] * l[b] * h);
            derivatives.push((dl[a] * l[b] + dl[b] * l[a]) * (2.0 * h) + Vector3::z() * (2.0 * l[a] * l[b] * side));
        }
    }
    for a in 0..3 {
        values.push(l[a] * bubble);
        derivatives.push(dl[a] * bubble + Vector3::z() * (-2.0 * l[a] * z));
    }
    ShapeFunctions { values, derivatives }
}
