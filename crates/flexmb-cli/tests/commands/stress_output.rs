//! Stresses in a run as a user gets them: a solid cantilever (C3D8I bricks, its root face coupled
//! rigidly to a reference node fixed to ground) under a static tip force, its FE model reduced with
//! the static correction mode of that force and `stresses = true` asked of the flexible body, started
//! at its static equilibrium: the hot spot the run reports is the root's bending stress `M c / I`, at a
//! root node of the top or bottom fibre, and the ParaView series carries `von_mises` and `stress` on
//! the deformed mesh.

use std::fmt::Write as _;

use crate::program::{scratch, succeed};
use crate::vtk_output::{point_data, points, read_pvd, read_vtu};

const LENGTH: f64 = 1.0;
const DEPTH: f64 = 0.1;
const CELLS: [usize; 3] = [20, 2, 2];

/// A deck of C3D8I bricks `LENGTH × DEPTH × DEPTH` (ν = 0: the rigid root face restrains no lateral
/// contraction) with reference node 1000 at the centre of the root face, coupled to it and clamped;
/// node 999 is the centre of the tip face (the label the load refers to).
fn cantilever_deck() -> String {
    let [nx, ny, nz] = CELLS;
    let label = |i: usize, j: usize, k: usize| 1 + i + (nx + 1) * (j + (ny + 1) * k);
    let mut s = String::from("*NODE\n");
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let (x, y, z) = (LENGTH * i as f64 / nx as f64, DEPTH * j as f64 / ny as f64, DEPTH * k as f64 / nz as f64);
                let _ = writeln!(s, "{}, {x}, {y}, {z}", label(i, j, k));
            }
        }
    }
    let _ = writeln!(s, "1000, 0, {}, {}", DEPTH / 2.0, DEPTH / 2.0);
    s += "*ELEMENT, TYPE=C3D8I, ELSET=BAR\n";
    let mut e = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                e += 1;
                let c = [(i, j, k), (i + 1, j, k), (i + 1, j + 1, k), (i, j + 1, k), (i, j, k + 1), (i + 1, j, k + 1), (i + 1, j + 1, k + 1), (i, j + 1, k + 1)];
                let nodes: Vec<String> = c.iter().map(|&(a, b, d)| label(a, b, d).to_string()).collect();
                let _ = writeln!(s, "{e}, {}", nodes.join(", "));
            }
        }
    }
    s += "*NSET, NSET=ROOT\n";
    for k in 0..=nz {
        for j in 0..=ny {
            let _ = writeln!(s, "{},", label(0, j, k));
        }
    }
    let _ = writeln!(s, "*NSET, NSET=TIP\n{}", label(nx, ny / 2, nz / 2));
    s += "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0\n*DENSITY\n7850\n*SOLID SECTION, ELSET=BAR, MATERIAL=STEEL\n";
    s += "*KINEMATIC COUPLING, REF NODE=1000\nROOT, 1, 3\n*BOUNDARY\n1000, 1, 6\n";
    s
}

