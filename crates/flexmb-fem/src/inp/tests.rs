use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use super::*;
use crate::mesh::{Dof, DofSet, ElementKind};

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs())
}

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn parse(text: &str) -> InpModel {
    parse_inp(text, "test.inp").unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str) -> String {
    parse_inp(text, "bad.inp")
        .expect_err("the deck should be refused")
        .to_string()
}

const MATERIAL: &str = "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850\n";

#[test]
fn cantilever_fixture() {
    let InpModel { model, warnings } = read_inp(&data_dir().join("cantilever_b31.inp")).unwrap();
    let mesh = &model.mesh;
    assert_eq!(mesh.nodes.len(), 11);
    assert_eq!(mesh.elements.len(), 10);
    assert_eq!(mesh.materials.len(), 1);
    assert_eq!(mesh.beam_sections.len(), 1);
    assert!(mesh.shell_sections.is_empty());
    assert!((mesh.nodes[10].position - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-15);
    assert_eq!(mesh.nodes[10].label, 11);
    let m = &mesh.materials[0];
    assert_eq!(
        (
            m.name.as_str(),
            m.youngs_modulus,
            m.poisson_ratio,
            m.density
        ),
        ("STEEL", 210e9, 0.3, 7850.0)
    );
    let s = &mesh.beam_sections[0];
    assert_eq!(s.name, "EBEAM");
    assert!(close(s.area, 2e-4, 1e-14));
    assert!(close(s.iy, 0.02 * 0.01_f64.powi(3) / 12.0, 1e-14));
    assert!(close(s.iz, 0.01 * 0.02_f64.powi(3) / 12.0, 1e-14));
    assert!(close(
        s.torsion_constant,
        0.229 * 0.02 * 0.01_f64.powi(3),
        2e-3
    ));
    assert_eq!(s.orientation, Vector3::new(0.0, 1.0, 0.0));
    assert_eq!(s.shear_coefficient, None);
    assert!(mesh
        .elements
        .iter()
        .all(|e| e.kind == ElementKind::Beam { section: 0 }));
    assert_eq!(mesh.elements[3].nodes, vec![3, 4]);
    assert_eq!(mesh.node_sets["ROOT"], vec![0]);
    assert_eq!(mesh.node_sets["NALL"].len(), 11);
    assert_eq!(model.supports.len(), 1);
    assert_eq!(
        (model.supports[0].node, model.supports[0].dofs),
        (0, DofSet::ALL)
    );
    assert!(model.static_loads.is_empty());
    // One warning per skipped keyword: *STEP, *FREQUENCY, *NODE FILE, *END STEP.
    assert_eq!(warnings.len(), 4, "{warnings:#?}");
    assert!(
        warnings[0]
            .ends_with("cantilever_b31.inp:43: *STEP is not read by flexmb: skipped (warned once)"),
        "{}",
        warnings[0]
    );
}

#[test]
fn plate_fixture() {
    let InpModel { model, warnings } = read_inp(&data_dir().join("plate_s4.inp")).unwrap();
    let mesh = &model.mesh;
    assert_eq!(mesh.nodes.len(), 20);
    assert_eq!(mesh.elements.len(), 12);
    assert_eq!(mesh.shell_sections.len(), 1);
    assert_eq!(mesh.shell_sections[0].thickness, 0.002);
    assert_eq!(
        mesh.materials[mesh.shell_sections[0].material].name,
        "Aluminium"
    );
    // Element 5 is written over two lines.
    assert_eq!(mesh.elements[4].label, 5);
    assert_eq!(mesh.elements[4].nodes, vec![5, 6, 11, 10]);
    assert!(mesh
        .elements
        .iter()
        .all(|e| e.kind == ElementKind::Shell { section: 0 } && e.nodes.len() == 4));
    assert_eq!(mesh.point_masses.len(), 1);
    assert_eq!(
        (mesh.point_masses[0].node, mesh.point_masses[0].mass),
        (19, 0.05)
    );
    assert_eq!(mesh.node_sets["CLAMPED"], vec![0, 5, 10, 15]);
    let supported: Vec<usize> = model.supports.iter().map(|s| s.node).collect();
    assert_eq!(supported, vec![0, 5, 10, 15]);
    assert!(model.supports.iter().all(|s| s.dofs == DofSet::ALL));
    assert_eq!(warnings.len(), 3, "{warnings:#?}");
}

#[test]
fn library_sections() {
    let text = format!(
        "*NODE\n1, 0,0,0\n2, 1,0,0\n3, 2,0,0\n4, 3,0,0\n5, 4,0,0\n\
         *ELEMENT, TYPE=B31, ELSET=R\n1, 1, 2\n*ELEMENT, TYPE=B31H, ELSET=C\n2, 2, 3\n\
         *ELEMENT, TYPE=B31, ELSET=P\n3, 3, 4\n*ELEMENT, TYPE=b31, ELSET=B\n4, 4, 5\n{MATERIAL}\
         *BEAM SECTION, ELSET=R, MATERIAL=STEEL, SECTION=RECT\n0.03, 0.01\n0, 1, 0\n\
         *BEAM SECTION, ELSET=C, MATERIAL=STEEL, SECTION=CIRC\n0.01\n\
         *BEAM SECTION, ELSET=P, MATERIAL=steel, SECTION=PIPE\n0.05, 0.005\n0, 0, 1\n\
         *BEAM SECTION, ELSET=B, MATERIAL=STEEL, SECTION=BOX\n0.1, 0.2, 0.01, 0.01, 0.01, 0.01\n0, 1, 1\n"
    );
    let InpModel { model, warnings } = parse(&text);
    assert!(warnings.is_empty(), "{warnings:?}");
    let s = &model.mesh.beam_sections;
    assert_eq!(s.len(), 4);
    // RECT a = 0.03 along n1 (local y), b = 0.01 along n2: iy = a b³/12, iz = b a³/12.
    assert!(close(s[0].area, 3e-4, 1e-14));
    assert!(close(s[0].iy, 0.03 * 1e-6 / 12.0, 1e-14));
    assert!(close(s[0].iz, 0.01 * 2.7e-5 / 12.0, 1e-14));
    // CIRC r = 0.01, default n1.
    assert!(close(s[1].area, PI * 1e-4, 1e-14));
    assert!(close(s[1].iy, PI * 1e-8 / 4.0, 1e-14) && close(s[1].iz, s[1].iy, 1e-15));
    assert!(close(s[1].torsion_constant, PI * 1e-8 / 2.0, 1e-14));
    assert_eq!(s[1].orientation, Vector3::from(DEFAULT_N1));
    // PIPE r = 0.05, t = 0.005.
    let ri: f64 = 0.045;
    assert!(close(s[2].area, PI * (0.0025 - ri * ri), 1e-14));
    assert!(close(
        s[2].iy,
        PI * (0.05_f64.powi(4) - ri.powi(4)) / 4.0,
        1e-14
    ));
    assert!(close(s[2].torsion_constant, 2.0 * s[2].iy, 1e-15));
    assert_eq!(s[2].orientation, Vector3::new(0.0, 0.0, 1.0));
    assert!(close(s[3].area, 0.02 - 0.08 * 0.18, 1e-13));
    assert_eq!(
        model.mesh.elements[1].kind,
        ElementKind::Beam { section: 1 }
    );
}

#[test]
fn general_section_mass_and_rotary_inertia() {
    let text = "*NODE\n1, 0,0,0\n2, 1,0,0\n3, 2,0,0\n\
                *ELEMENT, TYPE=B31, ELSET=G\n1, 1, 2\n2, 2, 3\n\
                *ELEMENT, TYPE=MASS, ELSET=M\n10, 3\n*ELEMENT, TYPE=ROTARYI, ELSET=J\n11, 3\n\
                *BEAM GENERAL SECTION, ELSET=G, DENSITY=2700\n1e-3, 2e-7, 0, 3e-7, 4e-7\n\n70e9, 26.3e9\n\
                *MASS, ELSET=M\n1.5\n*ROTARY INERTIA, ELSET=J\n0.1, 0.2, 0.3\n*ELSET, ELSET=MJ\nM, J\n";
    let InpModel { model, .. } = parse(text);
    let mesh = &model.mesh;
    let s = &mesh.beam_sections[0];
    assert_eq!(
        (s.area, s.iy, s.iz, s.torsion_constant),
        (1e-3, 2e-7, 3e-7, 4e-7)
    );
    assert_eq!(s.orientation, Vector3::from(DEFAULT_N1));
    let m = &mesh.materials[s.material];
    assert_eq!((m.youngs_modulus, m.density), (70e9, 2700.0));
    assert!(close(m.shear_modulus(), 26.3e9, 1e-12));
    assert_eq!(mesh.point_masses.len(), 2);
    assert_eq!(
        (mesh.point_masses[0].node, mesh.point_masses[0].mass),
        (2, 1.5)
    );
    assert_eq!(
        mesh.point_masses[1].rotary_inertia,
        Vector3::new(0.1, 0.2, 0.3)
    );
    assert_eq!(mesh.point_masses[1].mass, 0.0);
    // Both on one MASS element.
    let both = "*NODE\n1, 0,0,0\n*ELEMENT, TYPE=MASS, ELSET=M\n1, 1\n*MASS, ELSET=M\n2\n*ROTARY INERTIA, ELSET=M\n1, 1, 1\n";
    let mesh = parse(both).model.mesh;
    assert_eq!(mesh.point_masses.len(), 1);
    assert_eq!(
        (
            mesh.point_masses[0].mass,
            mesh.point_masses[0].rotary_inertia
        ),
        (2.0, Vector3::new(1.0, 1.0, 1.0))
    );
    let general_rect = "*NODE\n1, 0,0,0\n2, 1,0,0\n*ELEMENT, TYPE=B31, ELSET=G\n1, 1, 2\n\
                        *BEAM GENERAL SECTION, ELSET=G, SECTION=RECT, DENSITY=7800\n0.02, 0.01\n0, 1, 0\n200e9, 80e9\n";
    let s = &parse(general_rect).model.mesh.beam_sections[0];
    assert!(close(s.iy, 0.02e-6 / 12.0, 1e-14));
    assert_eq!(s.orientation, Vector3::new(0.0, 1.0, 0.0));
    let coupled = "*NODE\n1, 0,0,0\n2, 1,0,0\n*ELEMENT, TYPE=B31, ELSET=G\n1, 1, 2\n\
                   *BEAM GENERAL SECTION, ELSET=G, DENSITY=1\n1, 2, 0.5, 3, 4\n\n1, 0.4\n";
    assert!(
        error(coupled).starts_with("bad.inp:7: *BEAM GENERAL SECTION: I12 = 0.5 is not zero"),
        "{}",
        error(coupled)
    );
}

#[test]
fn supports_from_boundary_with_sets_merged_per_node() {
    let text = format!(
        "*NODE, NSET=ALL\n1, 0,0,0\n2, 1,0,0\n3, 2,0,0\n4, 3,0,0\n*NSET, NSET=ENDS\n1, 4\n*NSET, NSET=SOME\nENDS, 2\n\
         *ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n2, 2, 3\n3, 3, 4\n{MATERIAL}\
         *BEAM SECTION, ELSET=E, MATERIAL=STEEL, SECTION=CIRC\n0.01\n0, 1, 0\n\
         *BOUNDARY\nENDS, 1, 3\n4, 6\nsome, 5,, 0.0\n\
         *STEP\n*STATIC\n*BOUNDARY, OP=NEW\n3, ENCASTRE\n2, 4, 4, 0.01\n*CLOAD\n4, 2, 1.0\n*END STEP\n"
    );
    let InpModel { model, warnings } = parse(&text);
    let supports: Vec<(usize, DofSet)> = model.supports.iter().map(|s| (s.node, s.dofs)).collect();
    let d = |dofs: &[Dof]| dofs.iter().copied().collect::<DofSet>();
    assert_eq!(
        supports,
        vec![
            (0, d(&[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Ry])),
            (3, d(&[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Ry, Dof::Rz])),
            (1, d(&[Dof::Ry, Dof::Rx])),
            (2, DofSet::ALL),
        ]
    );
    assert_eq!(model.mesh.node_sets["SOME"], vec![0, 3, 1]);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("prescribed value 0.01 treated as zero")),
        "{warnings:?}"
    );
    assert!(warnings.iter().any(|w| w.contains("*CLOAD is not read")));
}

