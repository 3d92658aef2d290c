//! The beams' default mass against a geometrically exact reference: the beam pendulum of Exudyn's
//! ANCF cable (`tests/data/beam_pendulum_ancf.csv`, where the file says how it was made), built from
//! flexmb beams, reduced to its vibration modes and swung on a revolute joint for 1 s.
//!
//! The tip's elastic deflection is small (at most 2.6e-4 m against a 1 m swing), so the test measures
//! the whole tip trajectory's distance from the reference in units of that amplitude. The consistent
//! mass (the beams' default) integrates the bar's inertia about its hinge exactly; the lumped nodes of
//! `n` elements add `m L² / (6 n²)` to it, which slows the swing by many times the deflection.

use flexmb::analysis::{simulate, SimulationSettings};
use flexmb::body::{InitialState, Marker, ModalDamping};
use flexmb::integrate::Tolerances;
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{Mat3, Vec3};
use flexmb::model::{BodyRef, ModelBuilder, OutputKind};
use flexmb_fem::mesh::PointMass;
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use flexmb_fem::{BeamSection, Dof, DofSet, FeModel, MassModel, Material, Mesh, ModelOptions, Support};

use crate::program::workspace;

/// The reference's largest elastic tip deflection (m), its distance from the tangent at the hinge.
const DEFLECTION_AMPLITUDE: f64 = 2.63e-4;

