//! Tests of the beam: rigid motions, cantilever deflections against beam theory, axial and torsion,
//! the orientation vector, the lumped mass.

use nalgebra::{DVector, Matrix3, Vector3};

use super::*;
use crate::element::test_support::{assert_rigid_body_modes, DenseModel};

const E: f64 = 210e9;
const NU: f64 = 0.3;
const RHO: f64 = 7800.0;

fn steel() -> Material {
    Material {
        name: "steel".into(),
        youngs_modulus: E,
        poisson_ratio: NU,
        density: RHO,
    }
}

/// Lumped mass, with or without rotary inertia.
fn options(rotary_inertia: bool) -> ModelOptions {
    ModelOptions { rotary_inertia, ..Default::default() }
}

fn section(orientation: Vector3<f64>, shear_coefficient: Option<f64>) -> BeamSection {
    BeamSection {
        name: "s".into(),
        material: 0,
        area: 4e-3,
        iy: 2e-6,
        iz: 5e-6,
        torsion_constant: 3e-6,
        orientation,
        shear_coefficient,
        outline: Default::default(),
    }
}

/// An oblique beam in space and its direction matrix (rows: local x, y, z).
fn oblique_beam() -> (Vector3<f64>, Vector3<f64>, Vector3<f64>, Matrix3<f64>) {
    let a = Vector3::new(0.3, -0.2, 1.0);
    let b = a + Vector3::new(1.2, 0.8, -0.5);
    let orientation = Vector3::new(0.2, 0.1, 1.0);
    let x = (b - a).normalize();
    let y = (orientation - x * x.dot(&orientation)).normalize();
    let z = x.cross(&y);
    (
        a,
        b,
        orientation,
        Matrix3::from_rows(&[x.transpose(), y.transpose(), z.transpose()]),
    )
}

/// The tip displacement and rotation (body frame) of a single-element cantilever clamped at `a`
/// under a tip force and torque (body frame).
fn cantilever_tip(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    section: &BeamSection,
    force: Vector3<f64>,
    torque: Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let k = beam_matrices(a, b, section, &steel(), &options(false))
        .unwrap()
        .stiffness;
    let mut model = DenseModel::new(2);
    model.add(&[0, 1], &k);
    let mut loads = DVector::zeros(12);
    loads.fixed_rows_mut::<3>(6).copy_from(&force);
    loads.fixed_rows_mut::<3>(9).copy_from(&torque);
    let clamped: Vec<(usize, f64)> = (0..6).map(|d| (d, 0.0)).collect();
    let u = model.solve(&clamped, &loads);
    (
        u.fixed_rows::<3>(6).into_owned(),
        u.fixed_rows::<3>(9).into_owned(),
    )
}

fn assert_vector_close(actual: &Vector3<f64>, expected: &Vector3<f64>, tol: f64, what: &str) {
    let error = (actual - expected).norm() / expected.norm();
    assert!(
        error < tol,
        "{what}: {actual:?} vs {expected:?}, relative error {error:e}"
    );
}

#[test]
fn oblique_beam_has_exactly_six_rigid_body_modes() {
    let (a, b, orientation, _) = oblique_beam();
    for k in [None, Some(5.0 / 6.0)] {
        let m = beam_matrices(&a, &b, &section(orientation, k), &steel(), &options(true)).unwrap();
        let seventh = assert_rigid_body_modes(&m.stiffness, &[a, b], 1e-6);
        assert!(seventh < 1.0);
    }
}

#[test]
fn euler_bernoulli_cantilever_is_exact_in_both_planes() {
    // Beam along body x, local y = body y, local z = body z.
    let (a, b) = (Vector3::zeros(), Vector3::new(1.5, 0.0, 0.0));
    let l: f64 = 1.5;
    let s = section(Vector3::y(), None);
    let p = 1000.0;
    // x–y plane: Iz, tip rotation about +z.
    let (u, r) = cantilever_tip(&a, &b, &s, Vector3::new(0.0, p, 0.0), Vector3::zeros());
    assert_vector_close(
        &u,
        &Vector3::new(0.0, p * l.powi(3) / (3.0 * E * s.iz), 0.0),
        1e-12,
        "x-y deflection",
    );
    assert_vector_close(
        &r,
        &Vector3::new(0.0, 0.0, p * l * l / (2.0 * E * s.iz)),
        1e-12,
        "x-y rotation",
    );
    // x–z plane: Iy, a positive w turns the axis about −y.
    let (u, r) = cantilever_tip(&a, &b, &s, Vector3::new(0.0, 0.0, p), Vector3::zeros());
    assert_vector_close(
        &u,
        &Vector3::new(0.0, 0.0, p * l.powi(3) / (3.0 * E * s.iy)),
        1e-12,
        "x-z deflection",
    );
    assert_vector_close(
        &r,
        &Vector3::new(0.0, -p * l * l / (2.0 * E * s.iy), 0.0),
        1e-12,
        "x-z rotation",
    );
}