#[test]
fn sets_with_generate_and_set_names() {
    let mut text = String::from("*NODE\n");
    for i in 1..=9 {
        text += &format!("{i}, {}, 0, 0\n", i as f64);
    }
    text += "*ELEMENT, TYPE=B31\n";
    for i in 1..=8 {
        text += &format!("{i}, {i}, {}\n", i + 1);
    }
    text += "*ELSET, ELSET=ODD, GENERATE\n1, 7, 2\n*ELSET, ELSET=EVEN, GENERATE\n2, 8, 2\n*ELSET, ELSET=ALL\nODD, EVEN\n";
    text += "*NSET, NSET=N, GENERATE\n1, 9, 4\n*NSET, NSET=N\n2,\n";
    text += MATERIAL;
    text += "*BEAM SECTION, ELSET=ODD, MATERIAL=STEEL, SECTION=CIRC\n0.01\n0, 1, 0\n";
    text += "*BEAM SECTION, ELSET=EVEN, MATERIAL=STEEL, SECTION=CIRC\n0.02\n0, 1, 0\n";
    let mesh = parse(&text).model.mesh;
    assert_eq!(mesh.node_sets["N"], vec![0, 4, 8, 1]);
    for e in &mesh.elements {
        let expected = if e.label % 2 == 1 { 0 } else { 1 };
        assert_eq!(e.kind, ElementKind::Beam { section: expected });
    }
    // A section for a set whose elements already have one.
    let twice = text + "*BEAM SECTION, ELSET=ALL, MATERIAL=STEEL, SECTION=CIRC\n0.03\n0, 1, 0\n";
    assert!(
        error(&twice)
            .contains("*BEAM SECTION: element 1 already has one (*BEAM SECTION at bad.inp:"),
        "{}",
        error(&twice)
    );
}