#[test]
fn a_run_reports_the_root_bending_stress_as_its_hot_spot_and_writes_it_for_paraview() {
    let dir = scratch("stress-output");
    std::fs::write(dir.join("bar.inp"), cantilever_deck()).unwrap();
    let tip = 1 + CELLS[0] + (CELLS[0] + 1) * (CELLS[1] / 2 + (CELLS[1] + 1) * (CELLS[2] / 2));
    let fe = format!(
        "[fe_model]\nmesh = \"bar.inp\"\n\n[modes]\nset = \"4N1S\"\n\n[[static_load]]\nname = \"tip_y\"\nat = {tip}\nforce = [0, 1, 0]\n"
    );
    std::fs::write(dir.join("bar.toml"), fe).unwrap();
    let force = 1000.0;
    let model = format!(
        r#"[model]
gravity = [0, 0, 0]

[simulation]
t_end = 0.002
output_step = 0.001
start = "equilibrium"

[[flexible_body]]
name = "bar"
fe_model = "bar.toml"
stresses = true

[[marker]]
name = "wall"
body = "ground"
origin = [0, {half}, {half}]

[[marker]]
name = "root"
body = "bar"
node = 1000

[[marker]]
name = "tip"
body = "bar"
node = {tip}

[[joint]]
name = "clamp"
type = "fixed"
i = "wall"
j = "root"

[[force]]
name = "load"
type = "force"
marker = "tip"
components = [0, {force}, 0]
"#,
        half = DEPTH / 2.0
    );
    let model_path = dir.join("bar_run.toml");
    std::fs::write(&model_path, model).unwrap();
    let out = dir.join("out");
    let vtk = dir.join("vtk");
    let stdout = succeed(&["run", model_path.to_str().unwrap(), "--out", out.to_str().unwrap(), "--vtk", vtk.to_str().unwrap()]);
    let bending = force * LENGTH * (DEPTH / 2.0) / (DEPTH.powi(4) / 12.0);
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("bar_run.json")).unwrap()).unwrap();
    let hot = &summary["stress_hot_spots"][0];
    println!("{stdout}\nhot spot {hot}; M c / I = {bending:.5e} Pa");
    assert!(stdout.contains("stress hot spot of bar: von Mises"), "{stdout}");
    assert_eq!(hot["body"], "bar");
    assert_eq!(hot["place"], "solid");
    let von_mises = hot["von_mises"].as_f64().unwrap();
    assert!((von_mises / bending - 1.0).abs() < 0.05, "hot spot {von_mises} against M c / I = {bending}");
    // At a node of the root's top or bottom fibre (labels of i = 0, j = 0 or 2).
    let node = hot["node"].as_u64().unwrap() as usize - 1;
    let (i, j) = (node % (CELLS[0] + 1), (node / (CELLS[0] + 1)) % (CELLS[1] + 1));
    assert!(i == 0 && (j == 0 || j == CELLS[1]), "hot spot at node {}", node + 1);

    let entries = read_pvd(&vtk.join("bar_run.pvd"));
    let last = entries.iter().rev().find(|e| e.name == "bar").unwrap();
    let grid = read_vtu(&vtk.join(&last.file));
    let von_mises_field = point_data(&grid, "von_mises");
    let stress = point_data(&grid, "stress");
    assert_eq!(stress.len(), 9 * von_mises_field.len());
    let largest = von_mises_field.iter().copied().fold(0.0, f64::max);
    assert!((largest / von_mises - 1.0).abs() < 1e-9, "the series' largest von Mises {largest}, the hot spot's {von_mises}");
    // σxx at the root's top fibre (compression) and bottom fibre (tension), the tensor row by row.
    for (p, x) in points(&grid).iter().enumerate() {
        if x[0].abs() < 1e-6 && (x[1] - DEPTH / 2.0).abs() > 0.99 * DEPTH / 2.0 {
            let expected = if x[1] > DEPTH / 2.0 { -bending } else { bending };
            assert!((stress[9 * p] / expected - 1.0).abs() < 0.05, "σxx {} at {x:?}, expected {expected}", stress[9 * p]);
        }
    }
}

/// `stresses = true` on a body read from a flexible-body file written without them is an error at
/// that key that says how to write them; with them (`flexmb modes --stresses`) the run follows them.
#[test]
fn stresses_of_a_body_file_need_flexmb_modes_stresses() {
    let dir = scratch("stress-body-file");
    let (without, with) = (dir.join("link.json"), dir.join("link_stresses.json"));
    succeed(&["modes", "models/fe/solid_link.toml", "--out", without.to_str().unwrap()]);
    let stdout = succeed(&["modes", "models/fe/solid_link.toml", "--stresses", "--out", with.to_str().unwrap()]);
    assert!(stdout.contains("modal stresses: 203 stress points × 4 modes"), "{stdout}");
    let model = |body: &std::path::Path| {
        format!(
            "[model]\ngravity = [0, -9.81, 0]\n[simulation]\nt_end = 0.004\noutput_step = 0.001\n\n[[flexible_body]]\nname = \"link\"\nbody_file = \"{}\"\nstresses = true\n",
            body.display()
        )
    };
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, model(&without)).unwrap();
    let error = crate::program::fail(&["run", bad.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap()]);
    assert!(error.contains("flexible_body[0].stresses") && error.contains("flexmb modes --stresses"), "{error}");
    let good = dir.join("good.toml");
    std::fs::write(&good, model(&with)).unwrap();
    let stdout = succeed(&["run", good.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap()]);
    assert!(stdout.contains("stress hot spot of link: von Mises"), "{stdout}");
    // Falling freely, the link is not stressed: gravity and the frame's acceleration balance in every
    // mass point (to round-off: the hanging link's static stress is of order 1e5 Pa).
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("out/good.json")).unwrap()).unwrap();
    let von_mises = summary["stress_hot_spots"][0]["von_mises"].as_f64().unwrap();
    assert!(von_mises < 1.0, "{von_mises} Pa");
}
