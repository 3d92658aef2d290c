//! Distributing (RBE3-like) couplings (`*DISTRIBUTING COUPLING` with a `DCOUP3D` reference node):
//!
//! - against CalculiX: a cantilever block whose tip face's mean translation is held through the
//!   reference node vibrates as in ccx (which reads the same deck), to 1e-6;
//! - the coupling adds no stiffness: a free block with a coupled reference node has six rigid modes
//!   and exactly the bare block's elastic frequencies;
//! - in a reduced body's mode shapes the reference node moves as the weighted least-squares rigid
//!   fit of the coupled nodes' translations (the fit's residuals have no resultant and no moment);
//! - its errors name the reference node.
//!
//! The ccx comparison is skipped, with a message, when `ccx` is not installed.

#[path = "support/calculix.rs"]
mod calculix;
#[path = "support/solid_block.rs"]
mod solid_block;

use std::path::PathBuf;

use calculix::{ccx_path, natural_frequencies};
use flexmb_fem::inp::parse_inp;
use flexmb_fem::modes::{vibration_modes, EigenSettings};
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use flexmb_fem::MassModel;
use nalgebra::Vector3;
use solid_block::SolidBlock;

/// A reference node at the centre of the tip face (x = 1 m), its DCOUP3D element, and the tip face
/// coupled to it with unit weights.
const TIP_COUPLING: &str = "*NODE\n9000, 1., 0.05, 0.05\n*ELEMENT, TYPE=DCOUP3D, ELSET=TIP_REFERENCE\n9000, 9000\n\
                            *DISTRIBUTING COUPLING, ELSET=TIP_REFERENCE\nTIP, 1.\n";

#[test]
fn a_cantilever_with_its_tip_held_through_a_distributing_coupling_vibrates_as_in_calculix() {
    if ccx_path().is_none() {
        println!("skipped: ccx not found (install Debian package calculix-ccx)");
        return;
    }
    let block = SolidBlock::cantilever("C3D20", 4);
    // The tip face's mean translation held (all three, then y only: a propped cantilever).
    for held in ["1, 3", "2, 2"] {
        let deck = block.deck_with(&format!("{TIP_COUPLING}*BOUNDARY\n9000, {held}\n"));
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("ccx-rbe3-{}-{}", held.replace(", ", "-"), std::process::id()));
        let theirs = natural_frequencies(&deck, &dir).unwrap();
        let mut model = parse_inp(&deck, "rbe3.inp").unwrap().model;
        model.options.mass = Some(MassModel::Consistent);
        let ours = vibration_modes(&model, block.modes, &EigenSettings::default()).unwrap().frequencies_hz;
        println!("tip reference node held in dofs {held}: mode, flexmb [Hz], ccx [Hz], relative difference");
        let mut largest = 0.0_f64;
        for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
            let difference = (a - b).abs() / b;
            largest = largest.max(difference);
            println!("  {:2}  {a:14.6}  {b:14.6}  {difference:.1e}", k + 1);
        }
        assert_eq!(theirs.len(), block.modes);
        assert!(largest < 1e-6, "held {held}: largest relative difference {largest:.2e}");
    }
}

#[test]
fn a_distributing_coupling_adds_no_stiffness() {
    let free = SolidBlock { clamped: false, ..SolidBlock::cantilever("C3D8I", 8) };
    let coupled = vibration_modes(&parse_inp(&free.deck_with(TIP_COUPLING), "free.inp").unwrap().model, 6, &EigenSettings::default()).unwrap();
    let bare = vibration_modes(&parse_inp(&free.deck(), "bare.inp").unwrap().model, 6, &EigenSettings::default()).unwrap();
    assert_eq!(coupled.rigid_modes, 6);
    for (a, b) in coupled.frequencies_hz.iter().zip(&bare.frequencies_hz) {
        assert!((a - b).abs() < 1e-9 * b, "{a} against {b}");
    }
}

#[test]
fn the_reference_node_follows_the_least_squares_fit_of_the_coupled_nodes() {
    let block = SolidBlock::cantilever("C3D8", 4);
    // Unequal weights, and the reference node off the face's centre.
    let extra = "*NODE\n9000, 1.2, 0.08, 0.03\n*ELEMENT, TYPE=DCOUP3D, ELSET=R\n9000, 9000\n\
                 *DISTRIBUTING COUPLING, ELSET=R\nTIP, 2.\n1, 3.\n";
    let deck = block.deck_with(extra);
    let model = parse_inp(&deck, "fit.inp").unwrap().model;
    let settings = ReductionSettings { mode_set: "4N".parse().unwrap(), basis: Basis::Orthonormal, eigen: EigenSettings::default() };
    let body = reduce(&model, "fit", &settings).unwrap().body;
    let coupling = &model.mesh.distributing_couplings[0];
    let r = coupling.reference;
    let x_r = model.mesh.nodes[r].position;
    for shape in &body.shapes {
        let (u_r, theta) = (Vector3::from(shape.translation[r]), Vector3::from(shape.rotation[r]));
        let (mut force, mut moment, mut scale) = (Vector3::zeros(), Vector3::zeros(), 0.0_f64);
        for (&s, w) in coupling.nodes.iter().zip(&coupling.weights) {
            let d = model.mesh.nodes[s].position - x_r;
            let residual = Vector3::from(shape.translation[s]) - u_r - theta.cross(&d);
            force += *w * residual;
            moment += *w * d.cross(&residual);
            scale = scale.max(Vector3::from(shape.translation[s]).norm());
        }
        assert!(theta.norm() > 0.0);
        assert!(force.norm() < 1e-10 * scale && moment.norm() < 1e-10 * scale, "{force} {moment}");
    }
}

#[test]
fn distributing_coupling_errors_name_the_reference_node() {
    let block = SolidBlock::cantilever("C3D8", 4);
    let eigen = EigenSettings::default();
    // Coupled nodes on one line: the rotation about it is undefined.
    let deck = block.deck_with("*NODE\n9000, 1., 0.05, 0.05\n*ELEMENT, TYPE=DCOUP3D, ELSET=R\n9000, 9000\n*NSET, NSET=EDGE\n5, 10\n*DISTRIBUTING COUPLING, ELSET=R\nEDGE, 1.\n");
    let error = vibration_modes(&parse_inp(&deck, "line.inp").unwrap().model, 2, &eigen).unwrap_err();
    assert!(error.to_string().starts_with("the distributing coupling of reference node 9000:"), "{error}");
    // A node coupled twice, rigidly and distributed.
    let deck = block.deck_with(&format!("{TIP_COUPLING}*NODE\n9001, 1., 0.05, 0.05\n*KINEMATIC COUPLING, REF NODE=9001\nTIP, 1, 3\n"));
    let error = vibration_modes(&parse_inp(&deck, "twice.inp").unwrap().model, 2, &eigen).unwrap_err();
    assert!(error.to_string().contains("is coupled twice"), "{error}");
    // The Abaqus *COUPLING form is refused with the forms flexmb reads.
    let error = parse_inp(&block.deck_with("*COUPLING, REF NODE=9000, SURFACE=S, CONSTRAINT NAME=C\n*DISTRIBUTING\n"), "c.inp").unwrap_err();
    assert!(error.to_string().contains("*DISTRIBUTING COUPLING, ELSET="), "{error}");
    // The element set must hold the DCOUP3D element.
    let error = parse_inp(&block.deck_with("*DISTRIBUTING COUPLING, ELSET=BLOCK\nTIP, 1.\n"), "e.inp").unwrap_err();
    assert!(error.to_string().contains("exactly one DCOUP3D"), "{error}");
}