#[test]
fn errors_name_file_and_line() {
    let head = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n"; // lines 1-3
                                                  // Unknown element type: the keyword line.
    let e = error(&format!(
        "{head}*ELEMENT, TYPE=C3D8R, ELSET=E\n1, 1, 2, 1, 2, 1, 2, 1, 2\n"
    ));
    assert_eq!(
        e,
        "bad.inp:4: *ELEMENT: unknown element type C3D8R (C3D8R's hourglass control is not supported: use C3D8I, incompatible modes, or C3D8); \
         flexmb reads B31, B31H, B33, B33H, S3, S3R, S4, S4R, C3D4, C3D10, C3D6, C3D15, C3D8, C3D8I, C3D20, C3D20R, MASS, ROTARYI, DCOUP3D"
    );
    // A node that is not defined: the element's line.
    let e = error(&format!(
        "{head}*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n2, 2, 3\n{MATERIAL}*BEAM SECTION, ELSET=E, MATERIAL=STEEL, SECTION=CIRC\n0.01\n0,1,0\n"
    ));
    assert_eq!(e, "bad.inp:6: element 2: node 3 is not defined");
    // Non-numeric values.
    let e = error("*NODE\n1, 0, 0, 0\n2, 1, O.5, 0\n");
    assert_eq!(
        e,
        "bad.inp:3: *NODE: expected a number for y (field 3), got 'O.5'"
    );
    let e = error(&format!("{head}*MATERIAL, NAME=M\n*ELASTIC\n210e9, abc\n"));
    assert_eq!(
        e,
        "bad.inp:6: *ELASTIC: expected a number for Poisson's ratio (field 2), got 'abc'"
    );
    let e = error(&format!("{head}*ELEMENT, TYPE=B31\n1, 1, x2\n"));
    assert_eq!(
        e,
        "bad.inp:5: *ELEMENT: expected a positive integer for a node label (field 3), got 'x2'"
    );
    // An element without a section.
    let e = error(&format!("{head}*ELEMENT, TYPE=S3, ELSET=E\n1, 1, 2, 1\n"));
    assert!(
        e.starts_with("bad.inp:5: element 1: repeated nodes")
            || e.starts_with("bad.inp:5: element 1 (S3) has no section"),
        "{e}"
    );
    let e = error(&format!("{head}*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n"));
    assert_eq!(e, "bad.inp:5: element 1 (B31) has no section: no *BEAM SECTION or *BEAM GENERAL SECTION names an element set that contains it");
    // Wrong node count, duplicate node, unknown set, missing material data, beam along default n1.
    let e = error(&format!("{head}*ELEMENT, TYPE=S4\n1, 1, 2, 1\n"));
    assert_eq!(e, "bad.inp:5: *ELEMENT: element 1 has 3 nodes; a S4 has 4");
    assert_eq!(
        error("*NODE\n1, 0,0,0\n\n1, 1,0,0\n"),
        "bad.inp:4: *NODE: node 1 is defined twice (first at bad.inp:2)"
    );
    let e = error(&format!("{head}*BOUNDARY\nFIX, 1, 6\n"));
    assert_eq!(e, "bad.inp:5: *BOUNDARY: node set FIX is not defined");
    let e = error(&format!(
        "{head}*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n*MATERIAL, NAME=M\n*ELASTIC\n1e9, 0.3\n*BEAM SECTION, ELSET=E, MATERIAL=M, SECTION=CIRC\n0.1\n"
    ));
    assert_eq!(
        e,
        "bad.inp:9: *BEAM SECTION: material M (line 6) has no *DENSITY"
    );
    let e = error(&format!(
        "*NODE\n1, 0, 0, 0\n2, 0, 0, 1\n*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n{MATERIAL}*BEAM SECTION, ELSET=E, MATERIAL=STEEL, SECTION=CIRC\n0.1\n"
    ));
    assert!(e.starts_with("bad.inp:5: element 1 lies along its section's first direction n1 (the default (0, 0, -1)"), "{e}");
    let e = error("*NODE\n1, 0, 0, 0\n*BOUNDARY\n1, 1, 9x\n");
    assert_eq!(e, "bad.inp:4: *BOUNDARY: expected a positive integer for the last degree of freedom (field 3), got '9x'");
    let e = error("*NSET, NSET=A\n1, B\n");
    assert_eq!(
        e,
        "bad.inp:2: *NSET: unknown node set B (sets must be defined before they are used)"
    );
    let e = error("*ELEMENT\n1, 1\n");
    assert_eq!(e, "bad.inp:1: *ELEMENT: missing parameter TYPE=…");
}

