//! Vibration modes of a simply supported rectangular plate against Kirchhoff theory,
//! `f = (π/2)((i/a)² + (j/b)²) √(E t² / (12 ρ (1 − ν²)))`, for quadrilateral and triangular flat
//! shells, with mesh convergence; the in-plane rigid motions the supports leave are found and set
//! aside; the Lanczos path agrees with the dense one. On a thick plate the quadrilaterals (MITC4)
//! converge to Mindlin's frequencies and the triangles (DKT) to Kirchhoff's.

mod support;

use flexmb_fem::mesh::ShellShape;
use flexmb_fem::modes::{vibration_modes, EigenSettings, EigenSolver};
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use flexmb_fem::MassModel;
use nalgebra::Vector3;
use support::*;

const A: f64 = 1.0;
const B: f64 = 0.8;
const T: f64 = 0.005;

/// The lowest `count` Kirchhoff frequencies, ascending.
fn kirchhoff(count: usize) -> Vec<f64> {
    let mut f: Vec<f64> = (1..=8).flat_map(|i| (1..=8).map(move |j| plate_frequency(i, j, A, B, T))).collect();
    f.sort_by(f64::total_cmp);
    f.truncate(count);
    f
}

fn errors(na: usize, nb: usize, shape: ShellShape, count: usize) -> Vec<f64> {
    errors_with(na, nb, shape, count, MassModel::Lumped)
}

fn errors_with(na: usize, nb: usize, shape: ShellShape, count: usize, mass: MassModel) -> Vec<f64> {
    let mut model = simply_supported_plate(A, B, T, na, nb, shape);
    model.options.mass = Some(mass);
    let modes = vibration_modes(&model, count, &EigenSettings::default()).unwrap();
    assert_eq!(modes.rigid_modes, 3, "in-plane translations and turn are left free");
    modes.frequencies_hz.iter().zip(kirchhoff(count)).map(|(f, reference)| rel(*f, reference)).collect()
}

#[test]
fn quadrilateral_plate_frequencies_converge_to_kirchhoff() {
    let coarse = errors(10, 8, ShellShape::Quadrilateral, 6);
    let fine = errors(20, 16, ShellShape::Quadrilateral, 6);
    println!("quadrilaterals 10×8:  {coarse:?}\nquadrilaterals 20×16: {fine:?}");
    for k in 0..6 {
        assert!(fine[k] < coarse[k], "mode {}: {} then {}", k + 1, coarse[k], fine[k]);
        assert!(fine[k] < 0.02, "mode {}: error {:.2e} at 20×16", k + 1, fine[k]);
    }
    assert!(fine[0] < 5e-3, "first mode error {:.2e}", fine[0]);
}

#[test]
fn triangle_plate_frequencies_converge_to_kirchhoff() {
    let coarse = errors(10, 8, ShellShape::Triangle, 6);
    let fine = errors(20, 16, ShellShape::Triangle, 6);
    println!("triangles 10×8:  {coarse:?}\ntriangles 20×16: {fine:?}");
    for k in 0..6 {
        assert!(fine[k] < coarse[k], "mode {}: {} then {}", k + 1, coarse[k], fine[k]);
        assert!(fine[k] < 0.03, "mode {}: error {:.2e} at 20×16", k + 1, fine[k]);
    }
}

/// The consistent mass of the flat shells (bilinear or linear fields) converges at second order too,
/// but on plates it is less accurate than the lumped one: at 20 × 16 the six errors are
/// 0.34–3.4 % (quadrilaterals) and 0.42–2.7 % (triangles), against 0.13–0.67 % and 0.10–0.46 %
/// lumped. For shells the lumped mass is the better choice; the consistent one pays off on beams.
#[test]
fn consistent_mass_plate_frequencies_converge_to_kirchhoff() {
    for shape in [ShellShape::Quadrilateral, ShellShape::Triangle] {
        let coarse = errors_with(10, 8, shape, 6, MassModel::Consistent);
        let fine = errors_with(20, 16, shape, 6, MassModel::Consistent);
        println!("consistent {shape:?} 10×8:  {coarse:?}\nconsistent {shape:?} 20×16: {fine:?}");
        for k in 0..6 {
            let order = (coarse[k] / fine[k]).log2();
            assert!(order > 1.5, "{shape:?} mode {}: {} then {}, order {order:.2}", k + 1, coarse[k], fine[k]);
            assert!(fine[k] < 0.04, "{shape:?} mode {}: error {:.2e} at 20×16", k + 1, fine[k]);
        }
    }
}