/// The reference's samples: (t, tip x, tip y) every 0.01 s from 0 to 1 s.
fn reference() -> Vec<[f64; 3]> {
    let path = workspace().join("crates/flexmb-cli/tests/data/beam_pendulum_ancf.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('t'))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// The reference's beam in `n` Euler–Bernoulli elements along x: steel, 20 mm square. Like the ANCF
/// cable, the sections have no rotary inertia in bending; the bar's spin inertia about its own axis
/// (ρ J per length, lumped at the nodes) gives the body's rotation about x the mass that the cable's
/// rotation-free nodes do not need. It moves nothing in the plane of the swing.
fn beam(n: usize, mass: Option<MassModel>) -> FeModel {
    let (side, density, length): (f64, f64, f64) = (0.02, 7850.0, 1.0);
    let second_moment = side.powi(4) / 12.0;
    let mut mesh = Mesh {
        materials: vec![Material { name: "steel".into(), youngs_modulus: 2.1e11, poisson_ratio: 0.3, density }],
        beam_sections: vec![BeamSection {
            name: "square".into(),
            material: 0,
            area: side * side,
            iy: second_moment,
            iz: second_moment,
            torsion_constant: 0.1406 * side.powi(4),
            orientation: Vec3::new(0.0, 1.0, 0.0),
            shear_coefficient: None,
            outline: Default::default(),
        }],
        ..Default::default()
    };
    mesh.add_beam_line(Vec3::zeros(), Vec3::new(length, 0.0, 0.0), n, 0).unwrap();
    let spin_per_length = density * 2.0 * second_moment;
    let h = length / n as f64;
    mesh.point_masses = (0..=n)
        .map(|node| {
            let share = if node == 0 || node == n { 0.5 * h } else { h };
            PointMass { node, mass: 0.0, rotary_inertia: Vec3::new(spin_per_length * share, 0.0, 0.0) }
        })
        .collect();
    // The modes as the revolute holds the beam: its hinge node held in translation and in the two
    // rotations the joint holds; the turn about z is the mechanism the mode analysis sets aside.
    let supports = vec![Support { node: 0, dofs: DofSet::TRANSLATIONS.with(Dof::Rx).with(Dof::Ry) }];
    let options = ModelOptions { mass, rotary_inertia: false, ..Default::default() };
    FeModel { mesh, supports, options, ..Default::default() }
}

/// The pendulum of `n` elements, reduced to `modes` vibration modes, swung for 1 s: the tip's
/// (t, x, y) every 0.01 s, and the number of steps.
fn swing(n: usize, mass: Option<MassModel>, modes: usize) -> (Vec<[f64; 3]>, usize) {
    let fe = beam(n, mass);
    let settings = ReductionSettings { mode_set: format!("{modes}N").parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let reduced = reduce(&fe, "beam", &settings).unwrap();
    let modal = flexmb_files::flexible_body::modal_body(&reduced.body, &ModalDamping::None).unwrap();
    let mut b = ModelBuilder::new("beam pendulum").gravity(Vec3::new(0.0, -9.81, 0.0));
    let beam_id = b.add_flexible_body("beam", InitialState::default(), modal).unwrap();
    let hinge = b.add_node_marker("hinge", beam_id, 0, Mat3::identity()).unwrap();
    let tip = b.add_node_marker("tip", beam_id, n, Mat3::identity()).unwrap();
    let pivot = b.add_marker(Marker { name: "pivot".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap();
    b.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: pivot, marker_j: hinge }).unwrap();
    b.add_output("tip", OutputKind::MarkerPosition(tip)).unwrap();
    let model = b.build().unwrap();
    let settings = SimulationSettings { t_end: 1.0, output_step: 0.01, tolerances: Tolerances::new(1e-8, 1e-8), ..Default::default() };
    let mut samples = Vec::new();
    let report = simulate(&model, &settings, &mut |f| samples.push([f.t, f.values[0], f.values[1]])).unwrap();
    (samples, report.stats.steps)
}

/// The largest distance of the tip from the reference's over the run, in units of the deflection
/// amplitude.
fn largest_error(samples: &[[f64; 3]], reference: &[[f64; 3]]) -> f64 {
    assert_eq!(samples.len(), reference.len());
    samples
        .iter()
        .zip(reference)
        .map(|(s, r)| {
            assert!((s[0] - r[0]).abs() < 1e-9, "sample at {} s against {} s", s[0], r[0]);
            (s[1] - r[1]).hypot(s[2] - r[2])
        })
        .fold(0.0, f64::max)
        / DEFLECTION_AMPLITUDE
}

/// The beams' default mass (consistent) swings the beam, reduced to its 4 lowest modes, within 2 % of
/// the tip's deflection amplitude of the ANCF cable over the whole second at 10, 20 and 40 elements
/// (measured: 7.5e-3, 6.4e-3 and 6.4e-3 of it, 2e-6 m, which the mesh does not change: the rest of
/// the model, not the mass; the reference's own step error is about 3e-7 m). About 1 s in release.
#[test]
fn the_default_beam_mass_swings_within_two_percent_of_the_deflection_of_the_ancf_cable() {
    let reference = reference();
    for n in [10, 20, 40] {
        let (samples, steps) = swing(n, None, 4);
        let error = largest_error(&samples, &reference);
        println!("{n} elements, default (consistent) mass, 4N: tip within {error:.2e} deflection amplitudes of ANCF over 1 s ({steps} steps)");
        assert!(error < 0.02, "{n} elements: {error:.3e} amplitudes");
        // The tip has swung a whole metre, and the comparison resolves a hundredth of its elastic
        // deflection along the way.
        let last = samples.last().unwrap();
        assert!(last[1] < -0.99, "{last:?}");
    }
}

/// The same beam lumped: 28 deflection amplitudes off at 10 elements (the nodes add `m L² / (6 n²)`,
/// 0.5 %, to its inertia about the hinge, and the swing falls behind), 7.1 at 20, 1.8 at 40: second
/// order, a factor of about 4 each time the elements double. About 1 s in release.
#[test]
fn the_lumped_beam_mass_is_many_deflections_off_and_converges_at_second_order() {
    let reference = reference();
    let errors: Vec<f64> = [10, 20, 40].iter().map(|&n| largest_error(&swing(n, Some(MassModel::Lumped), 4).0, &reference)).collect();
    let shown: Vec<String> = errors.iter().map(|e| format!("{e:.3}")).collect();
    println!("lumped mass, 4N: tip within {} deflection amplitudes of ANCF over 1 s at 10, 20, 40 elements", shown.join(", "));
    assert!(errors[0] > 20.0 && errors[2] > 1.0, "{errors:?}");
    for pair in errors.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!((3.5..4.5).contains(&ratio), "second order: ratio {ratio:.2} for twice the elements ({errors:?})");
    }
}