#[test]
fn never_panics_on_garbage() {
    let decks = [
        "",
        "*",
        "**\n***\n*,,,=\n,\n",
        "*NODE\n,\n",
        "*NODE\n1\n",
        "*ELEMENT, TYPE=B31\n1,\n",
        "*ELEMENT, TYPE=S4\n1, 1, 2,\n",
        "*ELEMENT, TYPE=MASS\n\n1, 99999999999999999999\n",
        "*NSET, NSET=A, GENERATE\n5, 1\n",
        "*NSET, NSET=A, GENERATE\n1, 18446744073709551615, 1\n",
        "*ELSET, ELSET=A, GENERATE\n1\n",
        "*BOUNDARY\n,\n",
        "*BOUNDARY\n1\n",
        "*BOUNDARY\n1, 7, 3\n",
        "*BEAM SECTION, ELSET=E, SECTION=BOX\n1, 2\n",
        "*BEAM GENERAL SECTION, ELSET=E\n",
        "*ELASTIC\n1, 0.3\n",
        "*MATERIAL\n",
        "*SHELL SECTION, ELSET=E, MATERIAL=M\n-1\n",
        "*ROTARY INERTIA, ELSET=E\n1, 2, 3, 0, 0, 1\n",
        "*INCLUDE, INPUT=/nonexistent/file.inp\n",
        "*INCLUDE\n",
    ];
    for deck in decks {
        let _ = parse_inp(deck, "garbage.inp");
    }
    assert!(parse_inp("", "empty.inp").unwrap().warnings[0].contains("no elements"));
}

