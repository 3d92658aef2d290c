//! The large-model benchmark: a solid mesh of about 200,000 dofs reduced to a Craig–Bampton body,
//! 20 fixed-interface normal modes plus the constraint modes of two interface nodes (`20N12C`). The
//! mesh, generated in memory, is a steel plate-like link 1.2 m × 0.3 m × 20 mm of C3D8I bricks (240 ×
//! 60 × 4 cells, 73,505 nodes), with a reference node at each end coupled rigidly to its end face and
//! held in its six dofs (the interface). The whole reduction is timed: assembly (of the free model,
//! the supported model's matrices taken from it), the fixed-interface modes (block shift-invert
//! Lanczos, blocks of 12 vectors, on a sparse Cholesky factor, nested dissection by coordinate
//! bisection), the constraint modes (one solve with 12 right-hand sides with the same factor), the
//! orthonormalization and the inertia invariants. Not in the default run (about 17 s of CPU and 1.8
//! GiB; docs/preprocessor.md, "Cost").

use std::time::Instant;

use flexmb_fem::mesh::{Element, ElementKind, RigidCoupling};
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use flexmb_fem::{DofSet, FeModel, MassModel, Material, Mesh, SolidFormulation, SolidSection, Support};
use nalgebra::Vector3;

/// Cells along the length, the width and the thickness.
const CELLS: [usize; 3] = [240, 60, 4];
/// Size (m).
const SIZE: [f64; 3] = [1.2, 0.3, 0.02];
/// The mode set.
const MODE_SET: &str = "20N12C";

/// The link: `cells` C3D8I bricks filling `size`, reference nodes at the centres of the end faces
/// x = 0 and x = `size[0]`, each coupled rigidly to its face and held in all six dofs.
pub fn plate_link(cells: [usize; 3], size: [f64; 3]) -> FeModel {
    let [nx, ny, nz] = cells;
    let mut mesh = Mesh {
        materials: vec![Material { name: "steel".into(), youngs_modulus: 210e9, poisson_ratio: 0.3, density: 7850.0 }],
        solid_sections: vec![SolidSection { name: "link".into(), material: 0 }],
        ..Default::default()
    };
    let index = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let position = Vector3::new(size[0] * i as f64 / nx as f64, size[1] * j as f64 / ny as f64, size[2] * k as f64 / nz as f64);
                mesh.add_node(index(i, j, k) as u64 + 1, position);
            }
        }
    }
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let nodes = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
                    .map(|(a, b, c)| index(i + a, j + b, k + c))
                    .to_vec();
                let label = mesh.elements.len() as u64 + 1;
                mesh.elements.push(Element { label, kind: ElementKind::Solid { section: 0, formulation: SolidFormulation::IncompatibleModeBrick }, nodes });
            }
        }
    }
    let mut supports = Vec::new();
    for (end, i) in [(0.0, 0), (size[0], nx)] {
        let face: Vec<usize> = (0..=nz).flat_map(|k| (0..=ny).map(move |j| index(i, j, k))).collect();
        let label = mesh.max_node_label() + 1;
        let reference = mesh.add_node(label, Vector3::new(end, size[1] / 2.0, size[2] / 2.0));
        mesh.rigid_couplings.push(RigidCoupling { reference, nodes: face, rotations: false });
        supports.push(Support { node: reference, dofs: DofSet::ALL });
    }
    let mut model = FeModel { mesh, supports, ..Default::default() };
    model.options.mass = Some(MassModel::Lumped);
    model
}

/// The process's peak resident memory (bytes), from `/proc/self/status` (Linux); `None` elsewhere.
fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Runs the case `repeat` times and prints the fastest.
pub fn run(repeat: usize) -> Result<(), String> {
    let start = Instant::now();
    let model = plate_link(CELLS, SIZE);
    let mesh_seconds = start.elapsed().as_secs_f64();
    let settings = ReductionSettings { mode_set: MODE_SET.parse().map_err(|e| format!("{e}"))?, basis: Basis::Orthonormal, eigen: Default::default() };
    println!(
        "{:<16} {:>8} {:>7} {:>9} {:>13} {:>10} {:>10} {:>10}",
        "case", "mesh dofs", "set", "modes", "reduction [s]", "f1 [Hz]", "f20 [Hz]", "peak [GiB]"
    );
    let mut best: Option<(f64, usize, Vec<f64>, usize)> = None;
    for _ in 0..repeat {
        let start = Instant::now();
        let reduction = reduce(&model, "plate_link", &settings).map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        if best.as_ref().is_none_or(|b| seconds < b.0) {
            // The mesh's dofs: three per solid node.
            let dofs = 3 * (model.mesh.nodes.len() - 2);
            best = Some((seconds, dofs, reduction.fe_modes.frequencies_hz.clone(), reduction.body.mode_count()));
        }
    }
    let (seconds, dofs, f, modes) = best.ok_or("no run")?;
    let peak = peak_memory().map_or("-".to_string(), |b| format!("{:.2}", b as f64 / (1u64 << 30) as f64));
    println!(
        "{:<16} {:>8} {:>7} {:>9} {:>13.3} {:>10.4} {:>10.4} {:>10}",
        "solid-reduction", dofs, MODE_SET, modes, seconds, f[0], f[f.len() - 1], peak
    );
    println!(
        "(best of {repeat} runs; mesh of {} C3D8I bricks generated in {mesh_seconds:.2} s, not counted; f: fixed-interface \
         frequencies; sparse Cholesky with nested dissection or AMD ordering (the smaller factor), block shift-invert Lanczos (blocks of 12); peak: the process's resident high-water mark)",
        model.mesh.elements.len()
    );
    Ok(())
}
