//! The drilling stiffness of the flat shell: stiffness of the rotations θz about the element normal,
//! which membrane and bending leave without any, so that every node of a shell model has six stiff
//! degrees of freedom (also where all the elements at a node are coplanar).
//!
//! The energy is
//!
//! ```text
//! ½ k_ω (θ̄z − ω_c)²  +  ½ k_s Σᵢ (θzᵢ − θ̄z)²,
//! ```
//!
//! with θ̄z the mean of the nodal drilling rotations and ω_c = ½ (∂v/∂x − ∂u/∂y) the rotation of the
//! membrane displacement field at the element centre.
//!
//! - The first term is the penalty of Hughes & Brezzi ("On drilling degrees of freedom", CMAME 72,
//!   1989, 105–121), ½ ∫ γ (θz − ω)² dA, taken with the element's mean drilling rotation: it ties
//!   the drilling rotation to the rotation of the material, a constraint the exact solution
//!   satisfies, so it stiffens nothing that is not there (but a large k_ω over-constrains meshes
//!   with more elements than nodes, e.g. triangles).
//! - The second term is a small spring on the part of θz that varies over the element, which the
//!   first term leaves free (without it a patch of elements would have zero-energy drilling
//!   modes). It is a fictitious stiffness, so it must stay small compared with bending.
//!
//! Both vanish for every rigid motion (θz = ω_c = θ̄z, θzᵢ = θ̄z), and together they leave the
//! in-plane part of the element (u, v, θz) exactly its three rigid motions.

use nalgebra::{DMatrix, DVector, Vector2};

/// The drilling stiffness over `(u v θz)` of each node (3n × 3n), given the gradients (∂Nᵢ/∂x,
/// ∂Nᵢ/∂y) of the membrane shape functions at the element centre, the penalty `k_omega` on
/// θ̄z − ω_c and the spring `k_spread` on θzᵢ − θ̄z.
pub(super) fn drilling(
    centre_gradients: &[Vector2<f64>],
    k_omega: f64,
    k_spread: f64,
) -> DMatrix<f64> {
    let n = centre_gradients.len();
    let mean = 1.0 / n as f64;
    // θ̄z − ω_c = cᵀ d with ω_c = ½ Σ (∂Nᵢ/∂x vᵢ − ∂Nᵢ/∂y uᵢ).
    let mut c = DVector::zeros(3 * n);
    for (i, g) in centre_gradients.iter().enumerate() {
        c[3 * i] = 0.5 * g.y;
        c[3 * i + 1] = -0.5 * g.x;
        c[3 * i + 2] = mean;
    }
    let mut k = &c * c.transpose() * k_omega;
    for i in 0..n {
        for j in 0..n {
            let identity = if i == j { 1.0 } else { 0.0 };
            k[(3 * i + 2, 3 * j + 2)] += k_spread * (identity - mean);
        }
    }
    k
}