#[test]
fn orientation_nodes_and_degenerate_quads() {
    let text = format!(
        "*NODE\n1, 0,0,0\n2, 1,0,0\n3, 2,0,0\n9, 0,0,5\n10, 1,1,0\n11, 0,1,0\n\
         *ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2, 9\n2, 2, 3, 9\n3, 2, 3\n\
         *ELEMENT, TYPE=S4R, ELSET=S\n4, 1, 2, 10, 10\n5, 1, 2, 10, 11\n{MATERIAL}\
         *BEAM SECTION, ELSET=E, MATERIAL=STEEL, SECTION=RECT\n0.02, 0.01\n0, 1, 0\n\
         *SHELL SECTION, ELSET=S, MATERIAL=STEEL\n0.001\n"
    );
    let InpModel { model, warnings } = parse(&text);
    let mesh = &model.mesh;
    let sections: Vec<_> = mesh.elements.iter().map(|e| e.kind).collect();
    // Elements 1 and 2: n1 from their first node to node 9 (two distinct directions); element 3 the section's.
    assert_eq!(mesh.beam_sections.len(), 3);
    assert_eq!(sections[0], ElementKind::Beam { section: 1 });
    assert_eq!(sections[1], ElementKind::Beam { section: 2 });
    assert_eq!(sections[2], ElementKind::Beam { section: 0 });
    assert_eq!(
        mesh.beam_sections[1].orientation,
        Vector3::new(0.0, 0.0, 5.0)
    );
    assert_eq!(
        mesh.beam_sections[2].orientation,
        Vector3::new(-1.0, 0.0, 5.0)
    );
    assert_eq!(mesh.elements[0].nodes.len(), 2);
    assert_eq!(mesh.elements[3].nodes, vec![0, 1, 4]);
    assert_eq!(mesh.elements[4].nodes.len(), 4);
    assert!(warnings
        .iter()
        .any(|w| w.contains("1 quadrilateral shell(s) with a repeated node read as triangles")));
}

