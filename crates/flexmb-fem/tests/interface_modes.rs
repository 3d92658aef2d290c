//! Craig–Bampton and free-interface mode sets against the full FE model: a steel link 0.5 m × 10 mm ×
//! 40 mm of 20 C3D20 bricks (consistent mass) with an interface node at each end — coupled rigidly
//! (`*KINEMATIC COUPLING`) or distributed (`*DISTRIBUTING COUPLING`) to the end faces, each held in
//! its six dofs (the interface, 12 dofs). Each reduced body is judged by Rayleigh–Ritz on the full
//! model's K and M over its modes and the six rigid motions, free-free and with the interface held,
//! against the FE model's own eigen-solution:
//!
//! - `8N12C` (Craig–Bampton): exact (1e-8) with the interface held, by construction;
//! - `8F12A` (free interface): exact free-free, by construction;
//! - `8N6S` (the seed's set: the left end held, unit loads at the right end's six dofs).
//!
//! The errors are printed (`--nocapture`) as the table of docs/preprocessor.md; each is bounded.
//! (About 8 s in release: six reductions and their FE references.)
//! The orthonormalized interface bodies have unit modal mass, diagonal modal stiffness, and modes
//! M-orthogonal to the rigid motions (the mean-axis frame).

#[path = "support/solid_block.rs"]
mod solid_block;

use faer::Mat;
use flexmb_fem::assembly::{assemble, AssembledModel};
use flexmb_fem::inp::parse_inp;
use flexmb_fem::modes::rigid::free_rigid_motions;
use flexmb_fem::modes::{vibration_modes, EigenSettings};
use flexmb_fem::reduction::{reduce, Basis, FlexibleBody, ReductionSettings};
use flexmb_fem::{FeModel, MassModel, StaticLoad, StaticLoadKind, Support};
use nalgebra::{DMatrix, Vector3};
use solid_block::SolidBlock;

/// Elastic frequencies compared.
const COMPARED: usize = 6;

fn link() -> SolidBlock {
    SolidBlock { lx: 0.5, ly: 0.01, lz: 0.04, nx: 10, ny: 1, nz: 2, clamped: false, ..SolidBlock::cantilever("C3D20", 10) }
}

/// The link with an interface node at each end (1000 at x = 0, 1001 at x = 0.5), coupled by `kind`
/// ("kinematic" or "distributing") and held in their six dofs.
fn two_ended_link(kind: &str) -> FeModel {
    let ends = [(1000, 0.0, "ROOT"), (1001, 0.5, "TIP")];
    let mut extra = String::new();
    for (node, x, face) in ends {
        extra += &format!("*NODE\n{node}, {x}, 0.005, 0.02\n");
        extra += &match kind {
            "kinematic" => format!("*KINEMATIC COUPLING, REF NODE={node}\n{face}, 1, 3\n"),
            _ => format!("*ELEMENT, TYPE=DCOUP3D, ELSET=E{node}\n{node}, {node}\n*DISTRIBUTING COUPLING, ELSET=E{node}\n{face}, 1.\n"),
        };
        extra += &format!("*BOUNDARY\n{node}, 1, 6\n");
    }
    let mut model = parse_inp(&link().deck_with(&extra), "link.inp").unwrap().model;
    model.options.mass = Some(MassModel::Consistent);
    model
}

/// The seed's setting of the same link: the left interface node held, unit loads at the right one.
fn seed_setting(mut model: FeModel) -> FeModel {
    let right = model.mesh.node_index(1001).unwrap();
    model.supports.retain(|s| s.node != right);
    for k in 0..3 {
        let axis = Vector3::ith(k, 1.0);
        model.static_loads.push(StaticLoad { name: format!("f{k}"), node: right, kind: StaticLoadKind::Force(axis) });
        model.static_loads.push(StaticLoad { name: format!("t{k}"), node: right, kind: StaticLoadKind::Torque(axis) });
    }
    model
}

fn unsupported(model: &FeModel) -> FeModel {
    FeModel { supports: Vec::new(), ..model.clone() }
}

/// The body's modes over the free dofs of `assembled` (a model without supports).
fn modes_over(body: &FlexibleBody, assembled: &AssembledModel, nodes: usize) -> Mat<f64> {
    let dofs = &assembled.dofs;
    let mut basis = Mat::zeros(dofs.n_free(), body.shapes.len());
    for (j, shape) in body.shapes.iter().enumerate() {
        for g in 0..6 * nodes {
            if let Some(e) = dofs.equation_of(g) {
                let (node, d) = (g / 6, g % 6);
                basis[(e, j)] = if d < 3 { shape.translation[node][d] } else { shape.rotation[node][d - 3] };
            }
        }
    }
    basis
}

