//! Stress recovery of the beam: at each end, the section's stress resultants from the element's
//! end forces `K_loc T u` (axial force N, torque T, bending moments My, Mz), and from them the
//! stress at the section's extreme fibres — the corners of a rectangle or a box, eight points around
//! a circle or a tube (every 45°), the corners of the equivalent rectangle of a section given by its
//! properties only:
//!
//! - axial `σxx = N / A − Mz y / Iz + My z / Iy` (local axes; θz = dv/dx, θy = −dw/dx);
//! - torsional shear `τ = T r / J` tangential to the fibre's radius r: Saint-Venant's exact value
//!   for circles and tubes; for rectangles a bound (their corners carry none, their largest shear,
//!   at the middle of the long sides, is smaller than `T r_corner / J`);
//! - no transverse shear: `V Q / (I b)` is zero at the extreme fibres.
//!
//! Each end's stresses are its own (not averaged with the neighbour's at the node): members that
//! meet at an angle have different fibres there.

use nalgebra::{DMatrix, Vector3};

use super::{local_axes, local_stiffness, SectionProperties};
use crate::element::stress_points::{ElementStress, StressPlace};
use crate::element::validate::Elastic;
use crate::element::ElementError;
use crate::mesh::{BeamSection, Material, SectionOutline};

/// The stress at the extreme fibres of both end sections of the beam from `a` to `b`.
pub fn beam_stress_matrix(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    section: &BeamSection,
    material: &Material,
) -> Result<ElementStress, ElementError> {
    let elastic = Elastic::new(material)?;
    let properties = SectionProperties::checked(section)?;
    let axes = local_axes(a, b, &section.orientation)?;
    let length = (b - a).norm();
    let mut t = DMatrix::zeros(12, 12);
    for block in 0..4 {
        t.fixed_view_mut::<3, 3>(3 * block, 3 * block).copy_from(&axes);
    }
    // Local end forces from the body-frame displacements.
    let forces = local_stiffness(length, &elastic, &properties) * t;
    let fibres = fibres(section);
    let mut matrix = DMatrix::zeros(6 * 2 * fibres.len(), 12);
    let mut points = Vec::new();
    for end in 0..2 {
        // The resultants on the section (tension, moments of the part beyond it): minus the end
        // force at node a, the end force at node b.
        let sign = if end == 0 { -1.0 } else { 1.0 };
        let resultant = |dof: usize| forces.row(6 * end + dof) * sign;
        let (n, torque, my, mz) = (resultant(0), resultant(3), resultant(4), resultant(5));
        for (k, &(y, z)) in fibres.iter().enumerate() {
            let r = (y * y + z * z).sqrt();
            let axial = &n / properties.area - &mz * (y / properties.iz) + &my * (z / properties.iy);
            let shear = &torque * (r / properties.torsion_constant);
            let (tau_xy, tau_xz) = (&shear * (-z / r), &shear * (y / r));
            let p = points.len();
            for (c, (i, j)) in [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                // Body components of Λᵀ σ_loc Λ, σ_loc holding σxx, τxy, τxz.
                let l = |row: usize, col: usize| axes[(row, col)];
                let row = &axial * (l(0, i) * l(0, j))
                    + &tau_xy * (l(0, i) * l(1, j) + l(1, i) * l(0, j))
                    + &tau_xz * (l(0, i) * l(2, j) + l(2, i) * l(0, j));
                matrix.row_mut(6 * p + c).copy_from(&row);
            }
            points.push((end, StressPlace::Fibre(k as u8)));
        }
    }
    Ok(ElementStress { points, matrix, shared: false })
}

/// The extreme fibres `(y, z)` of the section.
fn fibres(section: &BeamSection) -> Vec<(f64, f64)> {
    let corners = |hy: f64, hz: f64| vec![(hy, hz), (-hy, hz), (-hy, -hz), (hy, -hz)];
    match section.outline {
        SectionOutline::Rectangle { half_y, half_z } => corners(half_y, half_z),
        SectionOutline::Round { radius } => (0..8)
            .map(|k| {
                let angle = k as f64 * std::f64::consts::FRAC_PI_4;
                (radius * angle.cos(), radius * angle.sin())
            })
            .collect(),
        SectionOutline::Equivalent => {
            corners((3.0 * section.iz / section.area).sqrt(), (3.0 * section.iy / section.area).sqrt())
        }
    }
}
