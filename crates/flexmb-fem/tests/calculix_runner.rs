//! The CalculiX runner of the outside checks: its decks are read by flexmb's `.inp` reader, and, when
//! `ccx` is installed, ccx's first bending frequency of the B31 cantilever agrees with
//! Euler–Bernoulli theory and that of the S4 cantilever plate lies between the narrow-beam and
//! wide-strip values.

#[path = "support/calculix.rs"]
mod calculix;

use std::path::PathBuf;

use calculix::{CantileverBeam, CantileverPlate};
use flexmb_fem::inp::parse_inp;
use flexmb_fem::DofSet;

fn work_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("calculix-{name}-{}", std::process::id()))
}

#[test]
fn eigenvalue_table_of_a_dat_file() {
    let dat = "\n     E I G E N V A L U E   O U T P U T\n\n MODE NO    EIGENVALUE                       FREQUENCY   \n\
               \x20                                    REAL PART            IMAGINARY PART\n\
               \x20                          (RAD/TIME)      (CYCLES/TIME     (RAD/TIME)\n\n\
               \x20     1   0.2768795E+04   0.5261934E+02   0.8374628E+01   0.0000000E+00\n\
               \x20     2   0.1106582E+05   0.1051942E+03   0.1674218E+02   0.0000000E+00\n\n\
               \x20    P A R T I C I P A T I O N   F A C T O R S\n\n\
               \x20     1  -0.1E-13  -0.6E-06  -0.29E+01   0.1E-13   0.21E+01   0.48E-09\n";
    assert_eq!(
        calculix::parse_eigenvalue_table(dat),
        Some(vec![8.374628, 16.74218])
    );
    assert_eq!(calculix::parse_eigenvalue_table("no table"), None);
}

#[test]
fn decks_are_read_by_flexmb() {
    let beam = CantileverBeam::default();
    let read = parse_inp(&beam.deck(), "beam.inp").unwrap();
    let mesh = &read.model.mesh;
    assert_eq!(
        (mesh.nodes.len(), mesh.elements.len()),
        (beam.elements + 1, beam.elements)
    );
    assert!((mesh.nodes[beam.elements].position.x - beam.length).abs() < 1e-15);
    assert!((mesh.beam_sections[0].iy - beam.a * beam.b.powi(3) / 12.0).abs() < 1e-24);
    assert_eq!(read.model.supports.len(), 1);
    assert_eq!(read.model.supports[0].dofs, DofSet::ALL);

    let plate = CantileverPlate::default();
    let read = parse_inp(&plate.deck(), "plate.inp").unwrap();
    let mesh = &read.model.mesh;
    assert_eq!(mesh.nodes.len(), (plate.nx + 1) * (plate.ny + 1));
    assert_eq!(mesh.elements.len(), plate.nx * plate.ny);
    assert_eq!(mesh.shell_sections[0].thickness, plate.thickness);
    let clamped: Vec<usize> = read.model.supports.iter().map(|s| s.node).collect();
    assert_eq!(clamped.len(), plate.ny + 1);
    assert!(clamped.iter().all(|&n| mesh.nodes[n].position.x == 0.0));
}

#[test]
fn ccx_cantilever_first_frequency_matches_beam_theory() {
    if calculix::ccx_path().is_none() {
        println!("skipped: ccx not found (install Debian package calculix-ccx)");
        return;
    }
    let beam = CantileverBeam::default();
    let dir = work_dir("beam");
    let frequencies =
        calculix::natural_frequencies(&beam.deck(), &dir).unwrap_or_else(|e| panic!("{e}"));
    let theory = beam.first_bending_frequency();
    println!("ccx: {frequencies:.4?} Hz; Euler–Bernoulli first bending: {theory:.4} Hz");
    assert_eq!(frequencies.len(), beam.modes);
    let error = (frequencies[0] - theory) / theory;
    assert!(
        error.abs() < 0.02,
        "ccx {} Hz against {theory} Hz ({:+.2} %)",
        frequencies[0],
        100.0 * error
    );
    // The second mode bends about the stiffer axis: a/b times higher.
    let ratio = frequencies[1] / frequencies[0];
    assert!(
        (ratio - beam.a / beam.b).abs() < 0.02 * beam.a / beam.b,
        "f2/f1 = {ratio}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ccx_cantilever_plate_first_frequency_is_near_the_strip_estimate() {
    if calculix::ccx_path().is_none() {
        println!("skipped: ccx not found (install Debian package calculix-ccx)");
        return;
    }
    let plate = CantileverPlate::default();
    let dir = work_dir("plate");
    let frequencies =
        calculix::natural_frequencies(&plate.deck(), &dir).unwrap_or_else(|e| panic!("{e}"));
    let estimate = plate.first_bending_frequency_beam_estimate();
    println!("ccx: {frequencies:.4?} Hz; strip estimate of the first bending: {estimate:.4} Hz");
    // Between the narrow beam (stiffness E t³/12, no Poisson restraint) and the wide strip (D), with
    // 1 % for ccx's solid expansion and the mesh.
    let narrow = estimate * (1.0 - plate.poisson_ratio.powi(2)).sqrt();
    assert!(
        frequencies[0] > 0.99 * narrow && frequencies[0] < 1.01 * estimate,
        "ccx {} Hz, expected between {narrow} and {estimate} Hz",
        frequencies[0]
    );
    let _ = std::fs::remove_dir_all(&dir);
}