fn to_nalgebra(m: &Mat<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

/// Rayleigh–Ritz frequencies (Hz, ascending, the zero ones included) of `assembled` over `basis`.
fn ritz_frequencies(assembled: &AssembledModel, basis: &Mat<f64>) -> Vec<f64> {
    let k = to_nalgebra(&(basis.transpose() * (&assembled.stiffness * basis)));
    let m = to_nalgebra(&(basis.transpose() * (&assembled.mass * basis)));
    let l_inverse = m.cholesky().expect("the Ritz basis is independent").l().try_inverse().unwrap();
    let a = &l_inverse * k * l_inverse.transpose();
    let mut values: Vec<f64> = a.symmetric_eigen().eigenvalues.iter().copied().collect();
    values.sort_by(f64::total_cmp);
    values.iter().map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)).collect()
}

/// The combinations of the columns of `basis` that vanish at the equations `held` (an orthonormal
/// basis of the null space of those rows).
fn held_subspace(basis: &Mat<f64>, held: &[usize]) -> Mat<f64> {
    let rows = DMatrix::from_fn(held.len(), basis.ncols(), |i, j| basis[(held[i], j)]);
    let gram = rows.transpose() * &rows;
    let eigen = gram.symmetric_eigen();
    let largest = eigen.eigenvalues.max();
    let null: Vec<usize> = (0..basis.ncols()).filter(|&k| eigen.eigenvalues[k] <= 1e-12 * largest).collect();
    let z = Mat::from_fn(basis.ncols(), null.len(), |i, c| eigen.eigenvectors[(i, null[c])]);
    basis * &z
}

/// Relative errors of the reduced body's first `COMPARED` elastic frequencies, free-free and with the
/// interface held, against the FE model's.
struct Errors {
    free: Vec<f64>,
    held: Vec<f64>,
}

fn errors(model: &FeModel, set: &str) -> Errors {
    let free_model = unsupported(model);
    let two_ended = two_ended_reference(model);
    let assembled = assemble(&free_model).unwrap();
    let rigid = free_rigid_motions(&free_model.mesh, &assembled.dofs);
    assert_eq!(rigid.ncols(), 6);
    let settings = ReductionSettings { mode_set: set.parse().unwrap(), basis: Basis::Orthonormal, eigen: EigenSettings::default() };
    let body = reduce(model, set, &settings).unwrap().body;
    let modes = modes_over(&body, &assembled, model.mesh.nodes.len());
    let mut full = Mat::zeros(modes.nrows(), 6 + modes.ncols());
    full.as_mut().subcols_mut(0, 6).copy_from(&rigid);
    full.as_mut().subcols_mut(6, modes.ncols()).copy_from(&modes);
    let free_fe = vibration_modes(&free_model, COMPARED, &EigenSettings::default()).unwrap().frequencies_hz;
    let held_fe = vibration_modes(&two_ended, COMPARED, &EigenSettings::default()).unwrap().frequencies_hz;
    let free_ritz = ritz_frequencies(&assembled, &full);
    let interface: Vec<usize> = flexmb_fem::reduction::interface_dofs(&two_ended)
        .into_iter()
        .filter_map(|(node, dof)| assembled.dofs.equation(node, dof))
        .collect();
    let held_ritz = ritz_frequencies(&assembled, &held_subspace(&full, &interface));
    println!("FE free-free {free_fe:.1?} Hz, interface held {held_fe:.1?} Hz");
    let relative = |ritz: &[f64], fe: &[f64]| fe.iter().zip(ritz).map(|(f, r)| (r - f) / f).collect::<Vec<f64>>();
    Errors { free: relative(&free_ritz[6..], &free_fe), held: relative(&held_ritz, &held_fe) }
}

/// The two-ended model (both interface nodes held), whatever `model` holds.
fn two_ended_reference(model: &FeModel) -> FeModel {
    let mut reference = unsupported(model);
    reference.static_loads.clear();
    for label in [1000, 1001] {
        reference.supports.push(Support { node: model.mesh.node_index(label).unwrap(), dofs: flexmb_fem::DofSet::ALL });
    }
    reference
}

fn largest(errors: &[f64]) -> f64 {
    errors.iter().fold(0.0_f64, |a, e| a.max(e.abs()))
}

fn print(kind: &str, set: &str, e: &Errors) {
    let format = |v: &[f64]| v.iter().map(|x| format!("{x:+.1e}")).collect::<Vec<_>>().join(" ");
    println!("{kind:12} {set:6} free-free: {}   held: {}", format(&e.free), format(&e.held));
}

#[test]
fn interface_sets_against_the_full_model() {
    for kind in ["kinematic", "distributing"] {
        let model = two_ended_link(kind);
        let craig_bampton = errors(&model, "8N12C");
        print(kind, "8N12C", &craig_bampton);
        assert!(largest(&craig_bampton.held) < 1e-8, "{kind}: {:?}", craig_bampton.held);
        assert!(largest(&craig_bampton.free) < 1e-2, "{kind}: {:?}", craig_bampton.free);
        let free_interface = errors(&model, "8F12A");
        print(kind, "8F12A", &free_interface);
        assert!(largest(&free_interface.free) < 1e-8, "{kind}: {:?}", free_interface.free);
        assert!(largest(&free_interface.held) < 5e-4, "{kind}: {:?}", free_interface.held);
        let seed = errors(&seed_setting(model), "8N6S");
        print(kind, "8N6S", &seed);
        assert!(largest(&seed.free) < 0.15 && largest(&seed.held) < 0.05, "{kind}: {:?} {:?}", seed.free, seed.held);
        // Every reduced frequency is an upper bound (Rayleigh–Ritz).
        for e in craig_bampton.free.iter().chain(&free_interface.held).chain(&seed.free).chain(&seed.held) {
            assert!(*e > -1e-9, "{kind}: {e}");
        }
    }
}

