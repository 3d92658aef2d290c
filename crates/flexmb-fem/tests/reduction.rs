//! Reduction to a mode set: the basis, the reduced model's frequencies, the modal mass and stiffness,
//! and the inertia invariants, checked against node-by-node sums and the FE matrices.

mod support;

use faer::Mat;
use flexmb_fem::modes::prepare;
use flexmb_fem::reduction::{reduce, Basis, BodyMass, FlexibleBody, ModeKind, ReductionSettings};
use flexmb_fem::assembly::assemble;
use flexmb_fem::mesh::ShellShape;
use flexmb_fem::{FeModel, MassModel};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use support::*;

fn settings(set: &str, basis: Basis) -> ReductionSettings {
    ReductionSettings { mode_set: set.parse().unwrap(), basis, eigen: Default::default() }
}

/// A cantilever with a tip force and a tip bending torque as deleted constraints, with the lumped
/// mass: the invariants are then the node sums the tests below form.
fn arm() -> FeModel {
    let mut model = cantilever(1.0, 12, square_section(0.01));
    model.options.mass = Some(MassModel::Lumped);
    let tip = model.mesh.nodes.len() - 1;
    model.static_loads = vec![force("tip_fz", tip, [0.0, 0.0, 1.0]), torque("tip_tz", tip, [0.0, 0.0, 1.0])];
    model
}

/// Deterministic pseudo-random numbers in (-1, 1).
fn pseudo_random(n: usize, seed: f64) -> Vec<f64> {
    (0..n).map(|i| 2.0 * ((i as f64 + seed) * 0.754_877_666_246_693).fract() - 1.0).collect()
}

/// `Φ` over all nodal dofs (6 n × m) from the body file.
fn nodal_basis(body: &FlexibleBody) -> DMatrix<f64> {
    let n = body.nodes.len();
    DMatrix::from_fn(6 * n, body.mode_count(), |g, j| {
        let (node, d) = (g / 6, g % 6);
        if d < 3 { body.shapes[j].translation[node][d] } else { body.shapes[j].rotation[node][d - 3] }
    })
}

/// The FE stiffness over all nodal dofs (zero rows and columns at supports).
fn nodal_stiffness(model: &FeModel) -> DMatrix<f64> {
    let prepared = prepare(model).unwrap();
    let k: Mat<f64> = prepared.assembled.stiffness.to_dense();
    let dofs = &prepared.assembled.dofs;
    let n = 6 * dofs.n_nodes();
    DMatrix::from_fn(n, n, |a, b| match (dofs.equation_of(a), dofs.equation_of(b)) {
        (Some(i), Some(j)) => k[(i, j)],
        _ => 0.0,
    })
}

#[test]
fn orthonormal_basis_has_identity_mass_and_diagonal_stiffness() {
    let reduction = reduce(&arm(), "arm", &settings("4N2S", Basis::Orthonormal)).unwrap();
    let body = &reduction.body;
    assert_eq!(body.mode_count(), 6);
    assert!(body.modes.iter().all(|m| m.kind == ModeKind::Orthonormal));
    let m = body.mode_count();
    for i in 0..m {
        for j in 0..m {
            let identity = if i == j { 1.0 } else { 0.0 };
            assert!((body.modal_mass[(i, j)] - identity).abs() < 1e-10);
            assert!((body.invariants.c9[(i, j)] - identity).abs() < 1e-10, "no rotary inertia: C9 is the modal mass");
            let expected = if i == j { (2.0 * std::f64::consts::PI * body.reduced_frequencies_hz[i]).powi(2) } else { 0.0 };
            assert!((body.modal_stiffness[(i, j)] - expected).abs() < 1e-8 * body.modal_stiffness[(m - 1, m - 1)]);
        }
    }
    // The span holds the four lowest vibration modes, so the reduced model has their frequencies
    // (the vibration modes come in pairs of equal frequency: square section); its other two
    // frequencies lie above the FE ones (Rayleigh–Ritz).
    for k in 0..4 {
        assert!(rel(body.reduced_frequencies_hz[k], body.fe_frequencies_hz[k]) < 1e-9);
    }
    for k in 4..6 {
        assert!(body.reduced_frequencies_hz[k] >= body.fe_frequencies_hz[k] * (1.0 - 1e-12));
    }
}

