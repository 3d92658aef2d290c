//! Rigid couplings (`*KINEMATIC COUPLING`, `*RIGID BODY`): the interface node of a solid. A cantilever
//! block held through a reference node coupled to its root face vibrates exactly as the block with
//! that face clamped; a beam attached to a solid through a reference node is no longer a hinge; and
//! the coupling's errors name the reference node.

#[path = "support/solid_block.rs"]
mod solid_block;

use flexmb_fem::inp::parse_inp;
use flexmb_fem::modes::{vibration_modes, EigenSettings};
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use nalgebra::Vector3;
use solid_block::SolidBlock;

const REFERENCE: &str = "*NODE\n9000, 0., 0.05, 0.05\n";

#[test]
fn a_block_held_through_its_coupled_root_face_is_a_clamped_block() {
    let clamped = SolidBlock::cantilever("C3D20", 4);
    let free = SolidBlock { clamped: false, ..clamped.clone() };
    for coupling in ["*KINEMATIC COUPLING, REF NODE=9000\nROOT, 1, 3\n", "*RIGID BODY, NSET=ROOT, REF NODE=9000\n"] {
        let deck = free.deck_with(&format!("{REFERENCE}{coupling}*BOUNDARY\n9000, 1, 6\n"));
        let coupled = vibration_modes(&parse_inp(&deck, "coupled.inp").unwrap().model, 8, &EigenSettings::default()).unwrap();
        let direct = vibration_modes(&parse_inp(&clamped.deck(), "clamped.inp").unwrap().model, 8, &EigenSettings::default()).unwrap();
        for (a, b) in coupled.frequencies_hz.iter().zip(&direct.frequencies_hz) {
            assert!((a - b).abs() < 1e-9 * b, "{coupling}: {a} against {b}");
        }
    }
}

#[test]
fn a_free_block_with_a_reference_node_keeps_six_rigid_modes() {
    let free = SolidBlock { clamped: false, ..SolidBlock::cantilever("C3D8I", 8) };
    let deck = free.deck_with(&format!("{REFERENCE}*KINEMATIC COUPLING, REF NODE=9000\nROOT, 1, 3\n"));
    let modes = vibration_modes(&parse_inp(&deck, "free.inp").unwrap().model, 4, &EigenSettings::default()).unwrap();
    assert_eq!(modes.rigid_modes, 6);
    // The coupled face is rigid: the free-free bending frequencies rise a little above the bare
    // block's.
    let bare = vibration_modes(&parse_inp(&free.deck(), "bare.inp").unwrap().model, 4, &EigenSettings::default()).unwrap();
    for (a, b) in modes.frequencies_hz.iter().zip(&bare.frequencies_hz) {
        assert!(a >= b && *a < 1.05 * b, "{a} against {b}");
    }
}

#[test]
fn a_beam_attached_through_a_reference_node_is_not_a_hinge_and_reduces() {
    let block = SolidBlock::cantilever("C3D8", 4);
    let extra = "*NODE\n9000, 1., 0.05, 0.05\n9001, 1.5, 0.05, 0.05\n\
                 *KINEMATIC COUPLING, REF NODE=9000\nTIP, 1, 3\n\
                 *ELEMENT, TYPE=B31, ELSET=ARM\n9000, 9000, 9001\n\
                 *BEAM SECTION, ELSET=ARM, MATERIAL=STEEL, SECTION=CIRC\n0.01\n0., 0., 1.\n";
    let model = parse_inp(&block.deck_with(extra), "arm.inp").unwrap().model;
    let modes = vibration_modes(&model, 4, &EigenSettings::default()).unwrap();
    assert_eq!(modes.rigid_modes, 0);
    let settings = ReductionSettings { mode_set: "4N".parse().unwrap(), basis: Basis::Orthonormal, eigen: EigenSettings::default() };
    let body = reduce(&model, "arm", &settings).unwrap().body;
    // The reference node moves with the mode shapes, rotations included, and the coupled tip
    // nodes move with it rigidly: u_s = u_r + θ_r × (x_s − x_r).
    let reference = body.nodes.iter().position(|n| n.label == 9000).unwrap();
    for shape in &body.shapes {
        let (u_r, theta) = (Vector3::from(shape.translation[reference]), Vector3::from(shape.rotation[reference]));
        assert!(theta.norm() > 0.0);
        for &s in &model.mesh.node_sets["TIP"] {
            let d = model.mesh.nodes[s].position - model.mesh.nodes[reference].position;
            let expected = u_r + theta.cross(&d);
            assert!((Vector3::from(shape.translation[s]) - expected).norm() < 1e-12 * u_r.norm().max(theta.norm()));
        }
    }
}

#[test]
fn coupling_errors_name_the_reference_node() {
    let block = SolidBlock::cantilever("C3D8", 4);
    // A reference node that is a solid node has no rotations.
    let deck = block.deck_with("*KINEMATIC COUPLING, REF NODE=1\nTIP, 1, 3\n");
    let error = vibration_modes(&parse_inp(&deck, "bad.inp").unwrap().model, 2, &EigenSettings::default()).unwrap_err();
    assert!(error.to_string().starts_with("the rigid coupling of reference node 1: the reference node is a node of solid elements only"), "{error}");
    // Coupled and supported.
    let deck = block.deck_with(&format!("{REFERENCE}*KINEMATIC COUPLING, REF NODE=9000\nROOT, 1, 3\n"));
    let error = vibration_modes(&parse_inp(&deck, "bad.inp").unwrap().model, 2, &EigenSettings::default()).unwrap_err();
    assert!(error.to_string().contains("coupled and supported"), "{error}");
    // Only rigid couplings of all translations.
    let deck = block.deck_with(&format!("{REFERENCE}*KINEMATIC COUPLING, REF NODE=9000\nROOT, 2, 3\n"));
    let error = parse_inp(&deck, "bad.inp").unwrap_err().to_string();
    assert!(error.contains("degrees of freedom 2 to 3"), "{error}");
}
