//! Static correction modes: unit-load responses against beam theory and against a direct solve, on a
//! statically determinate cantilever and on a door-like frame whose supports leave it free to turn
//! about its hinge line (the seed's boundary set).

mod support;

use faer::linalg::solvers::Solve;
use faer::Mat;
use flexmb_fem::assembly::assemble;
use flexmb_fem::modes::prepare;
use flexmb_fem::static_correction::{load_vectors, static_correction_modes};
use flexmb_fem::{BeamSection, Dof, DofSet, FeModel, MassModel, Mesh, ModelOptions, Support};
use nalgebra::Vector3;
use support::*;

/// Dense copy of a sparse matrix.
fn dense(a: &faer::sparse::SparseColMat<usize, f64>) -> Mat<f64> {
    a.to_dense()
}

#[test]
fn cantilever_tip_force_and_torque_give_beam_theory_deflection_and_twist() {
    let section = square_section(0.01);
    let (length, n) = (1.0, 10);
    let mut model = cantilever(length, n, section.clone());
    let tip = model.mesh.nodes.len() - 1;
    model.static_loads = vec![force("tip_fz", tip, [0.0, 0.0, 1.0]), torque("tip_tx", tip, [2.0, 0.0, 0.0])];
    let prepared = prepare(&model).unwrap();
    let statics = static_correction_modes(&prepared.model, &prepared.assembled, &prepared.rigid).unwrap();
    let dofs = &prepared.assembled.dofs;
    let at = |mode: usize, dof: Dof| statics.shapes[(dofs.equation(tip, dof).unwrap(), mode)];
    let ei = E * section.iy;
    let gj = E / (2.0 * (1.0 + NU)) * section.torsion_constant;
    // Cubic Hermite beams are exact for end loads.
    assert!(rel(at(0, Dof::Uz), length.powi(3) / (3.0 * ei)) < 1e-10, "tip deflection {}", at(0, Dof::Uz));
    assert!(rel(at(0, Dof::Ry), -length.powi(2) / (2.0 * ei)) < 1e-10, "tip rotation {}", at(0, Dof::Ry));
    assert!(rel(at(1, Dof::Rx), length / gj) < 1e-10, "tip twist {}", at(1, Dof::Rx));
    assert!(statics.max_residual < 1e-10);
    assert_eq!(statics.rigid_load_fractions, vec![0.0, 0.0]);
}

#[test]
fn cantilever_static_mode_equals_a_direct_dense_solve() {
    let mut model = cantilever(1.2, 8, square_section(0.02));
    let node = 5;
    model.static_loads = vec![force("oblique", node, [0.3, -0.5, 0.8])];
    let prepared = prepare(&model).unwrap();
    let statics = static_correction_modes(&prepared.model, &prepared.assembled, &prepared.rigid).unwrap();
    let loads = load_vectors(&prepared.model, &prepared.assembled).unwrap();
    let direct = dense(&prepared.assembled.stiffness).partial_piv_lu().solve(&loads);
    let difference = (&statics.shapes - &direct).norm_max() / direct.norm_max();
    assert!(difference < 1e-10, "difference {difference:.2e}");
}

/// A rectangular frame of beams in the y–z plane (a door's edges) with the seed's supports: bottom
/// hinge fixed in x, y, z, top hinge fixed in x, y. It can still turn about the hinge line (the z
/// axis): one rigid mechanism. The mass is lumped: the comparison below takes the mass-orthogonality
/// to the mechanism with the nodes' masses.
fn door_frame() -> (FeModel, usize, usize) {
    let mut mesh = Mesh {
        materials: vec![steel()],
        beam_sections: vec![BeamSection { orientation: Vector3::new(1.0, 0.0, 0.0), ..square_section(0.03) }],
        ..Default::default()
    };
    let (w, h) = (0.8, 2.0);
    let corners = [Vector3::zeros(), Vector3::new(0.0, w, 0.0), Vector3::new(0.0, w, h), Vector3::new(0.0, 0.0, h)];
    for k in 0..4 {
        mesh.add_beam_line(corners[k], corners[(k + 1) % 4], 6, 0).unwrap();
    }
    let bottom = mesh.nearest_node(&corners[0]).unwrap().0;
    let top = mesh.nearest_node(&corners[3]).unwrap().0;
    let supports = vec![
        Support { node: bottom, dofs: DofSet::TRANSLATIONS },
        Support { node: top, dofs: DofSet::EMPTY.with(Dof::Ux).with(Dof::Uy) },
    ];
    let static_loads = vec![
        torque("bottom_rx", bottom, [1.0, 0.0, 0.0]),
        torque("bottom_ry", bottom, [0.0, 1.0, 0.0]),
        torque("top_rx", top, [1.0, 0.0, 0.0]),
        torque("top_ry", top, [0.0, 1.0, 0.0]),
        force("top_fz", top, [0.0, 0.0, 1.0]),
    ];
    let options = ModelOptions { mass: Some(MassModel::Lumped), ..Default::default() };
    (FeModel { mesh, supports, static_loads, options, ..Default::default() }, bottom, top)
}