#[test]
fn oblique_cantilever_is_exact_in_local_axes() {
    let (a, b, orientation, axes) = oblique_beam();
    let l = (b - a).norm();
    let (ex, ey, ez) = (
        axes.row(0).transpose(),
        axes.row(1).transpose(),
        axes.row(2).transpose(),
    );
    let p = 700.0;
    for (shear, label) in [(None, "Euler-Bernoulli"), (Some(0.85), "Timoshenko")] {
        let s = section(orientation, shear);
        let g = steel().shear_modulus();
        let shear_flexibility = shear.map_or(0.0, |k| p * l / (k * g * s.area));
        // Load along local y: deflection along y, rotation about +z, second moment Iz.
        let (u, r) = cantilever_tip(&a, &b, &s, ey * p, Vector3::zeros());
        let deflection = p * l.powi(3) / (3.0 * E * s.iz) + shear_flexibility;
        assert_vector_close(&u, &(ey * deflection), 1e-11, label);
        assert_vector_close(&r, &(ez * (p * l * l / (2.0 * E * s.iz))), 1e-11, label);
        // Load along local z: deflection along z, rotation about −y, second moment Iy.
        let (u, r) = cantilever_tip(&a, &b, &s, ez * p, Vector3::zeros());
        let deflection = p * l.powi(3) / (3.0 * E * s.iy) + shear_flexibility;
        assert_vector_close(&u, &(ez * deflection), 1e-11, label);
        assert_vector_close(&r, &(-ey * (p * l * l / (2.0 * E * s.iy))), 1e-11, label);
        // Axial force and torque.
        let (u, r) = cantilever_tip(&a, &b, &s, ex * p, ex * p);
        assert_vector_close(&u, &(ex * (p * l / (E * s.area))), 1e-11, label);
        assert_vector_close(&r, &(ex * (p * l / (g * s.torsion_constant))), 1e-11, label);
    }
}

#[test]
fn timoshenko_cantilever_adds_shear_deflection() {
    // A short, deep beam, where shear deformation is a large part of the deflection.
    let (a, b) = (Vector3::zeros(), Vector3::new(0.2, 0.0, 0.0));
    let (l, k, p): (f64, f64, f64) = (0.2, 5.0 / 6.0, 1000.0);
    let s = section(Vector3::y(), Some(k));
    let g = steel().shear_modulus();
    let (u, r) = cantilever_tip(&a, &b, &s, Vector3::new(0.0, p, 0.0), Vector3::zeros());
    let bending = p * l.powi(3) / (3.0 * E * s.iz);
    let shear = p * l / (k * g * s.area);
    assert!(shear > 0.1 * bending);
    assert_vector_close(
        &u,
        &Vector3::new(0.0, bending + shear, 0.0),
        1e-12,
        "deflection",
    );
    assert_vector_close(
        &r,
        &Vector3::new(0.0, 0.0, p * l * l / (2.0 * E * s.iz)),
        1e-12,
        "rotation",
    );
}

#[test]
fn orientation_vector_chooses_the_bending_planes() {
    let (a, b) = (Vector3::zeros(), Vector3::new(2.0, 0.0, 0.0));
    let p = 100.0;
    let force = Vector3::new(0.0, p, 0.0);
    // Orientation y: body y is local y, bending about local z with Iz.
    let s = section(Vector3::y(), None);
    let (u, _) = cantilever_tip(&a, &b, &s, force, Vector3::zeros());
    assert!((u.y / (p * 8.0 / (3.0 * E * s.iz)) - 1.0).abs() < 1e-12);
    // Orientation (0.4, 0, 2), normal part along z: local y is body z, local z = x × y is −body y,
    // bending with Iy.
    let s = section(Vector3::new(0.4, 0.0, 2.0), None);
    let (u, r) = cantilever_tip(&a, &b, &s, force, Vector3::zeros());
    assert!((u.y / (p * 8.0 / (3.0 * E * s.iy)) - 1.0).abs() < 1e-12);
    assert!((r.z / (p * 4.0 / (2.0 * E * s.iy)) - 1.0).abs() < 1e-12);
    assert!(u.z.abs() < 1e-12 * u.y.abs());
}