#[test]
fn square_plate_has_repeated_frequencies_and_lanczos_agrees_with_dense() {
    // (1,2) and (2,1) of a square plate have the same frequency.
    let model = simply_supported_plate(1.0, 1.0, T, 14, 14, ShellShape::Quadrilateral);
    let dense = vibration_modes(&model, 6, &EigenSettings { solver: EigenSolver::Dense, ..Default::default() }).unwrap();
    let lanczos = vibration_modes(&model, 6, &EigenSettings { solver: EigenSolver::Lanczos, ..Default::default() }).unwrap();
    let f = &lanczos.frequencies_hz;
    assert!(rel(f[1], f[2]) < 1e-8, "repeated pair {} {}", f[1], f[2]);
    for (a, b) in dense.frequencies_hz.iter().zip(f) {
        assert!(rel(*b, *a) < 1e-9, "dense {a} vs Lanczos {b}");
    }
    assert!(lanczos.max_orthogonality_error < 1e-9, "{}", lanczos.max_orthogonality_error);
}

#[test]
fn plate_invariants_are_its_rigid_properties() {
    let model = simply_supported_plate(A, B, T, 10, 8, ShellShape::Quadrilateral);
    let settings = ReductionSettings { mode_set: "3N".parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let body = reduce(&model, "plate", &settings).unwrap().body;
    let mass = RHO * A * B * T;
    assert!(rel(body.invariants.mass, mass) < 1e-12);
    assert!((body.mass_properties.center_of_mass - Vector3::new(A / 2.0, B / 2.0, 0.0)).norm() < 1e-12);
    // Lumped masses at the nodes of a regular grid: Σ mᵢ yᵢ² about the centre is the trapezoidal rule,
    // m b² (1/12 + 1/(6 nb²)); likewise in x.
    let i = body.mass_properties.inertia;
    assert!(rel(i[(0, 0)], mass * B * B * (1.0 / 12.0 + 1.0 / (6.0 * 64.0))) < 1e-12, "Ixx {}", i[(0, 0)]);
    assert!(rel(i[(1, 1)], mass * A * A * (1.0 / 12.0 + 1.0 / (6.0 * 100.0))) < 1e-12, "Iyy {}", i[(1, 1)]);
    assert!(rel(i[(2, 2)], i[(0, 0)] + i[(1, 1)]) < 1e-12, "perpendicular axes");
    assert_eq!(body.rigid_modes, 3);
    // The consistent mass integrates x² and y² exactly: m b² / 12 and m a² / 12.
    let mut model = model;
    model.options.mass = Some(MassModel::Consistent);
    let body = reduce(&model, "plate", &settings).unwrap().body;
    let i = body.mass_properties.inertia;
    assert!(rel(body.invariants.mass, mass) < 1e-12);
    assert!(rel(i[(0, 0)], mass * B * B / 12.0) < 1e-12, "Ixx {}", i[(0, 0)]);
    assert!(rel(i[(1, 1)], mass * A * A / 12.0) < 1e-12, "Iyy {}", i[(1, 1)]);
}

/// A mesh whose mode analysis needs more memory than it may use is refused before it is assembled,
/// with what it needs; the estimate of a 300 × 300 plate is the 1.5 GB its analysis was measured to
/// take (a beam line of 10⁶ elements aborted on a 3.2 GB allocation before). So is the dense solver.
#[test]
fn a_mesh_larger_than_the_memory_limit_is_refused_before_it_is_assembled() {
    let model = simply_supported_plate(A, B, T, 20, 16, ShellShape::Quadrilateral);
    // 320 shells of 24² stiffness triplets and 64 Krylov vectors of 357 × 6 dofs.
    let needed = flexmb_fem::memory::mode_analysis_bytes(&model.mesh);
    assert_eq!(needed, 320 * 576 * 24 + 357 * 6 * 64 * 8);
    let limited = EigenSettings { memory_limit: Some(needed - 1), ..Default::default() };
    let e = vibration_modes(&model, 6, &limited).unwrap_err();
    assert_eq!(e, flexmb_fem::FemError::TooLarge { elements: 320, nodes: 357, needed, limit: needed - 1 });
    assert!(e.to_string().starts_with("the mesh is too large for the mode analysis: 320 elements and 357 nodes need about 5.3 MiB, more than the 5.3 MiB it may use"), "{e}");
    let settings = ReductionSettings { mode_set: "4N".parse().unwrap(), basis: Basis::Orthonormal, eigen: limited };
    assert!(matches!(reduce(&model, "plate", &settings), Err(flexmb_fem::FemError::TooLarge { .. })));
    let enough = EigenSettings { memory_limit: Some(needed), ..Default::default() };
    assert!(vibration_modes(&model, 6, &enough).is_ok());
    // The dense eigensolver holds about six matrices of the operator's dimension (the plate's massive
    // dofs): checked once that is known (`--solver dense` on 1600 × 12 shells asked for 28 GB).
    let dense = EigenSettings { solver: EigenSolver::Dense, memory_limit: Some(10_000_000), ..Default::default() };
    let e = vibration_modes(&model, 6, &dense).unwrap_err();
    assert!(matches!(e, flexmb_fem::FemError::DenseTooLarge { .. }), "{e}");
    assert!(e.to_string().ends_with("more than the 9.5 MiB it may use; use the Lanczos solver"), "{e}");
    let lanczos = EigenSettings { solver: EigenSolver::Lanczos, ..dense };
    assert!(vibration_modes(&model, 6, &lanczos).is_ok());
    let large = simply_supported_plate(A, B, T, 300, 300, ShellShape::Quadrilateral);
    let gb = flexmb_fem::memory::mode_analysis_bytes(&large.mesh) as f64 / 1e9;
    assert!((1.4..1.6).contains(&gb), "{gb} GB");
}

/// A plate at z = −1e300: its rigid motions about the mesh centre overflow (the centre itself is off
/// by 1e284), and the mode analysis ends with an error instead of the Lanczos iteration's thousand
/// restarts on NaN, which took minutes (found by the fuzz test).
#[test]
fn an_operator_that_overflows_is_an_error_not_a_thousand_restarts() {
    let mut model = simply_supported_plate(A, B, T, 20, 16, ShellShape::Quadrilateral);
    for node in &mut model.mesh.nodes {
        node.position.z -= 1e300;
    }
    for solver in [EigenSolver::Lanczos, EigenSolver::Dense] {
        let settings = EigenSettings { solver, ..Default::default() };
        let started = std::time::Instant::now();
        assert_eq!(vibration_modes(&model, 6, &settings).unwrap_err(), flexmb_fem::FemError::NotFinite, "{solver:?}");
        assert!(started.elapsed().as_secs_f64() < 5.0, "{solver:?}");
    }
}

/// A film (the plate 0.5 µm thick: its bending 10¹⁸ times softer than at 5 mm) gives the shift-invert
/// operator a numerical rank below the Lanczos basis: the basis becomes invariant and goes on with a
/// fresh direction; faer's Krylov–Schur, used before, re-orthogonalized a vector of round-off forever
/// there (found by the fuzz test). Both solvers now end, and alike.
#[test]
fn an_operator_of_low_numerical_rank_ends_the_lanczos_iteration() {
    let model = simply_supported_plate(A, B, 5e-7, 16, 12, ShellShape::Quadrilateral);
    let started = std::time::Instant::now();
    let lanczos = vibration_modes(&model, 6, &EigenSettings { solver: EigenSolver::Lanczos, ..Default::default() });
    assert!(started.elapsed().as_secs_f64() < 5.0, "{:?}", started.elapsed());
    let dense = vibration_modes(&model, 6, &EigenSettings { solver: EigenSolver::Dense, ..Default::default() });
    assert_eq!(lanczos.map(|m| m.frequencies_hz), dense.map(|m| m.frequencies_hz));
    // The consistent mass's operator acts on the mass points' motions: its dimension (more than 64
    // here) exceeds its rank (the massive dofs less the rigid motions, fewer than 64), which decides.
    let mut small = simply_supported_plate(A, B, T, 3, 2, ShellShape::Triangle);
    small.options.mass = Some(MassModel::Consistent);
    small.options.rotary_inertia = true;
    let lanczos = vibration_modes(&small, 3, &EigenSettings { solver: EigenSolver::Lanczos, ..Default::default() }).unwrap();
    let dense = vibration_modes(&small, 3, &EigenSettings { solver: EigenSolver::Dense, ..Default::default() }).unwrap();
    assert_eq!((lanczos.solver, lanczos.frequencies_hz), (EigenSolver::Dense, dense.frequencies_hz));
}

/// The lowest `count` frequencies of the Navier modes (i, j) of a simply supported plate a × b × t,
/// Kirchhoff's and Mindlin's (transverse shear with k = 5/6, no rotary inertia, as the FE model
/// without `rotary_inertia`): `f_M = f_K / √(1 + D κ² / (k G t))` with κ² = π²((i/a)² + (j/b)²), that
/// is `f_K / √(1 + κ² t² / (6 k (1 − ν)))`; both in the order of the Mindlin frequencies.
fn kirchhoff_and_mindlin(a: f64, b: f64, t: f64, count: usize) -> Vec<(f64, f64)> {
    let k = 5.0 / 6.0;
    let mut f: Vec<(f64, f64)> = (1..=8)
        .flat_map(|i| (1..=8).map(move |j| (i, j)))
        .map(|(i, j)| {
            let wave = std::f64::consts::PI.powi(2) * ((i as f64 / a).powi(2) + (j as f64 / b).powi(2));
            let kirchhoff = plate_frequency(i, j, a, b, t);
            (kirchhoff, kirchhoff / (1.0 + wave * t * t / (6.0 * k * (1.0 - NU))).sqrt())
        })
        .collect();
    f.sort_by(|x, y| x.1.total_cmp(&y.1));
    f.truncate(count);
    f
}

/// The Richardson limit (second order) of the lowest `count` frequencies of the plate a × b × t,
/// hard simply supported (w and the tangential rotation held on the edges, Navier's conditions), on
/// meshes n × (4n/5) and 2n × (8n/5).
fn plate_limit(a: f64, b: f64, t: f64, n: usize, shape: ShellShape, count: usize) -> Vec<f64> {
    let frequencies = |na: usize| {
        let nb = 4 * na / 5;
        let mut model = simply_supported_plate(a, b, t, na, nb, shape);
        for s in &mut model.supports {
            let p = model.mesh.nodes[s.node].position;
            let on_x_edge = p.x.abs() < 1e-12 || (p.x - a).abs() < 1e-12;
            let on_y_edge = p.y.abs() < 1e-12 || (p.y - b).abs() < 1e-12;
            if on_x_edge {
                s.dofs = s.dofs.with(flexmb_fem::Dof::Rx);
            }
            if on_y_edge {
                s.dofs = s.dofs.with(flexmb_fem::Dof::Ry);
            }
        }
        vibration_modes(&model, count, &EigenSettings::default()).unwrap().frequencies_hz
    };
    let (coarse, fine) = (frequencies(n), frequencies(2 * n));
    coarse.iter().zip(&fine).map(|(c, f)| (4.0 * f - c) / 3.0).collect()
}

/// Which plate theory each shell follows (issue 19, point 6): the quadrilateral (MITC4) is a
/// Reissner–Mindlin plate, whose transverse shear lowers the frequencies by the factor
/// `1/√(1 + κ² t² / (6 k (1 − ν)))`; the triangle (DKT) is a discrete Kirchhoff plate, without shear
/// deformation. On a plate 1 m × 0.8 m × 50 mm (a/t = 20; Mindlin 0.9–2.7 % below Kirchhoff in the
/// four lowest modes) the quadrilaterals' limit is Mindlin's (within 2.5e-5) and the triangles'
/// Kirchhoff's (within 2.4e-5); asserted within 1e-4. Four meshes up to 40 × 32, about 1 s.
#[test]
fn quadrilaterals_converge_to_mindlin_and_triangles_to_kirchhoff() {
    let (a, b, t) = (1.0, 0.8, 0.05);
    let theory = kirchhoff_and_mindlin(a, b, t, 4);
    let quads = plate_limit(a, b, t, 20, ShellShape::Quadrilateral, 4);
    let triangles = plate_limit(a, b, t, 20, ShellShape::Triangle, 4);
    println!("mode, Kirchhoff [Hz], Mindlin [Hz], quadrilaterals' limit (vs Mindlin, vs Kirchhoff), triangles' limit (vs Kirchhoff, vs Mindlin)");
    for k in 0..4 {
        let (kirchhoff, mindlin) = theory[k];
        println!(
            "  {}  {kirchhoff:10.4}  {mindlin:10.4}  {:10.4} ({:+.1e}, {:+.1e})  {:10.4} ({:+.1e}, {:+.1e})",
            k + 1,
            quads[k],
            quads[k] / mindlin - 1.0,
            quads[k] / kirchhoff - 1.0,
            triangles[k],
            triangles[k] / kirchhoff - 1.0,
            triangles[k] / mindlin - 1.0
        );
        let gap = kirchhoff / mindlin - 1.0;
        assert!(gap > 8e-3, "mode {}: the theories differ by {gap:.1e}", k + 1);
        assert!(rel(quads[k], mindlin) < 1e-4, "mode {}: quadrilaterals {} Hz, Mindlin {mindlin} Hz", k + 1, quads[k]);
        assert!(rel(triangles[k], kirchhoff) < 1e-4, "mode {}: triangles {} Hz, Kirchhoff {kirchhoff} Hz", k + 1, triangles[k]);
    }
}