#[test]
fn door_frame_static_modes_solve_the_singular_problem_and_match_an_extra_support_solution() {
    let (model, _, _) = door_frame();
    let prepared = prepare(&model).unwrap();
    assert_eq!(prepared.rigid.ncols(), 1, "one mechanism: the turn about the hinge line");
    let statics = static_correction_modes(&prepared.model, &prepared.assembled, &prepared.rigid).unwrap();
    // None of the five deleted constraints' loads moves the door about its hinges.
    for f in &statics.rigid_load_fractions {
        assert!(*f < 1e-12, "rigid load fraction {f}");
    }
    assert!(statics.max_residual < 1e-9, "residual {}", statics.max_residual);
    // M-orthogonal to the mechanism.
    let m = &prepared.assembled.mass;
    let coupling = prepared.rigid.transpose() * (m * &statics.shapes);
    assert!(coupling.norm_max() < 1e-12 * (m * &statics.shapes).norm_max());

    // The same loads with the mechanism held by a support far from the hinge line (x at the free
    // corner), solved densely, then freed of their mechanism part, give the same modes.
    let mut held = model.clone();
    let corner = held.mesh.nearest_node(&Vector3::new(0.0, 0.8, 2.0)).unwrap().0;
    held.supports.push(Support { node: corner, dofs: DofSet::EMPTY.with(Dof::Ux) });
    let assembled = assemble(&held).unwrap();
    let loads = load_vectors(&held, &assembled).unwrap();
    let direct = assembled.stiffness.to_dense().partial_piv_lu().solve(&loads);
    // Scatter both onto all nodal dofs and remove the rigid part of the direct solution.
    let full = |dofs: &flexmb_fem::assembly::DofMap, x: &Mat<f64>| -> Mat<f64> {
        let cols: Vec<Vec<f64>> = (0..x.ncols()).map(|j| dofs.expand(&(0..x.nrows()).map(|i| x[(i, j)]).collect::<Vec<_>>())).collect();
        Mat::from_fn(cols[0].len(), cols.len(), |i, j| cols[j][i])
    };
    let ours = full(&prepared.assembled.dofs, &statics.shapes);
    let theirs = full(&assembled.dofs, &direct);
    let rigid = full(&prepared.assembled.dofs, &prepared.rigid);
    let nodal_mass: Vec<f64> = (0..ours.nrows())
        .map(|g| if g % 6 < 3 { prepared.assembled.nodal_masses[g / 6].mass } else { 0.0 })
        .collect();
    let m_dot = |a: faer::ColRef<f64>, b: faer::ColRef<f64>| (0..a.nrows()).map(|g| nodal_mass[g] * a[g] * b[g]).sum::<f64>();
    for j in 0..ours.ncols() {
        let alpha = m_dot(rigid.col(0), theirs.col(j)) / m_dot(rigid.col(0), rigid.col(0));
        let corrected = theirs.col(j) - alpha * rigid.col(0);
        let difference = (&corrected - ours.col(j)).norm_max() / ours.col(j).norm_max();
        assert!(difference < 1e-8, "mode {j}: difference {difference:.2e}");
    }
}

#[test]
fn a_load_that_turns_the_door_is_balanced_by_inertia_relief() {
    let (mut model, _, top) = door_frame();
    model.static_loads = vec![torque("top_rz", top, [0.0, 0.0, 1.0])];
    let prepared = prepare(&model).unwrap();
    let statics = static_correction_modes(&prepared.model, &prepared.assembled, &prepared.rigid).unwrap();
    assert!(statics.rigid_load_fractions[0] > 0.1, "{:?}", statics.rigid_load_fractions);
    // The balanced load is solved exactly.
    assert!(statics.max_residual < 1e-9);
}

#[test]
fn a_load_on_a_supported_dof_is_an_error() {
    let (mut model, bottom, _) = door_frame();
    model.static_loads = vec![force("bottom_fx", bottom, [1.0, 0.0, 0.0])];
    let prepared = prepare(&model).unwrap();
    let error = static_correction_modes(&prepared.model, &prepared.assembled, &prepared.rigid).unwrap_err();
    assert!(error.to_string().contains("bottom_fx"), "{error}");
}