#[test]
fn raw_basis_keeps_the_seeds_modes_and_the_same_reduced_frequencies() {
    let raw = reduce(&arm(), "arm", &settings("4N2S", Basis::Raw)).unwrap().body;
    let orthonormal = reduce(&arm(), "arm", &settings("4N2S", Basis::Orthonormal)).unwrap().body;
    let labels: Vec<&str> = raw.modes.iter().map(|m| m.label.as_str()).collect();
    assert_eq!(labels, ["N1", "N2", "N3", "N4", "S1", "S2"]);
    assert_eq!(raw.modes[4].load.as_deref(), Some("tip_fz"));
    for (a, b) in raw.reduced_frequencies_hz.iter().zip(&orthonormal.reduced_frequencies_hz) {
        assert!(rel(*a, *b) < 1e-9);
    }
    // The static mode is the unit-load response: tip deflection L³/3EI.
    let tip = raw.nodes.len() - 1;
    let ei = E * square_section(0.01).iy;
    assert!(rel(raw.shapes[4].translation[tip][2], 1.0 / (3.0 * ei)) < 1e-10);
}

#[test]
fn modal_mass_and_stiffness_equal_the_projected_fe_matrices() {
    let model = arm();
    let body = reduce(&model, "arm", &settings("3N2S", Basis::Raw)).unwrap().body;
    let phi = nodal_basis(&body);
    let k = nodal_stiffness(&model);
    let k_aa = phi.transpose() * &k * &phi;
    assert!((&k_aa - &body.modal_stiffness).amax() < 1e-9 * k_aa.amax());
    // Φᵀ M Φ with the lumped masses, node by node.
    let mut c9 = DMatrix::zeros(5, 5);
    for (i, node) in body.nodes.iter().enumerate() {
        let psi = body.psi(i).expect("a node of the body");
        c9 += node.mass * psi.transpose() * psi;
    }
    assert!((&c9 - &body.invariants.c9).amax() < 1e-12 * c9.amax());
    assert!((&c9 - &body.modal_mass).amax() < 1e-12 * c9.amax());
}

#[test]
fn mass_first_moment_and_inertia_equal_the_rigid_properties_of_the_mesh() {
    let body = reduce(&arm(), "arm", &settings("2N", Basis::Orthonormal)).unwrap().body;
    let inv = &body.invariants;
    let section = square_section(0.01);
    let mass = RHO * section.area * 1.0;
    assert!(rel(inv.mass, mass) < 1e-12);
    assert!(rel(body.mass_properties.mass, mass) < 1e-12);
    // Centre of mass at mid-length.
    assert!((inv.c1 - mass * Vector3::new(0.5, 0.0, 0.0)).norm() < 1e-12 * mass);
    assert!((body.mass_properties.center_of_mass - Vector3::new(0.5, 0.0, 0.0)).norm() < 1e-12);
    // −C3 is the inertia about the frame origin; shifted to the centre of mass it is the mass
    // properties' inertia (parallel axes).
    let c = body.mass_properties.center_of_mass;
    let about_origin = body.mass_properties.inertia + inv.mass * (Matrix3::identity() * c.norm_squared() - c * c.transpose());
    assert!((-inv.c3 - about_origin).amax() < 1e-12 * about_origin.amax());
    // Lumped nodes: Σ mᵢ xᵢ² is the trapezoidal rule for m L²/3, exact up to m h²/6 / ... :
    // with n elements the lumped value is m L² (1/3 + 1/(6 n²)).
    let n = 12.0;
    assert!(rel(-inv.c3[(1, 1)], mass * (1.0 / 3.0 + 1.0 / (6.0 * n * n))) < 1e-12);
}

