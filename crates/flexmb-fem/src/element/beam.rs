//! The 2-node 3D beam: axial, torsion and bending in two planes, Euler–Bernoulli or Timoshenko,
//! with a lumped or a consistent mass.
//!
//! **Local axes.** x runs from node a to node b; y is the part of the section's orientation vector
//! normal to x (Abaqus' n₁); z = x × y. Local components are `u_loc = Λ u_body` with the rows of the
//! direction matrix Λ the local axes, and the body-frame stiffness is `Tᵀ K_loc T` with
//! `T = diag(Λ, Λ, Λ, Λ)` (Przemieniecki, *Theory of Matrix Structural Analysis*, 1968, §5.6).
//!
//! **Stiffness** (Przemieniecki 1968, §5.6, eq. 5.116 with shear deformation): the local degrees of
//! freedom per node are `u v w θx θy θz`,
//!
//! - axial `EA/L` on u, torsion `GJ/L` on θx (uniform torsion, no warping restraint);
//! - bending in the x–y plane (v, θz, θz = dv/dx, second moment `Iz`),
//!   `E Iz / ((1 + Φy) L³) · [12, 6L, −12, 6L; 6L, (4 + Φy)L², −6L, (2 − Φy)L²; …]`;
//! - bending in the x–z plane (w, θy) with `Iy` and `Φz`: the same matrix in (w, −θy), because a
//!   positive θy turns the axis towards −z (θy = −dw/dx), which flips the sign of every w–θy term;
//! - the shear parameters are `Φy = 12 E Iz / (k G A L²)` and `Φz = 12 E Iy / (k G A L²)` for a
//!   Timoshenko beam with shear coefficient k, and zero (Euler–Bernoulli) without one. For a tip
//!   load on a cantilever this matrix is exact: `P L³ / (3 E I) + P L / (k G A)`.
//!
//! **Lumped mass.** Half of `m = ρ A L` at each node. With rotary inertia each node also gets, in
//! local axes, the inertia of its half of the beam about the node: `ρ (Iy + Iz) L / 2` about x (the
//! polar second moment `Iy + Iz`, not J), and `m L² / 24 + ρ Iy L / 2` about y,
//! `m L² / 24 + ρ Iz L / 2` about z (a slender rod of mass m/2 and length L/2 about its end, plus the
//! sections' own rotary inertia); in body axes this is `Λᵀ diag(…) Λ`.
//!
//! **Consistent mass.** The mass `ρ A` per length moves with the Euler–Bernoulli displacement field
//! of the beam's axis: linear in the axial displacement, Hermite cubics in the deflections,
//! `v = H₁ v_a + L H₂ θz_a + H₃ v_b + L H₄ θz_b` with `H₁ = 1 − 3ξ² + 2ξ³`, `H₂ = ξ − 2ξ² + ξ³`,
//! `H₃ = 3ξ² − 2ξ³`, `H₄ = ξ³ − ξ²` (ξ = x / L), and `w` the same in `(w, −θy)`. The rotations
//! follow: `θx` linear, `θz = dv/dx`, `θy = −dw/dx`. Four Gauss points carry the mass (exact for
//! the products of cubics): `Σ m_g N_gᵀ N_g` is Przemieniecki's consistent mass (1968, eq. 11.31,
//! `ρ A L / 420 · [156, 22L, 54, −13L; …]` in bending, `ρ A L / 6 · [2, 1; 1, 2]` axially). With
//! rotary inertia the points also carry the sections' own rotary inertia, `ρ (Iy + Iz)` about x,
//! `ρ Iy` about y and `ρ Iz` about z per length (Rayleigh's rotary inertia; the translations
//! already hold the rest). A Timoshenko beam uses the same field for its mass.

mod geometric_stiffness;
mod stress;

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};

pub use geometric_stiffness::{axial_force, beam_geometric_stiffness};
pub use stress::beam_stress_matrix;

use super::validate::{positive, Elastic};
use super::{gauss_legendre_4, ElementError, ElementMatrices, MassPoint, NodalMass};
use crate::mesh::{BeamSection, MassModel, Material, ModelOptions};

/// Below this length relative to the distance of the nodes from the body origin, the two nodes are
/// taken as coincident.
const ZERO_LENGTH: f64 = 1e-12;

/// Below this sine of the angle between the orientation vector and the beam axis, the two are taken
/// as parallel.
const PARALLEL: f64 = 1e-6;

