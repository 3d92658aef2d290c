//! Solid meshes against closed form as they refine: the first bending frequency of a cantilever
//! block converges to that of a Timoshenko beam; a free-free cube has six rigid modes, the mass and
//! inertia of the cube, and a first elastic frequency that converges. And mixed meshes: a solid block
//! with a shell skin sharing its nodes keeps the rotations of the skin's nodes only.

mod support;
#[path = "support/solid_block.rs"]
mod solid_block;

use flexmb_fem::assembly::{assemble, MassProperties};
use flexmb_fem::inp::parse_inp;
use flexmb_fem::modes::{vibration_modes, EigenSettings};
use flexmb_fem::{BeamSection, Dof, DofSet, MassModel, ModelOptions, Support};
use nalgebra::{Matrix3, Vector3};
use solid_block::SolidBlock;
use support::{cantilever, rel, square_section, E, NU, RHO};

/// The first frequency (Hz) of `block` with the consistent mass, and the rigid modes. With
/// `beam_clamp`, the root face x = 0 is held as a beam's clamp (plane, free to contract): ux on the
/// whole face, uy on its line y = ly/2 and uz on its line z = lz/2.
fn first_frequency(block: &SolidBlock, count: usize, beam_clamp: bool) -> (f64, usize) {
    first_frequency_with(block, count, beam_clamp, MassModel::Consistent)
}

fn first_frequency_with(block: &SolidBlock, count: usize, beam_clamp: bool, mass: MassModel) -> (f64, usize) {
    let mut model = parse_inp(&block.deck(), "block.inp").unwrap().model;
    model.options.mass = Some(mass);
    if beam_clamp {
        for node in model.mesh.node_sets["ROOT"].clone() {
            let p = model.mesh.nodes[node].position;
            let mut dofs = DofSet::EMPTY.with(Dof::Ux);
            if (p.y - block.ly / 2.0).abs() < 1e-9 {
                dofs = dofs.with(Dof::Uy);
            }
            if (p.z - block.lz / 2.0).abs() < 1e-9 {
                dofs = dofs.with(Dof::Uz);
            }
            model.supports.push(Support { node, dofs });
        }
    }
    let modes = vibration_modes(&model, count, &EigenSettings::default()).unwrap();
    (modes.frequencies_hz[0], modes.rigid_modes)
}

/// The first bending frequency (Hz) of a Timoshenko cantilever 1 m × 0.1 m × 0.1 m of steel (Cowper's
/// shear coefficient of a square, 10 (1 + ν) / (12 + 11 ν); rotary inertia): flexmb's beam elements,
/// 200 of them, consistent mass.
fn timoshenko_frequency() -> f64 {
    let h: f64 = 0.1;
    let section = BeamSection { shear_coefficient: Some(10.0 * (1.0 + NU) / (12.0 + 11.0 * NU)), ..square_section(h) };
    let mut model = cantilever(1.0, 200, section);
    model.options = ModelOptions { mass: Some(MassModel::Consistent), rotary_inertia: true, ..ModelOptions::default() };
    vibration_modes(&model, 1, &EigenSettings::default()).unwrap().frequencies_hz[0]
}

/// Euler–Bernoulli: (1.8751)² / 2π √(E I / (ρ A L⁴)).
fn euler_bernoulli_frequency() -> f64 {
    1.875_104_068_711_961_f64.powi(2) / (2.0 * std::f64::consts::PI) * (E * 0.1f64.powi(2) / 12.0 / (RHO * 1.0)).sqrt()
}