#[test]
fn invariant_expansions_equal_node_sums_for_a_deformed_state() {
    let body = reduce(&arm(), "arm", &settings("3N2S", Basis::Raw)).unwrap().body;
    let inv = &body.invariants;
    let m = body.mode_count();
    let a = DVector::from_vec(pseudo_random(m, 0.3)) * 1e-2;
    // Node sums at the deformed positions r̄ᵢ = s̄ᵢ + Ψᵢ a.
    let mut first_moment = Vector3::zeros();
    let mut inertia = Matrix3::zeros();
    let mut coupling = DMatrix::zeros(3, m);
    for (i, node) in body.nodes.iter().enumerate() {
        let psi = body.psi(i).expect("a node of the body");
        let d = &psi * &a;
        let r = node.position + Vector3::new(d[0], d[1], d[2]);
        let r_tilde = r.cross_matrix();
        first_moment += node.mass * r;
        inertia -= node.mass * r_tilde * r_tilde;
        coupling += node.mass * DMatrix::from_fn(3, 3, |p, q| r_tilde[(p, q)]) * psi;
    }
    // S(a) = C1 + C2 a
    let c2a = &inv.c2 * &a;
    let s = inv.c1 + Vector3::new(c2a[0], c2a[1], c2a[2]);
    assert!((s - first_moment).norm() < 1e-12 * first_moment.norm());
    // J̄(a) = −(C3 + Σⱼ (C4(j) + C4(j)ᵀ) aⱼ + Σⱼₖ C5(j,k) aⱼ aₖ)
    let mut j_bar = inv.c3;
    for j in 0..m {
        j_bar += (inv.c4[j] + inv.c4[j].transpose()) * a[j];
        for k in 0..m {
            j_bar += inv.c5[j][k] * a[j] * a[k];
        }
    }
    assert!((-j_bar - inertia).amax() < 1e-12 * inertia.amax());
    // Σ mᵢ r̄̃ᵢ Ψᵢ = C6 + Σₖ C7(k) aₖ
    let mut expansion = inv.c6.clone();
    for k in 0..m {
        expansion += &inv.c7[k] * a[k];
    }
    assert!((&expansion - &coupling).amax() < 1e-12 * coupling.amax());
    // C8(j) = Σ mᵢ s̄ᵢᵀ ψᵢʲ
    for j in 0..m {
        let c8: f64 = body.nodes.iter().enumerate().map(|(i, n)| n.mass * n.position.dot(&body.psi(i).expect("a node of the body").column(j).into_owned().fixed_rows::<3>(0).into_owned())).sum();
        assert!((c8 - inv.c8[j]).abs() < 1e-12 * inv.c8.amax());
    }
}

/// The FE mass over all nodal dofs (supports removed), as assembled for the model's mass.
fn unsupported_mass(model: &FeModel) -> DMatrix<f64> {
    let free = FeModel { supports: Vec::new(), ..model.clone() };
    let m: Mat<f64> = assemble(&free).unwrap().mass.to_dense();
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

/// The rigid translations (3 columns) and rotations about the frame origin (3 columns; nodal
/// translations `e × x`, nodal rotations `e`) over all nodal dofs.
fn rigid_motions(body: &FlexibleBody) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = body.nodes.len();
    let mut translations = DMatrix::zeros(6 * n, 3);
    let mut rotations = DMatrix::zeros(6 * n, 3);
    for (i, node) in body.nodes.iter().enumerate() {
        for k in 0..3 {
            let e = Vector3::ith(k, 1.0);
            translations[(6 * i + k, k)] = 1.0;
            let u = e.cross(&node.position);
            for d in 0..3 {
                rotations[(6 * i + d, k)] = u[d];
            }
            rotations[(6 * i + 3 + k, k)] = 1.0;
        }
    }
    (translations, rotations)
}

/// The 0.6 m × 0.4 m plate of the tests below with a 10 mm square beam of 4 elements on its edge x = 0.6.
fn with_edge_beam(mut plate: FeModel) -> FeModel {
    plate.mesh.beam_sections.push(flexmb_fem::BeamSection { orientation: Vector3::new(1.0, 0.0, 0.0), ..square_section(0.01) });
    plate.mesh.add_beam_line(Vector3::new(0.6, 0.0, 0.0), Vector3::new(0.6, 0.4, 0.0), 4, 0).unwrap();
    plate
}

