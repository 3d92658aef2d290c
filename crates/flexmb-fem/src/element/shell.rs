//! The flat shell: a 3-node triangle or a 4-node quadrilateral with six degrees of freedom per node,
//! membrane plus bending plus drilling, formed in the element's own plane and turned into body-frame
//! components. One file per part:
//!
//! | part | triangle | quadrilateral | file |
//! |---|---|---|---|
//! | element frame | plane of the nodes | mean plane, rigid links if warped | `shell/frame.rs` |
//! | membrane | constant-strain triangle | QM6 (incompatible modes) | `shell/membrane.rs` |
//! | bending | DKT (Kirchhoff) | MITC4 (Mindlin, assumed shear) | `shell/dkt.rs`, `shell/mitc4.rs` |
//! | drilling | Hughes–Brezzi penalty + spring | the same | `shell/drilling.rs` |
//! | geometric stiffness | membrane stress, linear | membrane stress, bilinear | `shell/geometric_stiffness.rs` |
//!
//! Membrane and bending are uncoupled in the element plane (a flat, homogeneous section). The
//! local degrees of freedom of a node are `u v w θx θy θz` along and about the element axes
//! `x y z` (z the normal); with the direction matrix Λ (rows: the local axes in body components)
//! and the rigid link from each node to its projection onto the element plane (offset r, zero
//! unless the quadrilateral is warped), a node's local degrees of freedom are
//! `[Λ, −Λ [r]×; 0, Λ]` times its body-frame ones, and the body-frame stiffness is `Tᵀ K_local T`.
//!
//! **Drilling scaling.** Both drilling stiffnesses, the Hughes–Brezzi penalty k_ω and the spring
//! k_s on the varying part of θz (see `shell/drilling.rs`), are α times the plate bending stiffness,
//! `k_ω = k_s = α D`, `D = E t³ / (12 (1 − ν²))`, with α the model's
//! [`drilling_stiffness`](crate::mesh::ModelOptions::drilling_stiffness) (default 1e-3). Scaled by
//! the bending stiffness, the drilling terms stay a perturbation of relative size about α whatever
//! the thickness; scaled by the membrane stiffness G t A instead, they would grow like (size / t)²
//! against bending and stiffen thin folded and curved shells (with α G t A and α = 1e-3, the
//! frequencies of a folded plate moved by 2e-3, those of a thin faceted panel of triangles by
//! 1e-3). With the default, the bending frequencies of a folded plate and of a faceted cylindrical
//! panel, quadrilaterals or triangles, change by less than 1e-4 against α → 0 (see the tests);
//! those of a flat plate do not change at all (drilling is then uncoupled from bending). The price
//! of a small α is conditioning: the drilling stiffness is about α t² / (12 A) of the membrane
//! stiffness. With rotary inertia on, the drilling rotations of a node have a frequency of about
//! `√(α E n / ((1 − ν²) ρ A))` (elements of area A with n nodes), independent of the thickness.
//!
//! **Lumped mass.** `ρ t A / n` at each of the n nodes; with rotary inertia also
//! `(ρ t³ / 12)(A / n)` about each of the three axes (the bending rotary inertia of the node's share
//! of the plate, taken isotropic, so it is the same in body axes).
//!
//! **Consistent mass.** `ρ t` per area moves with the field interpolated from the nodes by the
//! bilinear (quadrilateral) or linear (triangle) shape functions, translations and rotations alike:
//! the mass points are the 2 × 2 Gauss points of the quadrilateral or the three midpoint-rule points
//! of the triangle, exact for the products of these shape functions. With rotary inertia each point
//! also carries `ρ t³ / 12` per area about each axis, as the lumped mass does.

mod bilinear;
mod dkt;
mod drilling;
mod frame;
mod geometric_stiffness;
mod membrane;
mod mitc4;
mod stress;

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector2, Vector3};

pub use frame::WARP_TOLERANCE;
pub use geometric_stiffness::shell_geometric_stiffness;
pub use stress::shell_stress_matrix;

use super::validate::{non_negative, positive, Elastic};
use super::{ElementError, ElementMatrices, MassPoint, NodalMass};
use crate::mesh::{MassModel, Material, ModelOptions, ShellSection};
use frame::ElementFrame;

