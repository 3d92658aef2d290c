//! Modal stress recovery against closed form: solid and beam cantilevers under a static tip load,
//! reduced to vibration modes plus the static correction mode of that load, reproduce the static
//! solution, and the stress `σ = Σ aⱼ σⱼ` of the reduced body at the root is beam theory's `M c / I`;
//! a simply supported plate of shells under uniform pressure has Timoshenko's centre stress.

mod support;
#[path = "support/solid_block.rs"]
mod solid_block;

use flexmb_fem::element::StressPlace;
use flexmb_fem::inp::parse_inp;
use flexmb_fem::reduction::{add_modal_stresses, reduce, von_mises, Basis, FlexibleBody, ReductionSettings};
use flexmb_fem::FeModel;
use nalgebra::{DMatrix, DVector};
use solid_block::SolidBlock;
use support::force;

/// `block` with a static load `tip_y` (unit force along y) at the centre of its tip face; the index of
/// that node.
fn loaded_block(block: &SolidBlock) -> (FeModel, usize) {
    let mut model = parse_inp(&block.deck(), "block.inp").unwrap().model;
    let tip = model
        .mesh
        .nodes
        .iter()
        .position(|n| (n.position - nalgebra::Vector3::new(block.lx, block.ly / 2.0, block.lz / 2.0)).norm() < 1e-9)
        .unwrap();
    model.static_loads = vec![force("tip_y", tip, [0.0, 1.0, 0.0])];
    (model, tip)
}

/// The modal coordinates of the reduced body's static equilibrium under `load` N along y at node
/// `tip`: `K_aa a = Φᵀ f`.
fn static_coordinates(body: &FlexibleBody, tip: usize, load: f64) -> Vec<f64> {
    let f = DVector::from_iterator(body.mode_count(), body.shapes.iter().map(|s| load * s.translation[tip][1]));
    let k: &DMatrix<f64> = &body.modal_stiffness;
    k.clone().lu().solve(&f).unwrap().iter().copied().collect()
}