/// Every invariant that is linear or quadratic in the motion is a product with the FE mass matrix
/// `M` itself, whatever the mass points are: with the rigid translations `R_t` and rotations `R_r`,
/// `m I = R_tᵀ M R_t`, `−C̃1 = R_tᵀ M R_r`, `−C3 + ΣJ = R_rᵀ M R_r`, `C2 = R_tᵀ M Φ`,
/// `C6 + Σ J Θ = R_rᵀ M Φ`, `C9 + Σ Θᵀ J Θ = Φᵀ M Φ`. Checked for the lumped and the consistent
/// mass, with and without rotary inertia, on beams (a cantilever) and shells (a plate), and for the
/// default mass of a plate with an edge beam (consistent beam, lumped shells: mixed).
#[test]
fn invariants_are_products_with_the_fe_mass_matrix_for_both_masses() {
    let (mut plate, grid) = plate(0.6, 0.4, 0.004, 6, 4, ShellShape::Quadrilateral);
    for &node in &grid[0] {
        plate.supports.push(flexmb_fem::Support { node, dofs: flexmb_fem::DofSet::ALL });
    }
    plate.static_loads = vec![force("corner_fz", plate.mesh.nodes.len() - 1, [0.0, 0.0, 1.0])];
    let framed = with_edge_beam(plate.clone());
    assert_eq!(framed.mesh.nodes.len(), plate.mesh.nodes.len(), "the beam is on the plate's edge nodes");
    let both = vec![Some(MassModel::Lumped), Some(MassModel::Consistent)];
    for (name, base, masses) in [("cantilever", arm(), both.clone()), ("plate", plate, both), ("framed plate", framed, vec![None])] {
        for mass in masses {
            for rotary_inertia in [false, true] {
                let mut model = base.clone();
                model.options.mass = mass;
                model.options.rotary_inertia = rotary_inertia;
                let case = format!("{name}, {}, rotary inertia {rotary_inertia}", mass.map_or("default", MassModel::name));
                let body = reduce(&model, name, &settings("3N1S", Basis::Raw)).unwrap_or_else(|e| panic!("{case}: {e}")).body;
                assert_eq!(body.mass, mass.map_or(BodyMass::Mixed, BodyMass::from), "{case}");
                let inv = &body.invariants;
                let m = unsupported_mass(&model);
                let phi = nodal_basis(&body);
                let (rt, rr) = rigid_motions(&body);
                let close = |a: &DMatrix<f64>, b: &DMatrix<f64>, what: &str| {
                    let error = (a - b).amax() / b.amax().max(f64::MIN_POSITIVE);
                    assert!(error < 1e-11, "{case}: {what}, relative error {error:.2e}");
                };
                let to_dynamic = |a: &Matrix3<f64>| DMatrix::from_fn(3, 3, |i, j| a[(i, j)]);
                close(&(rt.transpose() * &m * &rt), &(DMatrix::identity(3, 3) * inv.mass), "m I");
                close(&(rt.transpose() * &m * &rr), &to_dynamic(&-inv.c1.cross_matrix()), "C1");
                close(&(rr.transpose() * &m * &rr), &to_dynamic(&(-inv.c3 + inv.rotary_inertia)), "C3");
                close(&(rt.transpose() * &m * &phi), &inv.c2, "C2");
                close(&(rr.transpose() * &m * &phi), &(&inv.c6 + &inv.rotary_coupling), "C6");
                close(&(phi.transpose() * &m * &phi), &(&inv.c9 + &inv.rotary_modal_mass), "C9");
                close(&(phi.transpose() * &m * &phi), &body.modal_mass, "modal mass");
            }
        }
    }
}