/// Stiffness and mass (lumped, and the consistent mass points when `options` asks for them) of a
/// 2-node 3D beam from `a` to `b`.
///
/// Errors: `ZeroLength` if a and b coincide, `OrientationParallel` if the section's orientation
/// vector is zero or parallel to the beam, `InvalidProperty` / `OutOfRange` for a material or
/// section property that is not positive (E, A, Iy, Iz, J, k) or out of range (ν, ρ).
pub fn beam_matrices(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    section: &BeamSection,
    material: &Material,
    options: &ModelOptions,
) -> Result<ElementMatrices, ElementError> {
    let rotary_inertia = options.rotary_inertia;
    let elastic = Elastic::new(material)?;
    let properties = SectionProperties::checked(section)?;
    let axes = local_axes(a, b, &section.orientation)?;
    let length = (b - a).norm();

    let k_local = local_stiffness(length, &elastic, &properties);
    let mut t = DMatrix::zeros(12, 12);
    for block in 0..4 {
        t.fixed_view_mut::<3, 3>(3 * block, 3 * block)
            .copy_from(&axes);
    }
    let stiffness = t.transpose() * k_local * &t;
    // Exactly symmetric, whatever the rounding of the products.
    let stiffness = (&stiffness + stiffness.transpose()) * 0.5;

    let mass = elastic.density * properties.area * length;
    let rotary = if rotary_inertia {
        let rho = elastic.density;
        let half = 0.5 * length;
        let about_ends = mass * length * length / 24.0;
        let local = Matrix3::from_diagonal(&Vector3::new(
            rho * (properties.iy + properties.iz) * half,
            about_ends + rho * properties.iy * half,
            about_ends + rho * properties.iz * half,
        ));
        axes.transpose() * local * axes
    } else {
        Matrix3::zeros()
    };
    let nodal = NodalMass {
        mass: 0.5 * mass,
        rotary_inertia: rotary,
    };
    let consistent_mass = match options.beam_mass() {
        MassModel::Lumped => Vec::new(),
        MassModel::Consistent => consistent_mass_points(a, b, &axes, elastic.density, &properties, rotary_inertia),
    };
    Ok(ElementMatrices {
        stiffness,
        lumped_mass: vec![nodal, nodal],
        consistent_mass,
    })
}

/// The consistent mass of the beam from `a` to `b` (direction matrix `axes`, density `rho`) as
/// four mass points (see the module documentation); interpolation indices 0 (node a) and 1 (node b).
fn consistent_mass_points(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    axes: &Matrix3<f64>,
    rho: f64,
    section: &SectionProperties,
    rotary_inertia: bool,
) -> Vec<MassPoint> {
    let length = (b - a).norm();
    let section_rotary = Matrix3::from_diagonal(&Vector3::new(
        rho * (section.iy + section.iz),
        rho * section.iy,
        rho * section.iz,
    ));
    let mut to_body = Matrix6::zeros();
    to_body.fixed_view_mut::<3, 3>(0, 0).copy_from(&axes.transpose());
    to_body.fixed_view_mut::<3, 3>(3, 3).copy_from(&axes.transpose());
    gauss_legendre_4()
        .into_iter()
        .map(|(xi, weight)| {
            let [at_a, at_b] = axis_field(xi, length);
            let rotary = if rotary_inertia {
                axes.transpose() * section_rotary * axes * (weight * length)
            } else {
                Matrix3::zeros()
            };
            MassPoint {
                position: a + xi * (b - a),
                mass: rho * section.area * length * weight,
                rotary_inertia: rotary,
                interpolation: vec![
                    (0, to_body * at_a * to_body.transpose()),
                    (1, to_body * at_b * to_body.transpose()),
                ],
            }
        })
        .collect()
}

/// The axis' displacement field at ξ = x / L in local axes: for each node, the 6 × 6 block from
/// its local `u v w θx θy θz` to the point's translation and rotation.
fn axis_field(xi: f64, length: f64) -> [Matrix6<f64>; 2] {
    let l = length;
    let (x2, x3) = (xi * xi, xi * xi * xi);
    // Hermite cubics and their derivatives d/dξ.
    let h = [1.0 - 3.0 * x2 + 2.0 * x3, xi - 2.0 * x2 + x3, 3.0 * x2 - 2.0 * x3, x3 - x2];
    let dh = [-6.0 * xi + 6.0 * x2, 1.0 - 4.0 * xi + 3.0 * x2, 6.0 * xi - 6.0 * x2, 3.0 * x2 - 2.0 * xi];
    let linear = [1.0 - xi, xi];
    let mut blocks = [Matrix6::zeros(), Matrix6::zeros()];
    for (node, g) in blocks.iter_mut().enumerate() {
        let (h_disp, h_rot) = (h[2 * node], l * h[2 * node + 1]);
        let (dh_disp, dh_rot) = (dh[2 * node] / l, dh[2 * node + 1]);
        g[(0, 0)] = linear[node]; // u
        g[(3, 3)] = linear[node]; // θx
        // x–y plane: v and θz = dv/dx.
        g[(1, 1)] = h_disp;
        g[(1, 5)] = h_rot;
        g[(5, 1)] = dh_disp;
        g[(5, 5)] = dh_rot;
        // x–z plane: w and θy = −dw/dx, the same field in (w, −θy).
        g[(2, 2)] = h_disp;
        g[(2, 4)] = -h_rot;
        g[(4, 2)] = -dh_disp;
        g[(4, 4)] = dh_rot;
    }
    blocks
}

