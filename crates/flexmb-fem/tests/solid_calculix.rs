//! Solid elements against CalculiX (`ccx`) on the same decks: a steel cantilever block 1 m × 0.1 m ×
//! 0.1 m clamped at x = 0, meshed with each element type.
//!
//! - **Stiffness**, every type: a static load along y on the tip face gives the same tip
//!   displacements in ccx and flexmb, to 1e-6 of the largest (ccx prints 7 digits).
//! - **Frequencies** with the consistent mass (ccx's mass model): the first ten agree to 1e-6
//!   for C3D10, C3D6, C3D15, C3D8, C3D20 and C3D20R — the same formulations, integration points and
//!   mass. Two differ by design in the mass, not the stiffness: ccx integrates C3D4's mass at one
//!   point (the centroid), flexmb exactly (4 points), so that the element's inertia is right; and ccx
//!   gives C3D8I's incompatible modes mass (the bubbles move as internal nodes), flexmb condenses them
//!   out statically as massless internal modes, so that the body's dofs are its nodes'. Measured
//!   there: up to 6.6e-2 (C3D4, 8 × 2 × 2 cells, mode 6) and 1.1e-1 (C3D8I, mode 10); the first
//!   bending pair 1.5e-3 and 1.2e-3.
//!
//! Skipped, with a message, when `ccx` is not installed.

#[path = "support/calculix.rs"]
mod calculix;
#[path = "support/solid_block.rs"]
mod solid_block;

use std::path::PathBuf;

use calculix::{ccx_path, natural_frequencies, static_displacements};
use flexmb_fem::assembly::assemble;
use flexmb_fem::inp::parse_inp;
use faer::linalg::solvers::Solve;
use flexmb_fem::Dof;
use flexmb_fem::modes::{vibration_modes, EigenSettings};
use flexmb_fem::MassModel;
use solid_block::SolidBlock;

fn work_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("ccx-solid-{name}-{}", std::process::id()))
}

/// The largest relative difference of the first `block.modes` frequencies of flexmb (consistent
/// mass) and ccx on `block`'s deck, with the table printed; `None` without ccx.
fn largest_difference(block: &SolidBlock) -> Option<f64> {
    if ccx_path().is_none() {
        println!("skipped: ccx not found (install Debian package calculix-ccx)");
        return None;
    }
    let deck = block.deck();
    let name = format!("{}_{}x{}x{}", block.element, block.nx, block.ny, block.nz);
    let theirs = natural_frequencies(&deck, &work_dir(&name)).unwrap();
    let mut model = parse_inp(&deck, &name).unwrap().model;
    model.options.mass = Some(MassModel::Consistent);
    let ours = vibration_modes(&model, block.modes, &EigenSettings::default()).unwrap().frequencies_hz;
    println!("{name}: mode, flexmb [Hz], ccx [Hz], relative difference");
    let mut largest = 0.0_f64;
    for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        let difference = (a - b).abs() / b;
        largest = largest.max(difference);
        println!("  {:2}  {a:14.6}  {b:14.6}  {difference:.1e}", k + 1);
    }
    assert_eq!(theirs.len(), block.modes, "ccx found {} modes", theirs.len());
    Some(largest)
}

fn agrees(element: &'static str, nx: usize) {
    let block = SolidBlock::cantilever(element, nx);
    if let Some(largest) = largest_difference(&block) {
        assert!(largest < 1e-6, "{element}: largest relative difference {largest:.2e}");
    }
}

/// The largest difference of the tip displacements of ccx and flexmb under a tip load, relative to
/// the largest displacement; `None` without ccx.
fn static_difference(block: &SolidBlock) -> Option<f64> {
    if ccx_path().is_none() {
        println!("skipped: ccx not found (install Debian package calculix-ccx)");
        return None;
    }
    let force = 100.0;
    let deck = block.static_deck(force);
    let name = format!("{}_static", block.element);
    let theirs = static_displacements(&deck, &work_dir(&name)).unwrap();
    let model = parse_inp(&deck, &name).unwrap().model;
    let assembled = assemble(&model).unwrap();
    let tip = &model.mesh.node_sets["TIP"];
    let mut load = faer::Mat::zeros(assembled.dofs.n_free(), 1);
    for &node in tip {
        load[(assembled.dofs.equation(node, Dof::Uy).unwrap(), 0)] = force;
    }
    let ours = assembled.stiffness.to_dense().partial_piv_lu().solve(&load);
    assert_eq!(theirs.len(), tip.len());
    let largest = theirs.iter().map(|(_, u)| u[1].abs()).fold(0.0, f64::max);
    let mut difference = 0.0_f64;
    for (label, u) in &theirs {
        let node = model.mesh.node_index(*label).unwrap();
        for (k, dof) in [Dof::Ux, Dof::Uy, Dof::Uz].into_iter().enumerate() {
            let mine = ours[(assembled.dofs.equation(node, dof).unwrap(), 0)];
            difference = difference.max((mine - u[k]).abs() / largest);
        }
    }
    println!("{name}: tip deflection {largest:.7e} m, largest difference {difference:.1e} of it");
    Some(difference)
}

#[test]
fn static_tip_displacements_equal_calculix() {
    for (element, nx) in [("C3D4", 8), ("C3D10", 4), ("C3D6", 8), ("C3D15", 4), ("C3D8", 8), ("C3D8I", 8), ("C3D20", 4), ("C3D20R", 4)] {
        let Some(difference) = static_difference(&SolidBlock::cantilever(element, nx)) else { return };
        assert!(difference < 1e-6, "{element}: {difference:.2e}");
    }
}

/// The frequencies of a mesh whose mass differs from ccx's by design differ by less than `bound`.
fn differs_by_less_than(element: &'static str, nx: usize, bound: f64) {
    if let Some(largest) = largest_difference(&SolidBlock::cantilever(element, nx)) {
        assert!(largest < bound, "{element}: largest relative difference {largest:.2e}");
    }
}

/// ccx lumps C3D4's mass at the centroid (one point), flexmb integrates it exactly.
#[test]
fn c3d4_frequencies_differ_from_calculix_by_its_one_point_mass() {
    differs_by_less_than("C3D4", 8, 0.07);
}

#[test]
fn c3d10_frequencies_equal_calculix() {
    agrees("C3D10", 4);
}

#[test]
fn c3d6_frequencies_equal_calculix() {
    agrees("C3D6", 8);
}

#[test]
fn c3d15_frequencies_equal_calculix() {
    agrees("C3D15", 4);
}

#[test]
fn c3d8_frequencies_equal_calculix() {
    agrees("C3D8", 8);
}

/// ccx gives the incompatible modes mass, flexmb condenses them out.
#[test]
fn c3d8i_frequencies_differ_from_calculix_by_its_bubble_mass() {
    differs_by_less_than("C3D8I", 8, 0.12);
}

#[test]
fn c3d20_frequencies_equal_calculix() {
    agrees("C3D20", 4);
}

#[test]
fn c3d20r_frequencies_equal_calculix() {
    agrees("C3D20R", 4);
}