#[test]
fn interface_bodies_are_orthonormal_and_free_of_rigid_motion() {
    let model = two_ended_link("distributing");
    let free_model = unsupported(&model);
    let assembled = assemble(&free_model).unwrap();
    let rigid = free_rigid_motions(&free_model.mesh, &assembled.dofs);
    for set in ["8N12C", "8F12A"] {
        let settings = ReductionSettings { mode_set: set.parse().unwrap(), basis: Basis::Orthonormal, eigen: EigenSettings::default() };
        let reduction = reduce(&model, set, &settings).unwrap();
        let body = &reduction.body;
        // 12 constraint modes of two clamped interface nodes span their six rigid motions.
        let expected = if set == "8N12C" { 14 } else { 20 };
        assert_eq!(body.mode_count(), expected, "{set}");
        let modes = modes_over(body, &assembled, model.mesh.nodes.len());
        let rigid_coupling = rigid.transpose() * (&assembled.mass * &modes);
        let scale = (0..6).map(|k| rigid.col(k).norm_l2()).fold(0.0, f64::max);
        for i in 0..6 {
            for j in 0..modes.ncols() {
                assert!(rigid_coupling[(i, j)].abs() < 1e-9 * scale, "{set}: {}", rigid_coupling[(i, j)]);
            }
        }
        for i in 0..expected {
            for j in 0..expected {
                let (m, k) = (body.modal_mass[(i, j)], body.modal_stiffness[(i, j)]);
                let omega2 = (2.0 * std::f64::consts::PI * body.reduced_frequencies_hz[i]).powi(2);
                if i == j {
                    assert!((m - 1.0).abs() < 1e-9 && (k - omega2).abs() < 1e-8 * omega2, "{set} {i}: {m} {k} {omega2}");
                } else {
                    assert!(m.abs() < 1e-9 && k.abs() < 1e-8 * omega2.max(1.0), "{set} {i} {j}: {m} {k}");
                }
            }
        }
    }
}

/// A Craig–Bampton reduction assembles the unsupported model once and takes the supported model's
/// matrices from it (the held rows and columns removed): they are those of assembling the
/// supported model, for a rigid coupling (a distributing one may decline: its supports can change
/// what it eliminates).
#[test]
fn the_supported_assembly_is_the_unsupported_one_less_the_held_equations() {
    for kind in ["kinematic", "distributing"] {
        let model = two_ended_link(kind);
        let direct = assemble(&model).unwrap();
        let Some(taken) = assemble(&unsupported(&model)).unwrap().with_supports(&model).unwrap() else {
            assert_eq!(kind, "distributing", "the supports of a rigid coupling's reference nodes only remove equations");
            continue;
        };
        assert_eq!(taken.dofs, direct.dofs);
        assert_eq!(taken.equation_positions, direct.equation_positions);
        for (name, a, b) in [("K", &taken.stiffness, &direct.stiffness), ("M", &taken.mass, &direct.mass), ("F", &taken.mass_root, &direct.mass_root)] {
            assert_eq!((a.nrows(), a.ncols()), (b.nrows(), b.ncols()), "{kind}: {name}'s shape");
            let (a, b) = (a.to_dense(), b.to_dense());
            let difference = (0..a.nrows()).flat_map(|i| (0..a.ncols()).map(move |j| (i, j))).map(|(i, j)| (a[(i, j)] - b[(i, j)]).abs()).fold(0.0, f64::max);
            let size = (0..b.nrows()).flat_map(|i| (0..b.ncols()).map(move |j| (i, j))).map(|(i, j)| b[(i, j)].abs()).fold(0.0, f64::max);
            assert!(difference <= 1e-14 * size, "{kind}: {name} differs by {difference:e} of {size:e}");
        }
    }
}

#[test]
fn interface_set_errors_say_what_to_write() {
    let model = two_ended_link("kinematic");
    let settings = |set: &str, basis| ReductionSettings { mode_set: set.parse().unwrap(), basis, eigen: EigenSettings::default() };
    let error = reduce(&model, "link", &settings("8N6C", Basis::Orthonormal)).unwrap_err();
    assert!(error.to_string().contains("write 12C"), "{error}");
    let error = reduce(&model, "link", &settings("8N12C", Basis::Raw)).unwrap_err();
    assert!(error.to_string().contains("orthonormal"), "{error}");
}
