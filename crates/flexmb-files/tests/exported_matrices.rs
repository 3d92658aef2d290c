//! Flexible bodies from exported stiffness and mass matrices (`[matrices]` of FE model files).
//!
//! - **CalculiX**: a steel block 1 m × 0.1 m × 0.06 m of 4 × 2 × 2 C3D20 bricks (consistent mass)
//!   exported free-free by `ccx` (`*FREQUENCY, SOLVER=MATRIXSTORAGE`), read with its deck's nodes and
//!   clamped at x = 0 by `[[support]]`: its first ten frequencies agree with those ccx computes on the
//!   clamped deck and with flexmb's own reduction of that deck (1e-6), its mode shapes with flexmb's
//!   own, and its reduced body (mass, inertia, invariants of two static correction modes) with the one
//!   flexmb reduces from the deck. Skipped, with a message, when `ccx` is not installed.
//! - **Matrix Market, Ansys and Abaqus formats**: flexmb's own stiffness and mass of a C3D8I block
//!   written as Matrix Market files with a `node.dof` row file, as Ansys files (`*EXPORT` MMF, mapping
//!   vector, node list; the rows in a shuffled node order) and as Abaqus files (`node, dof, node, dof,
//!   value`), reduce to the deck's own frequencies (1e-9) and mode shapes.
//! - A matrix file given to `flexmb modes` and an unknown `format` are errors that list the formats.

#[path = "../../flexmb-fem/tests/support/calculix.rs"]
mod calculix;
#[path = "../../flexmb-fem/tests/support/solid_block.rs"]
mod solid_block;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use flexmb_fem::assembly::assemble;
use flexmb_fem::inp::parse_inp;
use flexmb_fem::modes::{vibration_modes, EigenSettings, VibrationModes};
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use flexmb_fem::{FeModel, MassModel};
use flexmb_files::fe_model_file::load_fe_model;
use solid_block::SolidBlock;

fn work_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("exported-matrices-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The block of the CalculiX check: flat (0.1 × 0.06), so that no two of its frequencies coincide.
fn flat_block(element: &'static str, nx: usize, clamped: bool) -> SolidBlock {
    SolidBlock { lz: 0.06, clamped, ..SolidBlock::cantilever(element, nx) }
}

/// The FE model file of exported matrices, clamped at the deck's node set `ROOT`, with two static
/// loads at the tip corner node `tip`.
fn fe_model_text(matrices: &str, tip: u64) -> String {
    format!(
        "[fe_model]\nname = \"block\"\n\n[matrices]\n{matrices}\n[[support]]\nat = \"ROOT\"\ndofs = \"translations\"\n\n\
         [[static_load]]\nname = \"tip_y\"\nat = {tip}\nforce = [0, 1, 0]\n\n[[static_load]]\nname = \"tip_z\"\nat = {tip}\nforce = [0, 0, 1]\n"
    )
}

/// The deck's model with the consistent mass, its root clamped, and the same static loads.
fn deck_model(deck: &str, tip: u64) -> FeModel {
    let mut model = parse_inp(deck, "block.inp").unwrap().model;
    model.options.mass = Some(MassModel::Consistent);
    let root = model.mesh.node_sets["ROOT"].clone();
    model.supports = root.iter().map(|&node| flexmb_fem::Support { node, dofs: flexmb_fem::DofSet::TRANSLATIONS }).collect();
    let node = model.mesh.node_index(tip).unwrap();
    for (name, direction) in [("tip_y", nalgebra::Vector3::y()), ("tip_z", nalgebra::Vector3::z())] {
        model.static_loads.push(flexmb_fem::StaticLoad { name: name.into(), node, kind: flexmb_fem::StaticLoadKind::Force(direction) });
    }
    model
}

/// The label of the deck's node at the corner (lx, 0, 0).
fn tip_corner(deck: &str) -> u64 {
    let model = parse_inp(deck, "block.inp").unwrap().model;
    let lx = model.mesh.nodes.iter().map(|n| n.position.x).fold(0.0, f64::max);
    model.mesh.nodes.iter().find(|n| n.position.x == lx && n.position.y == 0.0 && n.position.z == 0.0).unwrap().label
}

/// The largest relative difference of two frequency lists.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs() / y).fold(0.0, f64::max)
}

