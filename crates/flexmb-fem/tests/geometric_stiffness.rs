//! The geometric stiffness of solids and shells in the modal terms (formulation.md §11), against
//! closed forms: a slender C3D20 column's Euler load from the unit force at its coupled tip (an
//! interface node), a simply supported square plate's buckling under uniform compression from unit
//! forces along two opposite edges (interface nodes), and a rotating solid blade's Southwell
//! coefficient. The critical factor of a load case `G` is the smallest `f > 0` with `K_aa + f G`
//! singular, from the reduced (modal) matrices alone.

mod support;
#[path = "support/solid_block.rs"]
mod solid_block;

use flexmb_fem::inp::parse_inp;
use flexmb_fem::mesh::ShellShape;
use flexmb_fem::reduction::{reduce, Basis, FlexibleBody, ReductionSettings};
use flexmb_fem::{Dof, DofSet, Support};
use nalgebra::DMatrix;
use solid_block::SolidBlock;
use support::{rel, simply_supported_plate, E, NU};

fn settings(set: &str) -> ReductionSettings {
    ReductionSettings { mode_set: set.parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() }
}

/// The smallest `f > 0` with `K + f G` singular (`K` positive definite): with `K = L Lᵀ` and `μ` the
/// eigenvalues of `L⁻¹ G L⁻ᵀ`, `f = −1/μ` for the most negative `μ`.
fn critical_factor(k: &DMatrix<f64>, g: &DMatrix<f64>) -> f64 {
    let l_inv = k.clone().cholesky().expect("K_aa positive definite").l().try_inverse().unwrap();
    let s = &l_inv * g * l_inv.transpose();
    let mu = nalgebra::SymmetricEigen::new((&s + s.transpose()) * 0.5).eigenvalues.min();
    assert!(mu < 0.0, "the load does not soften the body");
    -1.0 / mu
}

/// The `G` of the interface case `case` (0..6: `F_x … M_z`) at the node labelled `label`.
fn interface_case(body: &FlexibleBody, label: u64, case: usize) -> DMatrix<f64> {
    let terms = body.geometric_stiffness.as_ref().expect("the body has the terms");
    terms.interface.iter().find(|i| i.node == label).expect("an interface node").loads[case].clone()
}

/// A steel column 2 m × 0.1 m × 0.1 m of 20 × 2 × 2 C3D20, clamped at x = 0, its tip face coupled
/// rigidly to a reference node (an interface node) at its centre: the unit compressive force there
/// buckles it at Euler's `π² E I / (4 L²)` = 1.0795e6 N, less the shear's `1/(1 + P/κGA)` (−0.16 %),
/// within 1 % (six modes).
#[test]
fn a_solid_column_buckles_at_eulers_load() {
    let block = SolidBlock { lx: 2.0, ..SolidBlock::cantilever("C3D20", 20) };
    let deck = block.deck_with("*NODE\n9000, 2., 0.05, 0.05\n*KINEMATIC COUPLING, REF NODE=9000\nTIP, 1, 3\n");
    let mut model = parse_inp(&deck, "column.inp").unwrap().model;
    model.interface_nodes.push(model.mesh.node_index(9000).unwrap());
    let body = reduce(&model, "column", &settings("6N")).unwrap().body;
    let compression = -interface_case(&body, 9000, 0);
    let found = critical_factor(&body.modal_stiffness, &compression);
    let inertia = block.ly.powi(4) / 12.0;
    let euler = std::f64::consts::PI.powi(2) * block.youngs_modulus * inertia / (4.0 * block.lx.powi(2));
    let shear = 5.0 / 6.0 * block.youngs_modulus / (2.0 * (1.0 + block.poisson_ratio)) * block.ly * block.lz;
    let expected = euler / (1.0 + euler / shear);
    eprintln!("C3D20 column: buckling load {found:.5e} N against {expected:.5e} N (Euler {euler:.5e}), {:+.2e}", found / expected - 1.0);
    assert!(rel(found, expected) < 0.01, "{found} against {expected}");
}