/// The default mass of a plate with a beam on its edge (4 elements along y, length 0.4 m) mixes the
/// beam's consistent mass with the plate's lumped one: against every element lumped, the second
/// moment `Σ m y²` loses exactly the lumped beam's trapezoid excess `m_b L² / (6 n²)`, and nothing else
/// changes in the mass properties' total.
#[test]
fn the_default_mass_of_a_plate_with_an_edge_beam_is_consistent_in_the_beam_only() {
    let (mut plate, grid) = plate(0.6, 0.4, 0.004, 6, 4, ShellShape::Quadrilateral);
    for &node in &grid[0] {
        plate.supports.push(flexmb_fem::Support { node, dofs: flexmb_fem::DofSet::ALL });
    }
    let mut framed = with_edge_beam(plate);
    let mixed = reduce(&framed, "framed", &settings("2N", Basis::Raw)).unwrap().body;
    framed.options.mass = Some(MassModel::Lumped);
    let lumped = reduce(&framed, "framed", &settings("2N", Basis::Raw)).unwrap().body;
    assert_eq!((mixed.mass, lumped.mass), (BodyMass::Mixed, BodyMass::Lumped));
    let (length, n) = (0.4, 4.0);
    let beam_mass = RHO * square_section(0.01).area * length;
    let excess = beam_mass * length * length / (6.0 * n * n);
    // −C3 is the inertia about the frame origin: its xx entry is Σ m (y² + z²), z = 0 on the plate.
    let drop = -lumped.invariants.c3[(0, 0)] + mixed.invariants.c3[(0, 0)];
    assert!(rel(drop, excess) < 1e-9, "drop {drop:.6e}, m_b L² / (6 n²) = {excess:.6e}");
    assert!(rel(mixed.mass_properties.mass, lumped.mass_properties.mass) < 1e-14);
}

/// With the consistent mass the invariants integrate the beam's field exactly: the cantilever's
/// inertia about its root is `m L² / 3` with no trapezoid term, and the first moment of its first
/// mode `∫ ρ A φ₁ dx` matches the closed form of the Euler–Bernoulli mode to the accuracy of the mode.
#[test]
fn consistent_invariants_are_the_beams_integrals() {
    let mut model = arm();
    model.options.mass = Some(MassModel::Consistent);
    let body = reduce(&model, "arm", &settings("2N", Basis::Raw)).unwrap().body;
    let mass = RHO * square_section(0.01).area;
    assert!(rel(-body.invariants.c3[(1, 1)], mass / 3.0) < 1e-12);
    assert!(rel(-body.invariants.c3[(2, 2)], mass / 3.0) < 1e-12);
    assert!(body.invariants.c3[(0, 0)].abs() < 1e-12 * mass, "the mass is on the axis");
    // The first bending mode φ(x) = A (cosh βx − cos βx − σ (sinh βx − sin βx)), mass-normalized
    // (∫ ρA φ² = 1 gives A² ρA L = 1), has ∫ ρA φ dx = 2 σ √(ρA L) / (βL) (its tip is ±2 A).
    let beta_l: f64 = 1.8751040687;
    let sigma = (beta_l.sinh() - beta_l.sin()) / (beta_l.cosh() + beta_l.cos());
    let expected = 2.0 * sigma * mass.sqrt() / beta_l;
    let c2 = &body.invariants.c2;
    let first_moment = (c2[(1, 0)].powi(2) + c2[(2, 0)].powi(2)).sqrt();
    assert!(rel(first_moment, expected) < 1e-6, "∫ρAφ₁ = {first_moment}, closed form {expected}");
}

#[test]
fn rotary_inertia_enters_the_modal_mass() {
    let mut model = arm();
    model.options.rotary_inertia = true;
    let body = reduce(&model, "arm", &settings("3N", Basis::Orthonormal)).unwrap().body;
    let total = &body.invariants.c9 + &body.invariants.rotary_modal_mass;
    assert!((total - DMatrix::identity(3, 3)).amax() < 1e-10, "Φᵀ M Φ = C9 + Σ Θᵀ J Θ = I");
    assert!(body.invariants.rotary_modal_mass.amax() > 0.0);
}

#[test]
fn flexible_body_file_round_trips() {
    let body = reduce(&arm(), "arm", &settings("2N2S", Basis::Raw)).unwrap().body;
    let text = body.to_json();
    let back = FlexibleBody::from_json(&text, "arm.json").unwrap();
    assert_eq!(back, body);
    let broken = text.replacen("\"format\":\"flexmb-flexible-body\"", "\"format\":\"other\"", 1);
    let error = FlexibleBody::from_json(&broken, "arm.json").unwrap_err().to_string();
    assert!(error.starts_with("arm.json: not a flexible-body file"), "{error}");
}