/// The largest difference of the mode shapes of `a` and `b` (each mode's nodal translations, by node
/// label, the sign of `b` matched), relative to the mode's largest translation.
fn largest_shape_difference(a: (&FeModel, &VibrationModes), b: (&FeModel, &VibrationModes)) -> f64 {
    let nodal = |(model, modes): (&FeModel, &VibrationModes), j: usize| -> std::collections::BTreeMap<u64, [f64; 3]> {
        let assembled = assemble(model).unwrap();
        let v = assembled.dofs.expand(&(0..modes.shapes.nrows()).map(|i| modes.shapes[(i, j)]).collect::<Vec<_>>());
        model.mesh.nodes.iter().enumerate().map(|(i, n)| (n.label, [v[6 * i], v[6 * i + 1], v[6 * i + 2]])).collect()
    };
    let mut largest = 0.0_f64;
    for j in 0..a.1.frequencies_hz.len() {
        let (x, y) = (nodal(a, j), nodal(b, j));
        let dot: f64 = x.iter().map(|(l, u)| (0..3).map(|d| u[d] * y[l][d]).sum::<f64>()).sum();
        let sign = dot.signum();
        let scale = y.values().flat_map(|u| u.iter().map(|c| c.abs())).fold(0.0, f64::max);
        let y = &y;
        let difference = x.iter().flat_map(|(l, u)| (0..3).map(move |d| (u[d] - sign * y[l][d]).abs())).fold(0.0, f64::max);
        largest = largest.max(difference / scale);
    }
    largest
}