/// The same column without the coupling, spun about z through its root (`centrifugal[zz]`): the first
/// bending pair's `φᵀ G φ` (mass-normalized) is the Southwell coefficient of a clamped rotating beam,
/// 1.1935 (Hodges and Rutkowski), within 1 %.
#[test]
fn a_rotating_solid_blade_has_the_beams_southwell_coefficient() {
    let block = SolidBlock { lx: 2.0, ..SolidBlock::cantilever("C3D20", 20) };
    let model = parse_inp(&block.deck(), "blade.inp").unwrap().model;
    let body = reduce(&model, "blade", &settings("2N")).unwrap().body;
    let centrifugal = &body.geometric_stiffness.as_ref().unwrap().centrifugal[2];
    let southwell = 0.5 * (centrifugal[(0, 0)] + centrifugal[(1, 1)]);
    eprintln!("C3D20 blade: Southwell coefficient {southwell:.4} against 1.1935 ({:+.2e})", southwell / 1.1935 - 1.0);
    assert!(rel(southwell, 1.1935) < 0.01, "{southwell}");
}

/// A simply supported square steel plate 1 m × 1 m × 10 mm of 16 × 16 quadrilaterals (MITC4), held
/// in-plane at its centre (x, y) and at the middle of one loaded edge (y) only, compressed along x by
/// unit forces at the nodes of the edges x = 0 and x = a (each node its share of the edge, the corners
/// half): it buckles at `N_cr = 4 π² D / b²` (k = 4, `D = E t³ / 12(1 − ν²)`), within 1 %. The
/// same with triangles (DKT, two per cell) within 2 %.
#[test]
fn a_simply_supported_plate_buckles_at_k_4() {
    let (a, t, n) = (1.0_f64, 0.01_f64, 16);
    let bending = E * t.powi(3) / (12.0 * (1.0 - NU * NU));
    let expected = 4.0 * std::f64::consts::PI.powi(2) * bending / (a * a);
    for (shape, tolerance) in [(ShellShape::Quadrilateral, 0.01), (ShellShape::Triangle, 0.02)] {
        let mut model = simply_supported_plate(a, a, t, n, n, shape);
        let node_at = |x: f64, y: f64| model.mesh.nearest_node(&nalgebra::Vector3::new(x, y, 0.0)).unwrap().0;
        let (centre, side) = (node_at(0.5 * a, 0.5 * a), node_at(a, 0.5 * a));
        let mut edges = Vec::new();
        for j in 0..=n {
            let y = a * j as f64 / n as f64;
            let share = if j == 0 || j == n { 0.5 } else { 1.0 } * a / n as f64;
            edges.push((node_at(0.0, y), share));
            edges.push((node_at(a, y), -share));
        }
        model.supports.push(Support { node: centre, dofs: DofSet::EMPTY.with(Dof::Ux).with(Dof::Uy) });
        model.supports.push(Support { node: side, dofs: DofSet::EMPTY.with(Dof::Uy) });
        model.interface_nodes = edges.iter().map(|&(node, _)| node).collect();
        let body = reduce(&model, "plate", &settings("6N")).unwrap().body;
        // Compression per unit length along x: +x on the edge x = 0, −x on x = a.
        let mut compression = DMatrix::zeros(6, 6);
        for &(node, share) in &edges {
            compression += interface_case(&body, model.mesh.nodes[node].label, 0) * share;
        }
        let found = critical_factor(&body.modal_stiffness, &compression);
        eprintln!("{shape:?} plate: buckling N_x {found:.2} N/m against 4π²D/b² = {expected:.2} N/m ({:+.2e})", found / expected - 1.0);
        assert!(rel(found, expected) < tolerance, "{shape:?}: {found} against {expected}");
    }
}
