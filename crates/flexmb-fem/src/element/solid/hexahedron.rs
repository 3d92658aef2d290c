//! The brick (hexahedron) on `[-1, 1]³`: the 8-node trilinear and the 20-node serendipity shape
//! functions, nodes in the Abaqus/CalculiX order — corners 1–4 on the face ζ = −1 and 5–8 on
//! ζ = +1, each face counter-clockwise seen from ζ > 0; mid-edge nodes 9–12 on the edges 1-2, 2-3,
//! 3-4, 4-1, 13–16 on 5-6, 6-7, 7-8, 8-5, and 17–20 on the edges 1-5, 2-6, 3-7, 4-8.

use nalgebra::Vector3;

use super::isoparametric::ShapeFunctions;

/// Natural coordinates of the 20 nodes (the first 8 are the corners).
pub(super) const NODES: [[f64; 3]; 20] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];

/// Volume of the reference brick.
pub(super) const REFERENCE_VOLUME: f64 = 8.0;

/// The trilinear shape functions `Nₐ = (1 + ξξₐ)(1 + ηηₐ)(1 + ζζₐ) / 8` of the 8-node brick.
pub(super) fn linear(x: [f64; 3]) -> ShapeFunctions {
    let mut values = Vec::with_capacity(8);
    let mut derivatives = Vec::with_capacity(8);
    for node in &NODES[..8] {
        let f = [0, 1, 2].map(|k| 1.0 + x[k] * node[k]);
        values.push(f[0] * f[1] * f[2] / 8.0);
        derivatives.push(Vector3::new(node[0] * f[1] * f[2], f[0] * node[1] * f[2], f[0] * f[1] * node[2]) / 8.0);
    }
    ShapeFunctions { values, derivatives }
}

/// The serendipity shape functions of the 20-node brick: at a corner
/// `(1 + ξξₐ)(1 + ηηₐ)(1 + ζζₐ)(ξξₐ + ηηₐ + ζζₐ − 2) / 8`, at a mid-edge node whose coordinate k is
/// zero `(1 − x_k²)` times the two other factors `(1 + x_j x_jₐ)`, over 4.
pub(super) fn quadratic(x: [f64; 3]) -> ShapeFunctions {
    let mut values = Vec::with_capacity(20);
    let mut derivatives = Vec::with_capacity(20);
    for node in &NODES {
        let f = [0, 1, 2].map(|k| 1.0 + x[k] * node[k]);
        match (0..3).find(|&k| node[k] == 0.0) {
            None => {
                let s = x[0] * node[0] + x[1] * node[1] + x[2] * node[2] - 2.0;
                values.push(f[0] * f[1] * f[2] * s / 8.0);
                derivatives.push(Vector3::from_fn(|k, _| {
                    let others: f64 = (0..3).filter(|&m| m != k).map(|m| f[m]).product();
                    node[k] * others * (s + f[k]) / 8.0
                }));
            }
            Some(zero) => {
                let mut g = f;
                g[zero] = 1.0 - x[zero] * x[zero];
                values.push(g[0] * g[1] * g[2] / 4.0);
                derivatives.push(Vector3::from_fn(|k, _| {
                    let others: f64 = (0..3).filter(|&m| m != k).map(|m| g[m]).product();
                    let own = if k == zero { -2.0 * x[k] } else { node[k] };
                    own * others / 4.0
                }));
            }
        }
    }
    ShapeFunctions { values, derivatives }
}
