//! Builders of the FE models the tests share: steel beams and plates, supports, static loads.
#![allow(dead_code)]

use flexmb_fem::mesh::{ModelOptions, ShellShape};
use flexmb_fem::{BeamSection, Dof, DofSet, FeModel, Material, Mesh, ShellSection, StaticLoad, StaticLoadKind, Support};
use nalgebra::Vector3;

pub const E: f64 = 2.1e11;
pub const NU: f64 = 0.3;
pub const RHO: f64 = 7850.0;

pub fn steel() -> Material {
    Material { name: "steel".into(), youngs_modulus: E, poisson_ratio: NU, density: RHO }
}

/// A square solid section of side `h`: A = h², I = h⁴/12, J ≈ 0.1406 h⁴.
pub fn square_section(h: f64) -> BeamSection {
    BeamSection {
        name: "square".into(),
        material: 0,
        area: h * h,
        iy: h.powi(4) / 12.0,
        iz: h.powi(4) / 12.0,
        torsion_constant: 0.1406 * h.powi(4),
        orientation: Vector3::new(0.0, 1.0, 0.0),
        shear_coefficient: None,
        outline: flexmb_fem::SectionOutline::Rectangle { half_y: h / 2.0, half_z: h / 2.0 },
    }
}

/// A straight beam of `n` elements from the origin to (L, 0, 0), no supports.
pub fn beam(length: f64, n: usize, section: BeamSection) -> FeModel {
    let mut mesh = Mesh { materials: vec![steel()], beam_sections: vec![section], ..Default::default() };
    mesh.add_beam_line(Vector3::zeros(), Vector3::new(length, 0.0, 0.0), n, 0).unwrap();
    FeModel { mesh, ..Default::default() }
}

/// A cantilever: the beam of [`beam`] clamped (all dofs) at the origin.
pub fn cantilever(length: f64, n: usize, section: BeamSection) -> FeModel {
    let mut model = beam(length, n, section);
    model.supports.push(Support { node: 0, dofs: DofSet::ALL });
    model
}

/// Euler–Bernoulli frequency (Hz) of a beam mode with eigenvalue βL.
pub fn beam_frequency(beta_l: f64, length: f64, section: &BeamSection) -> f64 {
    beta_l.powi(2) / (2.0 * std::f64::consts::PI) * (E * section.iy / (RHO * section.area * length.powi(4))).sqrt()
}

/// A flat plate a × b × t in the x–y plane with a corner at the origin, `na × nb` elements.
pub fn plate(a: f64, b: f64, t: f64, na: usize, nb: usize, shape: ShellShape) -> (FeModel, Vec<Vec<usize>>) {
    let mut mesh = Mesh {
        materials: vec![steel()],
        shell_sections: vec![ShellSection { name: "plate".into(), material: 0, thickness: t }],
        ..Default::default()
    };
    let grid = mesh.add_rectangular_plate(
        Vector3::zeros(),
        Vector3::new(a, 0.0, 0.0),
        Vector3::new(0.0, b, 0.0),
        na,
        nb,
        0,
        shape,
    ).unwrap();
    (FeModel { mesh, options: ModelOptions::default(), ..Default::default() }, grid)
}

/// The plate of [`plate`], simply supported: `uz = 0` on its four edges (in-plane motion left free,
/// so three rigid in-plane motions remain).
pub fn simply_supported_plate(a: f64, b: f64, t: f64, na: usize, nb: usize, shape: ShellShape) -> FeModel {
    let (mut model, grid) = plate(a, b, t, na, nb, shape);
    for (i, column) in grid.iter().enumerate() {
        for (j, &node) in column.iter().enumerate() {
            if i == 0 || j == 0 || i == na || j == nb {
                model.supports.push(Support { node, dofs: DofSet::EMPTY.with(Dof::Uz) });
            }
        }
    }
    model
}

/// Kirchhoff frequency (Hz) of mode (i, j) of a simply supported plate a × b × t.
pub fn plate_frequency(i: usize, j: usize, a: f64, b: f64, t: f64) -> f64 {
    let (i, j) = (i as f64, j as f64);
    std::f64::consts::PI / 2.0 * ((i / a).powi(2) + (j / b).powi(2)) * (E * t * t / (12.0 * RHO * (1.0 - NU * NU))).sqrt()
}

pub fn force(name: &str, node: usize, direction: [f64; 3]) -> StaticLoad {
    StaticLoad { name: name.into(), node, kind: StaticLoadKind::Force(Vector3::from(direction)) }
}

pub fn torque(name: &str, node: usize, axis: [f64; 3]) -> StaticLoad {
    StaticLoad { name: name.into(), node, kind: StaticLoadKind::Torque(Vector3::from(axis)) }
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