/// Stiffness and lumped mass of a 3- or 4-node flat shell.
///
/// Errors: `NodeCount` for other than 3 or 4 points, `DegenerateShape` for a triangle of (nearly)
/// zero area or a quadrilateral that is not convex (a corner of zero or negative angle, crossed or
/// collapsed sides), `Warped` for a quadrilateral whose warp exceeds [`WARP_TOLERANCE`],
/// `InvalidProperty` / `OutOfRange` for a thickness, Young's modulus, Poisson's ratio, density or
/// drilling stiffness factor out of range.
pub fn shell_matrices(
    points: &[Vector3<f64>],
    section: &ShellSection,
    material: &Material,
    options: &ModelOptions,
) -> Result<ElementMatrices, ElementError> {
    let elastic = Elastic::new(material)?;
    let t = positive("shell thickness", section.thickness)?;
    let alpha = non_negative("drilling stiffness factor", options.drilling_stiffness)?;
    let frame = ElementFrame::new(points)?;
    let n = points.len();
    let (e, nu, g) = (
        elastic.youngs_modulus,
        elastic.poisson_ratio,
        elastic.shear_modulus,
    );
    let d_membrane = membrane::plane_stress(e, nu, t);
    let d_bending = membrane::plane_stress(e, nu, t * t * t / 12.0);

    // Local stiffness, 6 degrees of freedom per node.
    let mut k = DMatrix::zeros(6 * n, 6 * n);
    let mut scatter = |part: &DMatrix<f64>, dofs: &[usize]| {
        let m = dofs.len();
        for (r, c) in (0..n * m).flat_map(|r| (0..n * m).map(move |c| (r, c))) {
            k[(6 * (r / m) + dofs[r % m], 6 * (c / m) + dofs[c % m])] += part[(r, c)];
        }
    };
    let xy = &frame.plane;
    let centre_gradients: Vec<Vector2<f64>> = if n == 3 {
        let k_m = membrane::constant_strain_triangle(xy, &d_membrane);
        scatter(&DMatrix::from_column_slice(6, 6, k_m.as_slice()), &[0, 1]);
        let k_b = dkt::dkt(xy, &d_bending);
        scatter(
            &DMatrix::from_column_slice(9, 9, k_b.as_slice()),
            &[2, 3, 4],
        );
        membrane::triangle_gradients(xy).0.to_vec()
    } else {
        let k_m = membrane::qm6(xy, &d_membrane)?;
        scatter(&DMatrix::from_column_slice(8, 8, k_m.as_slice()), &[0, 1]);
        let k_b = mitc4::mitc4(xy, &d_bending, mitc4::SHEAR_CORRECTION * g * t);
        scatter(
            &DMatrix::from_column_slice(12, 12, k_b.as_slice()),
            &[2, 3, 4],
        );
        let (gradients, _) = bilinear::cartesian_derivatives(xy, 0.0, 0.0);
        (0..4)
            .map(|i| Vector2::new(gradients[0][i], gradients[1][i]))
            .collect()
    };
    let k_drilling = alpha * d_bending[(0, 0)];
    scatter(
        &drilling::drilling(&centre_gradients, k_drilling, k_drilling),
        &[0, 1, 5],
    );

    let transform = to_local(&frame);
    let stiffness = transform.transpose() * k * &transform;
    // Exactly symmetric, whatever the rounding of the products.
    let stiffness = (&stiffness + stiffness.transpose()) * 0.5;

    let share = frame.area / n as f64;
    let rotary_inertia = if options.rotary_inertia {
        Matrix3::identity() * (elastic.density * t * t * t / 12.0 * share)
    } else {
        Matrix3::zeros()
    };
    let nodal = NodalMass {
        mass: elastic.density * t * share,
        rotary_inertia,
    };
    let consistent_mass = match options.shell_mass() {
        MassModel::Lumped => Vec::new(),
        MassModel::Consistent => {
            let rotary_per_area = if options.rotary_inertia { elastic.density * t * t * t / 12.0 } else { 0.0 };
            consistent_mass_points(points, &frame, elastic.density * t, rotary_per_area)
        }
    };
    Ok(ElementMatrices {
        stiffness,
        lumped_mass: vec![nodal; n],
        consistent_mass,
    })
}

/// The map from body-frame to local degrees of freedom: `[Λ, −Λ [r]×; 0, Λ]` at each node.
fn to_local(frame: &ElementFrame) -> DMatrix<f64> {
    let n = frame.offsets.len();
    let mut transform = DMatrix::zeros(6 * n, 6 * n);
    for (i, r) in frame.offsets.iter().enumerate() {
        let mut block = Matrix6::zeros();
        block.fixed_view_mut::<3, 3>(0, 0).copy_from(&frame.axes);
        block.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-frame.axes * r.cross_matrix()));
        block.fixed_view_mut::<3, 3>(3, 3).copy_from(&frame.axes);
        transform.fixed_view_mut::<6, 6>(6 * i, 6 * i).copy_from(&block);
    }
    transform
}

/// The mass points of the consistent mass: `mass_per_area` and `rotary_per_area` (about every axis)
/// at the quadrature points of the element's shape functions; interpolation indices are the nodes'
/// positions in `points`.
fn consistent_mass_points(
    points: &[Vector3<f64>],
    frame: &ElementFrame,
    mass_per_area: f64,
    rotary_per_area: f64,
) -> Vec<MassPoint> {
    // (shape function values, area weight) at each quadrature point.
    let rule: Vec<(Vec<f64>, f64)> = if points.len() == 3 {
        let third = frame.area / 3.0;
        [[2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0], [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0], [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0]]
            .into_iter()
            .map(|n| (n.to_vec(), third))
            .collect()
    } else {
        bilinear::gauss_points()
            .into_iter()
            .map(|[xi, eta]| {
                let det = bilinear::jacobian(&frame.plane, xi, eta).determinant();
                (bilinear::shape(xi, eta).to_vec(), det)
            })
            .collect()
    };
    rule.into_iter()
        .map(|(shape, area)| MassPoint {
            position: points.iter().zip(&shape).map(|(p, n)| *n * p).sum(),
            mass: mass_per_area * area,
            rotary_inertia: Matrix3::identity() * (rotary_per_area * area),
            interpolation: shape.iter().enumerate().map(|(i, n)| (i, Matrix6::identity() * *n)).collect(),
        })
        .collect()
}

#[cfg(test)]
mod tests;