/// The checked section properties.
struct SectionProperties {
    area: f64,
    iy: f64,
    iz: f64,
    torsion_constant: f64,
    shear_coefficient: Option<f64>,
}

impl SectionProperties {
    /// The properties of `section`, each positive.
    fn checked(section: &BeamSection) -> Result<Self, ElementError> {
        Ok(SectionProperties {
            area: positive("beam section area", section.area)?,
            iy: positive("beam section Iy", section.iy)?,
            iz: positive("beam section Iz", section.iz)?,
            torsion_constant: positive("beam torsion constant", section.torsion_constant)?,
            shear_coefficient: match section.shear_coefficient {
                Some(k) => Some(positive("beam shear coefficient", k)?),
                None => None,
            },
        })
    }
}

/// The direction matrix Λ of the beam: its rows are the local x, y, z axes in body components.
fn local_axes(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    orientation: &Vector3<f64>,
) -> Result<Matrix3<f64>, ElementError> {
    let axis = b - a;
    let length = axis.norm();
    if !length.is_finite() || length <= ZERO_LENGTH * a.norm().max(b.norm()) {
        return Err(ElementError::ZeroLength);
    }
    let x = axis / length;
    let size = orientation.norm();
    let y = orientation - x * x.dot(orientation);
    if !size.is_finite() || y.norm() <= PARALLEL * size {
        return Err(ElementError::OrientationParallel);
    }
    let y = y.normalize();
    let z = x.cross(&y);
    Ok(Matrix3::from_rows(&[
        x.transpose(),
        y.transpose(),
        z.transpose(),
    ]))
}

/// The 12 × 12 stiffness in local axes, degrees of freedom `u v w θx θy θz` of node a then node b
/// (Przemieniecki 1968, eq. 5.116).
fn local_stiffness(length: f64, elastic: &Elastic, s: &SectionProperties) -> DMatrix<f64> {
    let (e, g, l) = (elastic.youngs_modulus, elastic.shear_modulus, length);
    // Shear parameters: Φ = 12 E I / (k G A L²), zero for Euler–Bernoulli.
    let phi = |i: f64| match s.shear_coefficient {
        Some(k) => 12.0 * e * i / (k * g * s.area * l * l),
        None => 0.0,
    };
    let mut k = DMatrix::zeros(12, 12);
    let mut add_pair = |i: usize, j: usize, value: f64| {
        k[(i, i)] += value;
        k[(j, j)] += value;
        k[(i, j)] -= value;
        k[(j, i)] -= value;
    };
    add_pair(0, 6, e * s.area / l);
    add_pair(3, 9, g * s.torsion_constant / l);

    // Bending block in (deflection, rotation) of both nodes, rotation = +d(deflection)/dx.
    let bending = |i: f64| {
        let phi = phi(i);
        let c = e * i / ((1.0 + phi) * l * l * l);
        let (a, b, d, f) = (
            12.0 * c,
            6.0 * l * c,
            (4.0 + phi) * l * l * c,
            (2.0 - phi) * l * l * c,
        );
        [[a, b, -a, b], [b, d, -b, f], [-a, -b, a, -b], [b, f, -b, d]]
    };
    // x–y plane: v (1, 7) and θz (5, 11), θz = dv/dx.
    let xy = bending(s.iz);
    let xy_dofs = [1, 5, 7, 11];
    // x–z plane: w (2, 8) and θy (4, 10), θy = −dw/dx: the same block in (w, −θy).
    let xz = bending(s.iy);
    let xz_dofs = [2, 4, 8, 10];
    let xz_sign = [1.0, -1.0, 1.0, -1.0];
    for r in 0..4 {
        for c in 0..4 {
            k[(xy_dofs[r], xy_dofs[c])] += xy[r][c];
            k[(xz_dofs[r], xz_dofs[c])] += xz_sign[r] * xz_sign[c] * xz[r][c];
        }
    }
    k
}

#[cfg(test)]
mod tests;