#[test]
fn cantilever_block_converges_to_timoshenko_bending() {
    let timoshenko = timoshenko_frequency();
    let euler_bernoulli = euler_bernoulli_frequency();
    println!("first bending: Euler–Bernoulli {euler_bernoulli:.4} Hz, Timoshenko {timoshenko:.4} Hz");
    for (element, meshes) in [("C3D20", [(4, 2), (8, 2), (16, 4)]), ("C3D8I", [(8, 2), (16, 4), (32, 8)]), ("C3D10", [(4, 2), (8, 2), (16, 4)])] {
        let mut errors = Vec::new();
        for (nx, n) in meshes {
            let block = SolidBlock { ny: n, nz: n, clamped: false, ..SolidBlock::cantilever(element, nx) };
            let (f, _) = first_frequency(&block, 1, true);
            println!("  {element} {nx} × {n} × {n}: {f:.4} Hz, {:+.3e} from Timoshenko", f / timoshenko - 1.0);
            errors.push(rel(f, timoshenko));
        }
        assert!(errors[2] < 1e-3 && errors[2] < errors[0] / 4.0, "{element}: {errors:?}");
    }
}

#[test]
fn free_free_cube_has_six_rigid_modes_its_inertia_and_a_converging_first_frequency() {
    let mut frequencies = Vec::new();
    for n in 1..=4 {
        let cube = SolidBlock { lx: 1.0, ly: 1.0, lz: 1.0, nx: n, ny: n, nz: n, clamped: false, ..SolidBlock::cantilever("C3D20", 1) };
        let (f, rigid) = first_frequency(&cube, 1, false);
        assert_eq!(rigid, 6, "{n} × {n} × {n}");
        let mut model = parse_inp(&cube.deck(), "cube.inp").unwrap().model;
        model.options.mass = Some(MassModel::Consistent);
        let properties = MassProperties::of_points(&assemble(&model).unwrap().mass_points);
        assert!(rel(properties.mass, RHO) < 1e-12);
        assert!((properties.center_of_mass - Vector3::repeat(0.5)).norm() < 1e-12);
        assert!((properties.inertia - Matrix3::identity() * (RHO / 6.0)).norm() < 1e-12 * RHO);
        println!("free cube of {n}³ C3D20: first elastic frequency {f:.4} Hz");
        frequencies.push(f);
    }
    let steps: Vec<f64> = frequencies.windows(2).map(|w| (w[0] - w[1]).abs() / w[1]).collect();
    println!("relative changes per refinement: {:.2e} {:.2e} {:.2e}", steps[0], steps[1], steps[2]);
    // Measured: 1.95e-1, 1.06e-2, 2.67e-3 — from 2³ on the changes fall like h³ (their ratio 3.96,
    // where h³ gives 4.1), to a limit about 1457.6 Hz (Richardson, p = 3).
    assert!(steps[1] < steps[0] / 4.0 && steps[2] < steps[1] / 3.0, "{steps:?}");
    assert!(steps[2] < 3e-3, "{steps:?}");
}

/// A C3D8I block (8 × 2 × 2, clamped at x = 0) with a skin of S4 shells 5 mm thick on its top face,
/// sharing the block's nodes, its sets given with GENERATE.
fn skinned_block() -> (SolidBlock, String) {
    let block = SolidBlock::cantilever("C3D8I", 8);
    let grid = block.top_face_labels();
    let first = block.elements().len() + 1;
    let mut skin = "*ELEMENT, TYPE=S4\n".to_string();
    let mut label = first;
    for i in 0..block.nx {
        for j in 0..block.ny {
            skin += &format!("{label}, {}, {}, {}, {}\n", grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]);
            label += 1;
        }
    }
    skin += &format!("*ELSET, ELSET=SKIN, GENERATE\n{first}, {}, 1\n", label - 1);
    skin += "*SHELL SECTION, ELSET=SKIN, MATERIAL=STEEL\n0.005\n";
    skin += "*NSET, NSET=FIRST_TEN, GENERATE\n1, 10\n*ELSET, ELSET=EVERYTHING\nBLOCK, SKIN\n";
    (block.clone(), block.deck_with(&skin))
}