#[test]
fn calculix_matrices_reduce_to_ccx_and_to_the_deck() {
    if calculix::ccx_path().is_none() {
        println!("skipped: ccx not found (install Debian package calculix-ccx)");
        return;
    }
    let dir = work_dir("calculix");
    // ccx's frequencies of the clamped block.
    let clamped = flat_block("C3D20", 4, true);
    let theirs = calculix::natural_frequencies(&clamped.deck(), &dir.join("clamped")).unwrap();
    // ccx's matrices of the free block.
    let free = flat_block("C3D20", 4, false);
    let export = free.deck().replace("*FREQUENCY\n", "*FREQUENCY, SOLVER=MATRIXSTORAGE\n");
    let export_dir = dir.join("export");
    calculix::run_deck(&export, &export_dir).unwrap();
    let deck = clamped.deck();
    let tip = tip_corner(&deck);
    let own = deck_model(&deck, tip);
    let text = fe_model_text(
        "format = \"calculix\"\nstiffness = \"export/job.sti\"\nmass = \"export/job.mas\"\ndofs = \"export/job.dof\"\nnodes = \"export/job.inp\"\n",
        tip,
    );
    std::fs::write(dir.join("block.toml"), text).unwrap();
    let imported = load_fe_model(&dir.join("block.toml")).unwrap().model;

    let settings = EigenSettings::default();
    let ours = vibration_modes(&imported, clamped.modes, &settings).unwrap();
    let deck_modes = vibration_modes(&own, clamped.modes, &settings).unwrap();
    println!("mode, imported [Hz], ccx [Hz], flexmb from the deck [Hz]");
    for k in 0..clamped.modes {
        println!("  {:2}  {:14.6}  {:14.6}  {:14.6}", k + 1, ours.frequencies_hz[k], theirs[k], deck_modes.frequencies_hz[k]);
    }
    let against_ccx = largest_difference(&ours.frequencies_hz, &theirs);
    let against_deck = largest_difference(&ours.frequencies_hz, &deck_modes.frequencies_hz);
    let shapes = largest_shape_difference((&imported, &ours), (&own, &deck_modes));
    println!("largest relative differences: against ccx {against_ccx:.1e}, against the deck {against_deck:.1e}, mode shapes {shapes:.1e}");
    assert!(against_ccx < 1e-6, "against ccx: {against_ccx:.2e}");
    assert!(against_deck < 1e-6, "against the deck: {against_deck:.2e}");
    assert!(shapes < 1e-6, "mode shapes: {shapes:.2e}");

    // The reduced bodies: mass properties and the invariants of the static correction modes (their
    // sign is fixed by the load), consistent-mass integrals from the deck, mass points from the matrix.
    let reduction = ReductionSettings { mode_set: "2S".parse().unwrap(), basis: Basis::Raw, eigen: settings };
    let a = reduce(&imported, "block", &reduction).unwrap().body;
    let b = reduce(&own, "block", &reduction).unwrap().body;
    let relative = |x: f64, y: f64, scale: f64| (x - y).abs() / scale;
    let (ia, ib) = (&a.invariants, &b.invariants);
    let mut worst = relative(ia.mass, ib.mass, ib.mass);
    worst = worst.max((ia.c1 - ib.c1).norm() / (ib.mass * 1.0));
    worst = worst.max((ia.c3 - ib.c3).norm() / ib.c3.norm());
    worst = worst.max((&ia.c2 - &ib.c2).norm() / ib.c2.norm());
    worst = worst.max((&ia.c6 - &ib.c6).norm() / ib.c6.norm());
    worst = worst.max((&ia.c9 - &ib.c9).norm() / ib.c9.norm());
    worst = worst.max((&ia.c8 - &ib.c8).norm() / ib.c8.norm().max(ib.c9.norm().sqrt() * ib.mass.sqrt()));
    for j in 0..2 {
        worst = worst.max((ia.c4[j] - ib.c4[j]).norm() / ib.c4[j].norm());
        worst = worst.max((&ia.c7[j] - &ib.c7[j]).norm() / ib.c7[j].norm());
        for k in 0..2 {
            worst = worst.max((ia.c5[j][k] - ib.c5[j][k]).norm() / ib.c5[j][k].norm());
        }
    }
    worst = worst.max((a.mass_properties.inertia - b.mass_properties.inertia).norm() / b.mass_properties.inertia.norm());
    println!("reduced body (2S, raw): largest relative difference of the mass, inertia and invariants {worst:.1e}");
    assert!(worst < 1e-6, "invariants: {worst:.2e}");
}

/// flexmb's own stiffness and mass of `model` (no supports) over every nodal dof: `(node label, dof)`
/// of each row and the upper triangles.
#[allow(clippy::type_complexity)]
fn own_matrices(model: &FeModel) -> (Vec<(u64, usize)>, Vec<(usize, usize, f64)>, Vec<(usize, usize, f64)>) {
    let mut free = model.clone();
    free.supports.clear();
    free.static_loads.clear();
    let assembled = assemble(&free).unwrap();
    let n = assembled.dofs.n_free();
    let rows: Vec<(u64, usize)> = (0..n)
        .map(|e| {
            let (node, dof) = assembled.dofs.node_dof(e).unwrap();
            (model.mesh.nodes[node].label, dof.index())
        })
        .collect();
    let upper = |m: &faer::sparse::SparseColMat<usize, f64>| {
        let mut entries = Vec::new();
        for j in 0..n {
            let range = m.col_range(j);
            for (&i, &v) in m.row_idx()[range.clone()].iter().zip(&m.val()[range]) {
                if i <= j && v != 0.0 {
                    entries.push((i, j, v));
                }
            }
        }
        entries
    };
    (rows, upper(&assembled.stiffness), upper(&assembled.mass))
}