/// The root stress σxx at the nodes of the top (y = ly) and bottom (y = 0) fibres of the clamped
/// face, for a tip load of 1 kN, against `∓ F L c / I`; the largest relative error.
fn root_stress_error(element: &'static str, nx: usize, n: usize) -> f64 {
    // ν = 0: the clamp then holds the root section as beam theory does (no lateral contraction to
    // restrain), so the root stress is M c / I without the clamp's local Poisson stress.
    let block = SolidBlock { ny: n, nz: n, poisson_ratio: 0.0, ..SolidBlock::cantilever(element, nx) };
    let (model, tip) = loaded_block(&block);
    let settings = ReductionSettings { mode_set: "4N1S".parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let mut body = reduce(&model, "block", &settings).unwrap().body;
    assert_eq!(add_modal_stresses(&model, &mut body).unwrap(), None);
    let load = 1000.0;
    let a = static_coordinates(&body, tip, load);
    // The static correction mode is in the basis: the tip deflects as the FE model's static solution,
    // and a beam's F L³ / (3 E I) within the shear and mesh error.
    let deflection: f64 = body.shapes.iter().zip(&a).map(|(s, aj)| aj * s.translation[tip][1]).sum();
    let i = block.lz * block.ly.powi(3) / 12.0;
    let beam = load * block.lx.powi(3) / (3.0 * block.youngs_modulus * i);
    assert!((deflection / beam - 1.0).abs() < 0.02, "{element}: tip deflection {deflection} against {beam}");
    let stresses = body.stresses.as_ref().unwrap();
    let mut sigma = vec![[0.0; 6]; stresses.len()];
    stresses.superpose(&a, &mut sigma);
    let bending = load * block.lx * (block.ly / 2.0) / i;
    let mut worst = 0.0_f64;
    for (p, (&node, &place)) in stresses.nodes.iter().zip(&stresses.places).enumerate() {
        assert_eq!(place, StressPlace::Solid);
        let x = body.nodes[node].position;
        if x.x.abs() > 1e-9 || ((x.y - block.ly / 2.0).abs() - block.ly / 2.0).abs() > 1e-9 {
            continue;
        }
        // Top fibre (y = ly) in compression, bottom in tension.
        let expected = if x.y > block.ly / 2.0 { -bending } else { bending };
        let error = (sigma[p][0] / expected - 1.0).abs();
        println!("  {element} node {} at z = {:.3}: σxx {:.5e} Pa, von Mises {:.5e} Pa ({error:.2e})", body.nodes[node].label, x.z, sigma[p][0], von_mises(&sigma[p]));
        worst = worst.max(error);
    }
    println!("{element} {nx} × {n} × {n}: root stress within {worst:.2e} of M c / I = {bending:.5e} Pa");
    worst
}

#[test]
fn solid_cantilever_root_stress_is_m_c_over_i() {
    // C3D20 quadratic bricks: their bending stress is linear through the depth and along the
    // element, as the beam's (measured 6.7e-4 low).
    assert!(root_stress_error("C3D20", 10, 2) < 2e-3);
    // C3D8I: the incompatible modes bend without locking, but their bending strain is constant
    // along an element: the root nodes carry about the moment at the first element's centre,
    // (1 − 1/40) of the root's (measured 1.9 % low).
    assert!(root_stress_error("C3D8I", 20, 4) < 0.025);
}

/// A beam-element cantilever (20 elements, 10 mm square, 1 m) under a tip load along y, reduced to
/// 4N1S: the fibres of the root section carry `± F L c / I` and the tip's none (Hermite beams are
/// exact for end loads; the static mode is in the basis).
#[test]
fn beam_cantilever_root_fibres_carry_m_c_over_i() {
    let h = 0.01;
    let mut model = support::cantilever(1.0, 20, support::square_section(h));
    let tip = model.mesh.nodes.len() - 1;
    model.static_loads = vec![force("tip_y", tip, [0.0, 1.0, 0.0])];
    let settings = ReductionSettings { mode_set: "4N1S".parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let mut body = reduce(&model, "beam", &settings).unwrap().body;
    assert_eq!(add_modal_stresses(&model, &mut body).unwrap(), None);
    let load = 10.0;
    let a = static_coordinates(&body, tip, load);
    let stresses = body.stresses.as_ref().unwrap();
    let mut sigma = vec![[0.0; 6]; stresses.len()];
    stresses.superpose(&a, &mut sigma);
    let bending = load * 1.0 * (h / 2.0) / (h.powi(4) / 12.0);
    let root: Vec<usize> = (0..stresses.len()).filter(|&p| stresses.nodes[p] == 0).collect();
    assert_eq!(root.len(), 4, "the root section's four corners");
    for &p in &root {
        assert!(matches!(stresses.places[p], StressPlace::Fibre(_)));
        assert!((sigma[p][0].abs() / bending - 1.0).abs() < 1e-8, "σxx {} against ± {bending}", sigma[p][0]);
        assert!((von_mises(&sigma[p]) / bending - 1.0).abs() < 1e-8);
    }
    // The fibres at y = +c are compressed (the beam bends towards +y).
    let top = root.iter().find(|&&p| sigma[p][0] < 0.0).unwrap();
    let bottom = root.iter().find(|&&p| sigma[p][0] > 0.0).unwrap();
    println!("beam root fibres: {:.6e} and {:.6e} Pa, M c / I = {bending:.6e} Pa", sigma[*top][0], sigma[*bottom][0]);
    // At the tip, the moment is zero.
    let tip_max = (0..stresses.len()).filter(|&p| stresses.nodes[p] == tip).map(|p| von_mises(&sigma[p])).fold(0.0, f64::max);
    assert!(tip_max < 1e-8 * bending, "tip {tip_max}");
}

/// A simply supported square steel plate (1 m, 10 mm, 20 × 20 elements) under a uniform pressure q,
/// its static deflection superposed from its lowest 40 vibration modes (`K_aa a = Φᵀ f`, f the
/// pressure's nodal forces): at the centre, the surface stresses `±6 M / t²` with Timoshenko's
/// `M = 0.0479 q a²` (Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, table 8,
/// ν = 0.3), and the deflection `0.00406 q a⁴ / D`. Returns the relative errors (deflection,
/// stress) for `shape`.
fn plate_errors(shape: flexmb_fem::mesh::ShellShape) -> (f64, f64) {
    let (a, t, n, q) = (1.0, 0.01, 20, 1000.0);
    let model = support::simply_supported_plate(a, a, t, n, n, shape);
    let settings = ReductionSettings { mode_set: "40N".parse().unwrap(), basis: Basis::Raw, eigen: Default::default() };
    let mut body = reduce(&model, "plate", &settings).unwrap().body;
    assert_eq!(add_modal_stresses(&model, &mut body).unwrap(), None);
    // The pressure's nodal forces: each element's share q A / n to each of its n nodes.
    let mut force = vec![0.0; body.nodes.len()];
    for element in &model.mesh.elements {
        let p: Vec<_> = element.nodes.iter().map(|&k| model.mesh.nodes[k].position).collect();
        let area = match p.len() {
            3 => 0.5 * (p[1] - p[0]).cross(&(p[2] - p[0])).norm(),
            _ => 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm(),
        };
        for &k in &element.nodes {
            force[k] += q * area / p.len() as f64;
        }
    }
    let f = DVector::from_iterator(body.mode_count(), body.shapes.iter().map(|s| (0..force.len()).map(|k| force[k] * s.translation[k][2]).sum()));
    let coordinates: Vec<f64> = body.modal_stiffness.clone().lu().solve(&f).unwrap().iter().copied().collect();
    let centre = body.nodes.iter().position(|node| (node.position - nalgebra::Vector3::new(a / 2.0, a / 2.0, 0.0)).norm() < 1e-9).unwrap();
    let deflection: f64 = body.shapes.iter().zip(&coordinates).map(|(s, x)| x * s.translation[centre][2]).sum();
    let d = support::E * t.powi(3) / (12.0 * (1.0 - support::NU * support::NU));
    let expected_deflection = 0.00406 * q * a.powi(4) / d;
    let stresses = body.stresses.as_ref().unwrap();
    let mut sigma = vec![[0.0; 6]; stresses.len()];
    stresses.superpose(&coordinates, &mut sigma);
    let expected = 6.0 * 0.0479 * q * a * a / (t * t);
    let mut worst = 0.0_f64;
    for (p, (&node, &place)) in stresses.nodes.iter().zip(&stresses.places).enumerate() {
        if node != centre {
            continue;
        }
        // The pressure pushes along +z: the top surface (+z) is stretched, the bottom compressed.
        let sign = match place {
            StressPlace::Top => 1.0,
            StressPlace::Bottom => -1.0,
            other => panic!("a shell's place {other}"),
        };
        for component in [0, 1] {
            worst = worst.max((sigma[p][component] / (sign * expected) - 1.0).abs());
        }
        println!("  {shape:?} centre {place}: σxx {:.5e}, σyy {:.5e}, von Mises {:.5e} Pa", sigma[p][0], sigma[p][1], von_mises(&sigma[p]));
    }
    let deflection_error = (deflection / expected_deflection - 1.0).abs();
    println!("{shape:?} 20 × 20, 40N: centre deflection {deflection:.5e} m ({deflection_error:.2e} from {expected_deflection:.5e}), surface stress within {worst:.2e} of 6 M / t² = {expected:.5e} Pa");
    (deflection_error, worst)
}

#[test]
fn simply_supported_plate_under_pressure_has_timoshenkos_centre_stress() {
    for shape in [flexmb_fem::mesh::ShellShape::Quadrilateral, flexmb_fem::mesh::ShellShape::Triangle] {
        let (deflection, stress) = plate_errors(shape);
        // Measured: quadrilaterals 2.0e-3 and 2.6e-3, triangles 1.7e-3 and 1.2e-3.
        assert!(deflection < 5e-3 && stress < 5e-3, "{shape:?}: {deflection}, {stress}");
    }
}