#[test]
fn a_shell_skin_on_a_solid_block_keeps_the_rotations_of_its_nodes_only() {
    let (block, deck) = skinned_block();
    let read = parse_inp(&deck, "skinned.inp").unwrap();
    let mut model = read.model;
    assert_eq!(model.mesh.node_sets["FIRST_TEN"].len(), 10);
    let skin_nodes = (block.nx + 1) * (block.ny + 1);
    let root_nodes = model.mesh.node_sets["ROOT"].len();
    let all_nodes = model.mesh.nodes.len();
    let assembled = assemble(&model).unwrap();
    // Three dofs at every node, three more (rotations) at the skin's; the root's translations held
    // (its skin nodes keep their rotations: the clamp is ccx's "1, 3").
    assert_eq!(assembled.dofs.n_free(), 3 * all_nodes + 3 * skin_nodes - 3 * root_nodes);
    model.options.mass = Some(MassModel::Consistent);
    let skinned = vibration_modes(&model, 2, &EigenSettings::default()).unwrap();
    let (bare, _) = first_frequency(&block, 2, false);
    // The skin (5 % of the block's mass, its mid-surface on the top face) stiffens bending in z:
    // by beam theory EI × 1.143 and ρA × 1.05, so the frequency × 1.043; measured 1.041.
    let ratio = skinned.frequencies_hz[1] / bare;
    println!("bare block {bare:.3} Hz, skinned {:.3} / {:.3} Hz", skinned.frequencies_hz[0], skinned.frequencies_hz[1]);
    assert!((ratio - 1.043).abs() < 5e-3, "{ratio}");
}

#[test]
fn a_beam_on_a_single_solid_node_is_a_hinge() {
    let block = SolidBlock::cantilever("C3D8", 4);
    let tip = block.top_face_labels()[block.nx][0];
    let extra = "*NODE\n1000, 1.5, 0., 0.1\n*ELEMENT, TYPE=B31, ELSET=ARM\n1000, TIP_CORNER, 1000\n"
        .replace("TIP_CORNER", &tip.to_string())
        + "*BEAM SECTION, ELSET=ARM, MATERIAL=STEEL, SECTION=CIRC\n0.01\n0., 0., 1.\n";
    let model = parse_inp(&block.deck_with(&extra), "arm.inp").unwrap().model;
    let error = vibration_modes(&model, 2, &EigenSettings::default()).unwrap_err();
    assert!(error.to_string().contains("mechanism"), "{error}");
}

/// The lumped mass (row sums for C3D8I, HRZ for C3D20 and C3D10) converges to the same first bending
/// frequency as the consistent one, from below: their gap on the same mesh falls like h² (measured:
/// C3D20 1.8e-2, 4.9e-3, 1.2e-3; C3D8I 6.9e-3, 1.7e-3, 4.3e-4).
#[test]
fn the_lumped_mass_of_solids_converges_to_the_same_bending_frequency() {
    for (element, meshes) in [("C3D20", [(4, 2), (8, 2), (16, 4)]), ("C3D8I", [(8, 2), (16, 4), (32, 8)]), ("C3D10", [(4, 2), (8, 2), (16, 4)])] {
        let mut gaps = Vec::new();
        for (nx, n) in meshes {
            let block = SolidBlock { ny: n, nz: n, clamped: false, ..SolidBlock::cantilever(element, nx) };
            let (lumped, _) = first_frequency_with(&block, 1, true, MassModel::Lumped);
            let (consistent, _) = first_frequency_with(&block, 1, true, MassModel::Consistent);
            println!("  {element} {nx} × {n} × {n}: lumped {lumped:.4} Hz, consistent {consistent:.4} Hz");
            assert!(lumped < consistent, "{element}");
            gaps.push(rel(lumped, consistent));
        }
        assert!(gaps[1] < gaps[0] / 3.0 && gaps[2] < gaps[1] / 3.0 && gaps[2] < 1.5e-3, "{element}: {gaps:?}");
    }
}