#[test]
fn asking_for_more_static_modes_than_loads_is_an_error() {
    let error = reduce(&arm(), "arm", &settings("3S", Basis::Raw)).unwrap_err().to_string();
    assert!(error.contains("3 static correction modes") && error.contains("2 static loads"), "{error}");
}

#[test]
fn a_static_mode_in_the_span_of_the_others_makes_the_basis_singular() {
    let mut model = arm();
    let tip = model.mesh.nodes.len() - 1;
    model.static_loads.push(force("tip_fz_again", tip, [0.0, 0.0, 2.0]));
    let error = reduce(&model, "arm", &settings("3S", Basis::Raw)).unwrap_err().to_string();
    assert!(error.contains("linearly dependent"), "{error}");
}

#[test]
fn a_static_mode_that_moves_no_mass_is_dropped_with_a_warning() {
    let mut model = arm();
    let tip = model.mesh.nodes.len() - 1;
    // A torque about the beam's axis only twists it: without rotary inertia, nothing with mass moves.
    model.static_loads[1] = torque("tip_tx", tip, [1.0, 0.0, 0.0]);
    let reduction = reduce(&model, "arm", &settings("2S", Basis::Raw)).unwrap();
    let labels: Vec<&str> = reduction.body.modes.iter().map(|m| m.label.as_str()).collect();
    assert_eq!(labels, ["S1"]);
    assert!(reduction.warnings.iter().any(|w| w.starts_with("mode S2 (tip_tx) moves no mass") && w.contains("dropped")), "{:?}", reduction.warnings);
    model.options.rotary_inertia = true;
    assert_eq!(reduce(&model, "arm", &settings("2S", Basis::Raw)).unwrap().body.mode_count(), 2);
}

/// A door like the seed's: a plate in the y–z plane framed by beams, supported as in the seed (bottom
/// hinge fixed in x, y, z; top hinge in x, y), five static correction modes for the five deleted
/// constraints. The door can still turn about its hinge line; the mode sets reduce all the same.
#[test]
fn door_with_the_seeds_supports_reduces_to_the_seeds_mode_sets() {
    use flexmb_fem::mesh::ShellShape;
    use flexmb_fem::{BeamSection, Dof, DofSet, Mesh, ShellSection, Support};
    let (w, h) = (0.8, 2.0);
    let mut mesh = Mesh {
        materials: vec![steel()],
        beam_sections: vec![BeamSection { orientation: Vector3::new(1.0, 0.0, 0.0), ..square_section(0.03) }],
        shell_sections: vec![ShellSection { name: "panel".into(), material: 0, thickness: 0.003 }],
        ..Default::default()
    };
    mesh.add_rectangular_plate(Vector3::zeros(), Vector3::new(0.0, w, 0.0), Vector3::new(0.0, 0.0, h), 3, 4, 0, ShellShape::Quadrilateral).unwrap();
    let corners = [Vector3::zeros(), Vector3::new(0.0, w, 0.0), Vector3::new(0.0, w, h), Vector3::new(0.0, 0.0, h)];
    for k in 0..4 {
        mesh.add_beam_line(corners[k], corners[(k + 1) % 4], if k % 2 == 0 { 6 } else { 8 }, 0).unwrap();
    }
    let bottom = mesh.nearest_node(&corners[0]).unwrap().0;
    let top = mesh.nearest_node(&corners[3]).unwrap().0;
    let model = FeModel {
        mesh,
        supports: vec![
            Support { node: bottom, dofs: DofSet::TRANSLATIONS },
            Support { node: top, dofs: DofSet::EMPTY.with(Dof::Ux).with(Dof::Uy) },
        ],
        static_loads: vec![
            torque("bottom_rx", bottom, [1.0, 0.0, 0.0]),
            torque("bottom_ry", bottom, [0.0, 1.0, 0.0]),
            torque("top_rx", top, [1.0, 0.0, 0.0]),
            torque("top_ry", top, [0.0, 1.0, 0.0]),
            force("top_fz", top, [0.0, 0.0, 1.0]),
        ],
        ..Default::default()
    };
    for set in ["5S", "5N", "9N", "4N5S"] {
        let reduction = reduce(&model, "door", &settings(set, Basis::Orthonormal)).unwrap();
        let body = &reduction.body;
        assert_eq!(body.rigid_modes, 1, "{set}: the turn about the hinge line");
        assert!(reduction.warnings.iter().any(|w| w.contains("1 rigid motion")), "{set}: {:?}", reduction.warnings);
        assert!(!reduction.warnings.iter().any(|w| w.contains("inertia relief")), "{set}: {:?}", reduction.warnings);
        // Rayleigh–Ritz: every reduced frequency lies at or above the FE frequency of the same rank,
        // and sets that hold the vibration modes reproduce them.
        for (k, (r, f)) in body.reduced_frequencies_hz.iter().zip(&body.fe_frequencies_hz).enumerate() {
            assert!(*r >= f * (1.0 - 1e-9), "{set} mode {}: reduced {r} below FE {f}", k + 1);
        }
        let vibration = set.parse::<flexmb_fem::reduction::ModeSet>().unwrap().vibration();
        for k in 0..vibration {
            assert!(rel(body.reduced_frequencies_hz[k], body.fe_frequencies_hz[k]) < 1e-8, "{set} mode {}", k + 1);
        }
    }
}