/// Writes the block's own matrices in the Matrix Market, Ansys and Abaqus formats (the rows in a shuffled node
/// order) and returns the `[matrices]` tables.
fn write_formats(model: &FeModel, dir: &Path) -> [String; 3] {
    let (rows, k, m) = own_matrices(model);
    assert!(rows.iter().all(|&(_, d)| d < 3), "translations only");
    // Nodes in a shuffled order: equation block b of the files is the node order[b].
    let labels: Vec<u64> = model.mesh.nodes.iter().map(|n| n.label).collect();
    let mut order: Vec<u64> = labels.iter().rev().copied().collect();
    order.rotate_left(labels.len() / 3);
    let block_of = |label: u64| order.iter().position(|&l| l == label).unwrap();
    let file_row = |r: usize| 3 * block_of(rows[r].0) + rows[r].1;
    let n = rows.len();
    // Ansys: MMF of the lower triangle (file rows), the mapping vector, the node list.
    for (name, entries) in [("k.mmf", &k), ("m.mmf", &m)] {
        let mut text = format!("%%MatrixMarket matrix coordinate real symmetric\n%written as Ansys *EXPORT does\n{n} {n} {}\n", entries.len());
        for &(i, j, v) in entries {
            let (a, b) = (file_row(i), file_row(j));
            let _ = writeln!(text, "{} {} {v:.17e}", a.max(b) + 1, a.min(b) + 1);
        }
        std::fs::write(dir.join(name), text).unwrap();
    }
    let mut mapping = format!("%%MatrixMarket matrix array integer general\n{} 1\n", order.len());
    for label in &order {
        let _ = writeln!(mapping, "{label}");
    }
    std::fs::write(dir.join("mapping.txt"), mapping).unwrap();
    let mut nodes = "Node Number\tX Location (m)\tY Location (m)\tZ Location (m)\n".to_string();
    for node in model.mesh.nodes.iter().rev() {
        let p = node.position;
        let _ = writeln!(nodes, "{}\t{}\t{}\t{}", node.label, p.x, p.y, p.z);
    }
    std::fs::write(dir.join("nodes.txt"), nodes).unwrap();
    // Abaqus: node, dof, node, dof, value (dofs from 1), the lower triangle in its own order.
    for (name, entries) in [("k.mtx", &k), ("m.mtx", &m)] {
        let mut text = "** written as Abaqus *MATRIX OUTPUT, FORMAT=MATRIX INPUT does\n".to_string();
        for &(i, j, v) in entries {
            let ((la, da), (lb, db)) = (rows[j], rows[i]);
            let _ = writeln!(text, "{la},{},{lb},{},{v:.17e}", da + 1, db + 1);
        }
        std::fs::write(dir.join(name), text).unwrap();
    }
    // Matrix Market: the upper triangle in the deck's row order, the `node.dof` row file.
    for (name, entries) in [("k.mm", &k), ("m.mm", &m)] {
        let mut text = format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {}\n", entries.len());
        for &(i, j, v) in entries {
            let _ = writeln!(text, "{} {} {v:.17e}", i + 1, j + 1);
        }
        std::fs::write(dir.join(name), text).unwrap();
    }
    let dofs: String = rows.iter().map(|(label, d)| format!("{label}.{}\n", d + 1)).collect();
    std::fs::write(dir.join("rows.dof"), dofs).unwrap();
    [
        "format = \"matrix-market\"\nstiffness = \"k.mm\"\nmass = \"m.mm\"\ndofs = \"rows.dof\"\nnodes = \"block.inp\"\n".to_string(),
        "format = \"ansys\"\nstiffness = \"k.mmf\"\nmass = \"m.mmf\"\ndofs = \"mapping.txt\"\nnodes = \"nodes.txt\"\n".to_string(),
        "format = \"abaqus\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\nnodes = \"block.inp\"\n".to_string(),
    ]
}