#[test]
fn lumped_mass_and_rotated_rotary_inertia() {
    let (a, b, orientation, axes) = oblique_beam();
    let l = (b - a).norm();
    let s = section(orientation, None);
    let m = rho_a_l(&s, l);
    let without = beam_matrices(&a, &b, &s, &steel(), &options(false)).unwrap();
    let total: f64 = without.lumped_mass.iter().map(|n| n.mass).sum();
    assert!((total / m - 1.0).abs() < 1e-14);
    assert!(without
        .lumped_mass
        .iter()
        .all(|n| n.rotary_inertia == Matrix3::zeros()));

    let with = beam_matrices(&a, &b, &s, &steel(), &options(true)).unwrap();
    let expected_local = [
        RHO * (s.iy + s.iz) * l / 2.0,
        m * l * l / 24.0 + RHO * s.iy * l / 2.0,
        m * l * l / 24.0 + RHO * s.iz * l / 2.0,
    ];
    for node in &with.lumped_mass {
        assert!((node.mass / (m / 2.0) - 1.0).abs() < 1e-14);
        let j = node.rotary_inertia;
        assert!((j - j.transpose()).amax() < 1e-14 * j.amax());
        // Each local axis is a principal axis with the local moment of inertia.
        for (k, &moment) in expected_local.iter().enumerate() {
            let axis = axes.row(k).transpose();
            assert!(
                (j * axis - axis * moment).norm() < 1e-12 * moment,
                "axis {k}"
            );
        }
    }
}

fn rho_a_l(s: &BeamSection, l: f64) -> f64 {
    RHO * s.area * l
}

#[test]
fn bad_geometry_and_properties_are_reported() {
    let a = Vector3::new(1.0, 2.0, 3.0);
    let s = section(Vector3::z(), None);
    assert_eq!(
        beam_matrices(&a, &a, &s, &steel(), &options(false)),
        Err(ElementError::ZeroLength)
    );
    let b = a + Vector3::new(0.0, 0.0, 1.0);
    assert_eq!(
        beam_matrices(&a, &b, &s, &steel(), &options(false)),
        Err(ElementError::OrientationParallel)
    );
    let zero = section(Vector3::zeros(), None);
    assert_eq!(
        beam_matrices(&a, &b, &zero, &steel(), &options(false)),
        Err(ElementError::OrientationParallel)
    );
    let b = a + Vector3::x();
    let bad = BeamSection {
        area: -1.0,
        ..s.clone()
    };
    assert!(matches!(
        beam_matrices(&a, &b, &bad, &steel(), &options(false)),
        Err(ElementError::InvalidProperty { .. })
    ));
    let light = Material {
        density: -1.0,
        ..steel()
    };
    assert!(matches!(
        beam_matrices(&a, &b, &s, &light, &options(false)),
        Err(ElementError::OutOfRange { .. })
    ));
    let rubber = Material {
        poisson_ratio: 0.6,
        ..steel()
    };
    assert!(matches!(
        beam_matrices(&a, &b, &s, &rubber, &options(false)),
        Err(ElementError::OutOfRange { .. })
    ));
}