/// The geometric stiffness of the unit inertia loads (formulation.md §11) on a cantilever along x
/// (40 elements, consistent mass): spun about z (`centrifugal[zz]`), the first bending pair's
/// `φᵀ G φ` (mass-normalized `φ`) is Southwell's coefficient 1.193 (Hodges and Rutkowski's table: 1.192 between
/// ν = 0 and 1); spun about its own axis x, the beam carries no axial force (`centrifugal[xx]` = 0);
/// accelerated along x, the clamp pushes it: `acceleration[x]` softens. A file without the terms
/// (written before them) still reads, without them; a plate (shells) has them too.
#[test]
fn geometric_stiffness_of_the_inertia_loads_gives_southwells_coefficient() {
    let section = square_section(0.01);
    let mut model = cantilever(1.0, 40, section.clone());
    model.options.mass = Some(MassModel::Consistent);
    model.options.rotary_inertia = true;
    let body = reduce(&model, "arm", &settings("2N", Basis::Orthonormal)).unwrap().body;
    let terms = body.geometric_stiffness.as_ref().expect("a beam body has the terms");
    assert_eq!((terms.acceleration.len(), terms.angular_acceleration.len(), terms.centrifugal.len()), (3, 3, 6));
    // Mass-normalized modes: ω² = ω₀² + (φᵀ G_zz φ) Ω², so the entry is the coefficient itself.
    let southwell = 0.5 * (terms.centrifugal[2][(0, 0)] + terms.centrifugal[2][(1, 1)]);
    assert!((southwell / 1.1935 - 1.0).abs() < 2e-3, "Southwell coefficient {southwell}");
    assert!(terms.centrifugal[0].amax() < 1e-9 * terms.centrifugal[2].amax());
    assert!(terms.acceleration[0][(0, 0)] < 0.0 && terms.acceleration[0][(1, 1)] < 0.0);

    let mut json: serde_json::Value = serde_json::from_str(&body.to_json()).unwrap();
    json.as_object_mut().unwrap().remove("geometric_stiffness");
    let older = FlexibleBody::from_json(&json.to_string(), "older.json").unwrap();
    assert!(older.geometric_stiffness.is_none());
    let mut wrong: serde_json::Value = serde_json::from_str(&body.to_json()).unwrap();
    wrong["geometric_stiffness"]["centrifugal"].as_array_mut().unwrap().pop();
    let error = FlexibleBody::from_json(&wrong.to_string(), "wrong.json").unwrap_err().to_string();
    assert!(error.contains("geometric_stiffness.centrifugal has 5 matrices, expected 6"), "{error}");

    let (mut plate_model, _) = plate(1.0, 0.5, 0.01, 4, 2, ShellShape::Quadrilateral);
    plate_model.supports.push(flexmb_fem::Support { node: 0, dofs: flexmb_fem::DofSet::ALL });
    let plate_body = reduce(&plate_model, "plate", &settings("2N", Basis::Orthonormal)).unwrap().body;
    assert!(plate_body.geometric_stiffness.is_some());
}