#[test]
fn matrix_market_ansys_and_abaqus_files_of_known_matrices_reduce_to_the_same_modes() {
    let dir = work_dir("formats");
    let block = flat_block("C3D8I", 6, true);
    let deck = block.deck();
    std::fs::write(dir.join("block.inp"), &deck).unwrap();
    let tip = tip_corner(&deck);
    let own = deck_model(&deck, tip);
    let settings = EigenSettings::default();
    let expected = vibration_modes(&own, 8, &settings).unwrap();
    let [matrix_market, ansys, abaqus] = write_formats(&own, &dir);
    for (format, table) in [("matrix-market", matrix_market), ("ansys", ansys), ("abaqus", abaqus)] {
        let path = dir.join(format!("{format}.toml"));
        // The Ansys node list has no node sets: the root is given by positions there.
        let mut text = fe_model_text(&table, tip);
        if format == "ansys" {
            let roots: Vec<String> = own.mesh.node_sets["ROOT"].iter().map(|&i| own.mesh.nodes[i].label.to_string()).collect();
            text = text.replace("[[support]]\nat = \"ROOT\"\ndofs = \"translations\"\n", "");
            for label in roots {
                let _ = write!(text, "\n[[support]]\nat = {label}\ndofs = \"translations\"\n");
            }
        }
        std::fs::write(&path, text).unwrap();
        let imported = load_fe_model(&path).unwrap_or_else(|e| panic!("{e}")).model;
        let modes = vibration_modes(&imported, 8, &settings).unwrap();
        let difference = largest_difference(&modes.frequencies_hz, &expected.frequencies_hz);
        let shapes = largest_shape_difference((&imported, &modes), (&own, &expected));
        println!("{format}: {:.4?} Hz; against the deck's {difference:.1e}, shapes {shapes:.1e}", modes.frequencies_hz);
        assert!(difference < 1e-9, "{format}: {difference:.2e}");
        assert!(shapes < 1e-7, "{format}: shapes {shapes:.2e}");
    }
}

#[test]
fn matrix_files_and_unknown_formats_are_refused_with_the_supported_ones() {
    let dir = work_dir("errors");
    let mtx = dir.join("rotor_stiffness.mtx");
    std::fs::write(&mtx, "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 4.0\n2 2 4.0\n").unwrap();
    let message = load_fe_model(&mtx).unwrap_err().to_string();
    println!("{message}");
    for expected in ["rotor_stiffness.mtx", "matrix file", "unsupported format", "[matrices]", "calculix", "matrix-market", "abaqus", "ansys"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
    let toml = dir.join("nastran.toml");
    std::fs::write(&toml, "[matrices]\nformat = \"nastran\"\nstiffness = \"k.pch\"\nmass = \"m.pch\"\nnodes = \"n.txt\"\n").unwrap();
    let message = load_fe_model(&toml).unwrap_err().to_string();
    println!("{message}");
    for expected in ["nastran.toml:2", "matrices.format", "`nastran` is not a supported matrix format", "calculix", "ansys"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
}

#[test]
fn a_mass_that_is_not_the_same_in_every_direction_is_refused() {
    let dir = work_dir("anisotropic");
    std::fs::write(dir.join("nodes.txt"), "1 0 0 0\n2 1 0 0\n").unwrap();
    std::fs::write(dir.join("rows.dof"), "1.1\n1.2\n1.3\n2.1\n2.2\n2.3\n").unwrap();
    let diagonal = |values: [f64; 6]| values.iter().enumerate().map(|(i, v)| format!("{} {} {v}\n", i + 1, i + 1)).collect::<String>();
    std::fs::write(dir.join("k.sti"), diagonal([1.0; 6])).unwrap();
    std::fs::write(dir.join("m.mas"), diagonal([1.0, 1.0, 2.0, 1.0, 1.0, 1.0])).unwrap();
    let text = "[matrices]\nformat = \"calculix\"\nstiffness = \"k.sti\"\nmass = \"m.mas\"\ndofs = \"rows.dof\"\nnodes = \"nodes.txt\"\n[modes]\nset = \"2N\"\n";
    std::fs::write(dir.join("pair.toml"), text).unwrap();
    let model = load_fe_model(&dir.join("pair.toml")).unwrap().model;
    let message = vibration_modes(&model, 2, &EigenSettings::default()).unwrap_err().to_string();
    println!("{message}");
    assert!(message.contains("differently in x, y and z"), "{message}");
}