#[test]
fn include_relative_to_the_including_file() {
    let dir = std::env::temp_dir().join(format!("flexmb-inp-include-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("mesh")).unwrap();
    std::fs::write(
        dir.join("mesh/nodes.inp"),
        "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*INCLUDE, INPUT=elements.inp\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("mesh/elements.inp"),
        "*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n2, 2, 7\n",
    )
    .unwrap();
    let main = format!(
        "*HEADING\n*INCLUDE, INPUT=mesh/nodes.inp\n{MATERIAL}*BEAM SECTION, ELSET=E, MATERIAL=STEEL, SECTION=CIRC\n0.01\n0,1,0\n"
    );
    std::fs::write(dir.join("main.inp"), &main).unwrap();
    let e = read_inp(&dir.join("main.inp")).unwrap_err();
    // The error is reported in the included file.
    let elements = dir.join("mesh").join("elements.inp");
    assert_eq!(
        e.to_string(),
        format!("{}:3: element 2: node 7 is not defined", elements.display())
    );
    assert_eq!(e.line(), Some(3));
    std::fs::write(&elements, "*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n").unwrap();
    let model = read_inp(&dir.join("main.inp")).unwrap().model;
    assert_eq!((model.mesh.nodes.len(), model.mesh.elements.len()), (2, 1));
    let missing = read_inp(&dir.join("nothing.inp")).unwrap_err();
    assert!(matches!(missing, InpError::Read { .. }));
    std::fs::write(dir.join("self.inp"), "*INCLUDE, INPUT=self.inp\n").unwrap();
    assert!(read_inp(&dir.join("self.inp"))
        .unwrap_err()
        .to_string()
        .contains("nested includes"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn devices_and_directories_are_refused_as_decks_and_includes() {
    // /dev/zero would be read until memory runs out; a directory cannot be read at all.
    let dir = std::env::temp_dir().join(format!("flexmb-inp-device-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let e = read_inp(&dir).unwrap_err().to_string();
    assert_eq!(e, format!("{}: cannot read: it is a directory, not a regular file", dir.display()));
    #[cfg(unix)]
    {
        let e = read_inp(Path::new("/dev/zero")).unwrap_err().to_string();
        assert_eq!(e, "/dev/zero: cannot read: it is a character device, not a regular file");
        let e = parse_inp("*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=/dev/zero\n", "deck.inp").unwrap_err();
        assert_eq!(
            e.to_string(),
            "deck.inp:3: *INCLUDE: cannot read /dev/zero: it is a character device, not a regular file"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn absurd_magnitudes_are_named_at_their_keyword_and_line() {
    // Finite but absurd: once accepted and reported later as a mechanism or a massless mode.
    let beam = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n";
    let section = "*BEAM SECTION, ELSET=E, MATERIAL=STEEL, SECTION=RECT\n0.02, 0.01\n0, 1, 0\n";
    let deck = format!("{beam}{MATERIAL}{section}");
    parse(&deck);
    let e = error(&deck.replace("210e9, 0.3", "1e308, 0.3"));
    assert_eq!(
        e,
        "bad.inp:8: *ELASTIC: Young's modulus E (field 1): 1e308 Pa is outside the range of an elastic modulus, \
         |x| ≤ 1e15 Pa"
    );
    let e = error(&deck.replace("7850", "1e300"));
    assert_eq!(
        e,
        "bad.inp:10: *DENSITY: the density (field 1): 1e300 kg/m³ is outside the range of a density, |x| ≤ 1e8 kg/m³"
    );
    let e = error(&deck.replace("2, 1, 0, 0", "2, 1, 1e300, 0"));
    assert_eq!(e, "bad.inp:3: *NODE: node 2: y (field 3): 1e300 m is outside the range of a length, |x| ≤ 1e12 m");
    let e = error(&deck.replace("0.02, 0.01", "0.02, 1e13"));
    assert!(e.starts_with("bad.inp:12: *BEAM SECTION: b (field 2): 1e13 m is outside the range of a length"), "{e}");
    let general = "*BEAM GENERAL SECTION, ELSET=E, DENSITY=1e300\n1e-4, 1e-8, 0, 1e-8, 2e-8\n0, 1, 0\n210e9, 80e9\n";
    let e = error(&format!("{beam}{general}"));
    assert!(e.starts_with("bad.inp:6: *BEAM GENERAL SECTION: DENSITY=1e300: 1e300 kg/m³ is outside the range"), "{e}");
    let e = error(&format!("{beam}{}", general.replace("DENSITY=1e300", "DENSITY=7850").replace("210e9", "1e308")));
    assert!(e.starts_with("bad.inp:9: *BEAM GENERAL SECTION: Young's modulus E (field 1): 1e308 Pa"), "{e}");
    let shell = "*SHELL SECTION, ELSET=S, MATERIAL=STEEL\n1e20\n";
    let e = error(&format!("{MATERIAL}{shell}"));
    assert!(e.contains("*SHELL SECTION: the thickness (field 1): 1e20 m is outside the range of a length"), "{e}");
    let mass = "*ELEMENT, TYPE=MASS, ELSET=M\n3, 1\n*MASS, ELSET=M\n1e300\n";
    let e = error(&format!("{beam}{mass}"));
    assert!(e.contains("*MASS: the mass (field 1): 1e300 kg is outside the range of a mass, |x| ≤ 1e12 kg"), "{e}");
}
