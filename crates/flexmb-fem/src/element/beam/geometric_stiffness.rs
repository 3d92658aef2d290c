//! The geometric (initial-stress) stiffness of the 2-node 3D beam under an axial force.
//!
//! A beam carrying the axial force `N` (tension positive) stores, when it bends, the extra energy
//! `½ ∫ N (v′² + w′²) dx` (the shortening of the chord under the force) and, when it twists,
//! `½ ∫ N (Iy + Iz)/A θx′² dx` (the fibres at distance r from the axis turn by r θx′). With the
//! beam's Hermite cubics in `v`, `w` and linear `θx` this is (Przemieniecki, *Theory of Matrix
//! Structural Analysis*, 1968, §15.2, eq. 15.29; Cook et al., *Concepts and Applications of Finite
//! Element Analysis*, 4th ed., §18.3), per bending plane in (deflection, rotation) of both nodes,
//!
//! ```text
//! N / (30 L) · [ 36   3L  −36   3L
//!                3L  4L²  −3L  −L²
//!               −36  −3L   36  −3L
//!                3L  −L²  −3L  4L² ]
//! ```
//!
//! and `N (Iy + Iz) / (A L) · [1, −1; −1, 1]` in torsion. The x–z plane takes the same block in
//! `(w, −θy)`, as the elastic stiffness does. Included: the axial force only. Not included: the
//! bending moments and the torque of the stress state (they couple bending and torsion, as in lateral
//! buckling, and vanish on the straight axis of a beam loaded along it) and the `N u′²` term of the
//! axial displacement (of relative size `N / EA` against the elastic axial stiffness).

use nalgebra::{DMatrix, Vector3};

use super::{local_axes, ElementError};
use crate::element::validate::{positive, Elastic};
use crate::mesh::{BeamSection, Material};

/// The axial force (N, tension positive) of the beam from `a` to `b` whose nodes move by `u_a`,
/// `u_b` (translations, body frame): `N = E A (u_b − u_a) · x / L`.
pub fn axial_force(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    section: &BeamSection,
    material: &Material,
    u_a: &Vector3<f64>,
    u_b: &Vector3<f64>,
) -> Result<f64, ElementError> {
    let elastic = Elastic::new(material)?;
    let area = positive("beam section area", section.area)?;
    let axis = b - a;
    let length = axis.norm();
    Ok(elastic.youngs_modulus * area * (u_b - u_a).dot(&axis) / (length * length))
}

/// The 12 × 12 geometric stiffness in body-frame components (dofs `ux uy uz rx ry rz` of node a then
/// node b) of the beam from `a` to `b` carrying the axial force `axial_force` (module documentation).
pub fn beam_geometric_stiffness(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    section: &BeamSection,
    axial_force: f64,
) -> Result<DMatrix<f64>, ElementError> {
    let axes = local_axes(a, b, &section.orientation)?;
    let area = positive("beam section area", section.area)?;
    let polar = positive("beam section Iy", section.iy)? + positive("beam section Iz", section.iz)?;
    let l = (b - a).norm();
    let c = axial_force / (30.0 * l);
    let bending = [
        [36.0 * c, 3.0 * l * c, -36.0 * c, 3.0 * l * c],
        [3.0 * l * c, 4.0 * l * l * c, -3.0 * l * c, -l * l * c],
        [-36.0 * c, -3.0 * l * c, 36.0 * c, -3.0 * l * c],
        [3.0 * l * c, -l * l * c, -3.0 * l * c, 4.0 * l * l * c],
    ];
    let mut k = DMatrix::zeros(12, 12);
    // x–y plane: v (1, 7), θz (5, 11); x–z plane: w (2, 8), −θy (4, 10).
    let xy_dofs = [1, 5, 7, 11];
    let xz_dofs = [2, 4, 8, 10];
    let xz_sign = [1.0, -1.0, 1.0, -1.0];
    for r in 0..4 {
        for s in 0..4 {
            k[(xy_dofs[r], xy_dofs[s])] += bending[r][s];
            k[(xz_dofs[r], xz_dofs[s])] += xz_sign[r] * xz_sign[s] * bending[r][s];
        }
    }
    let torsion = axial_force * polar / (area * l);
    k[(3, 3)] += torsion;
    k[(9, 9)] += torsion;
    k[(3, 9)] -= torsion;
    k[(9, 3)] -= torsion;
    let mut t = DMatrix::zeros(12, 12);
    for block in 0..4 {
        t.fixed_view_mut::<3, 3>(3 * block, 3 * block).copy_from(&axes);
    }
    let global = t.transpose() * k * &t;
    Ok((&global + global.transpose()) * 0.5)
}