/// Przemieniecki's consistent mass (1968, eqs. 11.31 and 11.41) in local axes, dofs
/// `u v w θx θy θz` of both nodes: axial, bending (Hermite cubics), and with rotary inertia the
/// torsion and Rayleigh terms.
fn przemieniecki_consistent_mass(s: &BeamSection, l: f64, rotary: bool) -> DMatrix<f64> {
    let m = rho_a_l(s, l);
    let mut k = DMatrix::zeros(12, 12);
    let pair = |k: &mut DMatrix<f64>, i: usize, j: usize, c: f64| {
        k[(i, i)] += 2.0 * c;
        k[(j, j)] += 2.0 * c;
        k[(i, j)] += c;
        k[(j, i)] += c;
    };
    pair(&mut k, 0, 6, m / 6.0);
    let translation = [
        [156.0, 22.0 * l, 54.0, -13.0 * l],
        [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
        [54.0, 13.0 * l, 156.0, -22.0 * l],
        [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
    ];
    let rayleigh = [
        [36.0, 3.0 * l, -36.0, 3.0 * l],
        [3.0 * l, 4.0 * l * l, -3.0 * l, -l * l],
        [-36.0, -3.0 * l, 36.0, -3.0 * l],
        [3.0 * l, -l * l, -3.0 * l, 4.0 * l * l],
    ];
    let planes = [([1, 5, 7, 11], [1.0; 4], s.iz), ([2, 4, 8, 10], [1.0, -1.0, 1.0, -1.0], s.iy)];
    for (dofs, sign, i) in planes {
        for r in 0..4 {
            for c in 0..4 {
                let mut value = m / 420.0 * translation[r][c];
                if rotary {
                    value += RHO * i / (30.0 * l) * rayleigh[r][c];
                }
                k[(dofs[r], dofs[c])] += sign[r] * sign[c] * value;
            }
        }
    }
    if rotary {
        pair(&mut k, 3, 9, RHO * (s.iy + s.iz) * l / 6.0);
    }
    k
}

#[test]
fn consistent_mass_points_give_przemieniecki_consistent_mass() {
    let (a, b, orientation, axes) = oblique_beam();
    let l = (b - a).norm();
    let s = section(orientation, None);
    let t = crate::element::test_support::block_rotation(2, &axes);
    for rotary in [false, true] {
        let consistent = ModelOptions { mass: Some(MassModel::Consistent), ..options(rotary) };
        let points = beam_matrices(&a, &b, &s, &steel(), &consistent).unwrap().consistent_mass;
        assert_eq!(points.len(), 4);
        let body = crate::element::test_support::mass_matrix_of_points(&points, 2);
        let expected = t.transpose() * przemieniecki_consistent_mass(&s, l, rotary) * &t;
        let error = (&body - &expected).amax() / expected.amax();
        assert!(error < 1e-13, "rotary inertia {rotary}: relative error {error:.2e}");
        // The points sit on the axis and carry the whole mass.
        let total: f64 = points.iter().map(|p| p.mass).sum();
        assert!((total / rho_a_l(&s, l) - 1.0).abs() < 1e-14);
        for p in &points {
            let along = (p.position - a).dot(&(b - a)) / (l * l);
            assert!((p.position - (a + along * (b - a))).norm() < 1e-14 && (0.0..=1.0).contains(&along));
        }
    }
}

/// Euler buckling of an oblique cantilever of 16 elements: the smallest loads `P` with
/// `(K − P K_geo(N = 1)) φ = 0` are `π² E I / (4 L²)` for `Iy` and for `Iz` (Timoshenko and Gere,
/// *Theory of Elastic Stability*, 1961, §2.1), to the discretization error of cubic elements.
#[test]
fn geometric_stiffness_gives_the_euler_buckling_loads_of_a_cantilever() {
    let (a, b, orientation, _) = oblique_beam();
    let s = section(orientation, None);
    let n = 16;
    let size = 6 * (n + 1);
    let (mut k, mut kg) = (nalgebra::DMatrix::<f64>::zeros(size, size), nalgebra::DMatrix::<f64>::zeros(size, size));
    for e in 0..n {
        let pa = a + (b - a) * (e as f64 / n as f64);
        let pb = a + (b - a) * ((e + 1) as f64 / n as f64);
        let ke = beam_matrices(&pa, &pb, &s, &steel(), &options(false)).unwrap().stiffness;
        let ge = beam_geometric_stiffness(&pa, &pb, &s, 1.0).unwrap();
        for r in 0..12 {
            for c in 0..12 {
                k[(6 * e + r, 6 * e + c)] += ke[(r, c)];
                kg[(6 * e + r, 6 * e + c)] += ge[(r, c)];
            }
        }
    }
    // Clamp node 0.
    let k = k.view((6, 6), (size - 6, size - 6)).into_owned();
    let kg = kg.view((6, 6), (size - 6, size - 6)).into_owned();
    let l = k.cholesky().unwrap().l();
    let l_inv = l.try_inverse().unwrap();
    let reduced: nalgebra::DMatrix<f64> = &l_inv * kg * l_inv.transpose();
    let mut mu: Vec<f64> = nalgebra::SymmetricEigen::new((&reduced + reduced.transpose()) * 0.5).eigenvalues.iter().copied().collect();
    mu.sort_by(|x, y| y.total_cmp(x));
    let length = (b - a).norm();
    let euler = |i: f64| std::f64::consts::PI.powi(2) * E * i / (4.0 * length * length);
    assert!((1.0 / mu[0] / euler(s.iy) - 1.0).abs() < 1e-4, "{} vs {}", 1.0 / mu[0], euler(s.iy));
    assert!((1.0 / mu[1] / euler(s.iz) - 1.0).abs() < 1e-4, "{} vs {}", 1.0 / mu[1], euler(s.iz));
}

/// The axial force of a stretched beam is `E A δ / L` whatever its orientation; a transverse motion
/// gives none.
#[test]
fn axial_force_is_the_stretch_along_the_axis() {
    let (a, b, orientation, axes) = oblique_beam();
    let s = section(orientation, None);
    let x: Vector3<f64> = axes.row(0).transpose();
    let y: Vector3<f64> = axes.row(1).transpose();
    let length = (b - a).norm();
    let stretch = axial_force(&a, &b, &s, &steel(), &Vector3::zeros(), &(1e-4 * x)).unwrap();
    assert!((stretch / (E * s.area * 1e-4 / length) - 1.0).abs() < 1e-12);
    let sideways = axial_force(&a, &b, &s, &steel(), &Vector3::zeros(), &(1e-4 * y)).unwrap();
    assert!(sideways.abs() < 1e-9 * stretch);
}
