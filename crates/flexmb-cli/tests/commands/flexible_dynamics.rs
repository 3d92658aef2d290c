//! Flexible bodies in mechanisms, end to end: an FE model from the preprocessor, reduced to a mode set,
//! put into the engine as a modal body, simulated.
//!
//! - A cantilever arm clamped to ground and loaded at its tip settles (with damping) to the FE static
//!   deflection: exactly when the tip force's static correction mode is in the set, approximately with
//!   vibration modes only.
//! - A flexible pendulum on a revolute joint converges as modes are added.

use flexmb::analysis::{simulate, SimulationSettings};
use flexmb::body::{InitialState, Marker, ModalDamping};
use flexmb::force::{ForceElement, ForceFrame, ForceKind};
use flexmb::function::Expression;
use flexmb::integrate::{BdfConfig, Tolerances};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{Mat3, Vec3};
use flexmb::model::{BodyRef, Model, ModelBuilder, OutputKind};
use flexmb_files::flexible_body::modal_body;
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use flexmb_fem::{
    BeamSection, DofSet, FeModel, MassModel, Material, Mesh, ModelOptions, StaticLoad, StaticLoadKind, Support,
};

/// A steel beam along x, `n` elements, rectangular `w` (y) × `h` (z), rotary inertia lumped.
fn beam(length: f64, n: usize, w: f64, h: f64) -> FeModel {
    let mut mesh = Mesh {
        materials: vec![Material { name: "steel".into(), youngs_modulus: 210e9, poisson_ratio: 0.3, density: 7850.0 }],
        beam_sections: vec![BeamSection {
            name: "bar".into(),
            material: 0,
            area: w * h,
            iy: w * h.powi(3) / 12.0,
            iz: h * w.powi(3) / 12.0,
            torsion_constant: 0.263 * w * h.powi(3),
            orientation: Vec3::new(0.0, 1.0, 0.0),
            shear_coefficient: None,
            outline: Default::default(),
        }],
        ..Default::default()
    };
    mesh.add_beam_line(Vec3::zeros(), Vec3::new(length, 0.0, 0.0), n, 0).unwrap();
    FeModel { mesh, options: ModelOptions { rotary_inertia: true, ..Default::default() }, ..Default::default() }
}

fn settings(t_end: f64, output_step: f64, tolerance: f64) -> SimulationSettings {
    SimulationSettings {
        t_end,
        output_step,
        tolerances: Tolerances::new(tolerance, tolerance),
        ..Default::default()
    }
}

/// The clamped arm with a tip force `force_z` (N, along z) and modal damping ratio 0.7, reduced to
/// `set`; returns the model and the FE static tip deflection under the same force.
fn loaded_arm(set: &str, force_z: f64) -> (Model, f64) {
    let mut fe = beam(1.0, 12, 0.03, 0.01);
    let tip = fe.mesh.nodes.len() - 1;
    fe.supports.push(Support { node: 0, dofs: DofSet::ALL });
    fe.static_loads.push(StaticLoad { name: "tip_fz".into(), node: tip, kind: StaticLoadKind::Force(Vec3::z()) });
    let settings = ReductionSettings { mode_set: set.parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let reduced = reduce(&fe, "arm", &settings).unwrap();
    // The FE static deflection: the static mode is the unit-load response, scaled by the force.
    let raw = reduce(&fe, "arm", &ReductionSettings { mode_set: "1S".parse().unwrap(), basis: Basis::Raw, eigen: Default::default() }).unwrap();
    let static_tip = force_z * raw.body.shapes[0].translation[tip][2];
    let modal = modal_body(&reduced.body, &ModalDamping::Ratios(vec![0.7])).unwrap();
    let mut b = ModelBuilder::new("clamped arm");
    let arm = b.add_flexible_body("arm", InitialState::default(), modal).unwrap();
    let root = b.add_node_marker("root", arm, 0, Mat3::identity()).unwrap();
    let tip_marker = b.add_node_marker("tip", arm, tip, Mat3::identity()).unwrap();
    let ground = b.add_marker(Marker { name: "wall".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap();
    b.add_joint(Joint { name: "clamp".into(), kind: JointKind::Fixed, marker_i: ground, marker_j: root }).unwrap();
    let component = |x: f64| Expression::parse(&format!("{x}"), &|_| None).unwrap();
    b.add_force(ForceElement {
        name: "load".into(),
        kind: ForceKind::AppliedForce { marker: tip_marker, components: [component(0.0), component(0.0), component(force_z)], frame: ForceFrame::Global },
    }).unwrap();
    b.add_output("tip", OutputKind::MarkerPosition(tip_marker)).unwrap();
    (b.build().unwrap(), static_tip)
}

#[test]
fn a_clamped_arm_settles_to_the_fe_static_deflection() {
    let force = 5.0;
    for (set, tolerance) in [("2N1S", 1e-6), ("1S", 1e-6), ("4N", 2e-2)] {
        let (model, static_tip) = loaded_arm(set, force);
        let mut tip_z = Vec::new();
        let report = simulate(&model, &settings(3.0, 0.05, 1e-8), &mut |f| tip_z.push(f.values[2])).unwrap();
        let settled = *tip_z.last().unwrap();
        let error = (settled - static_tip).abs() / static_tip.abs();
        println!(
            "{set}: tip deflection after 3 s {settled:.6e} m, FE static {static_tip:.6e} m, relative error {error:.1e} ({} steps)",
            report.stats.steps
        );
        assert!(error < tolerance, "{set}: settled at {settled}, FE static {static_tip}");
        // It really moved from rest and overshot on the way (a damped vibration, not a creep).
        assert!(tip_z[0].abs() < 1e-12);
    }
}

/// A pendulum: the beam on a revolute joint (axis z) at its first node, released horizontal under
/// gravity −y. Returns the tip's (x, y) at every output time.
fn pendulum(set: Option<&str>) -> Vec<[f64; 2]> {
    pendulum_with(10, MassModel::Lumped, set)
}

/// [`pendulum`] with a beam of `elements` elements and the lumped or consistent mass.
fn pendulum_with(elements: usize, mass: MassModel, set: Option<&str>) -> Vec<[f64; 2]> {
    // Slender in the plane of the swing (6 mm along y): first in-plane bending about 20 Hz.
    let mut fe = beam(1.0, elements, 0.006, 0.03);
    fe.options.mass = Some(mass);
    let tip = fe.mesh.nodes.len() - 1;
    // The modes of the beam as the revolute holds it: the hinge node held in translation and in the two
    // rotations the revolute holds; the turn about the hinge axis is the rigid mechanism. (No joint
    // constraint is deleted, so no static correction mode is needed.)
    fe.supports.push(Support { node: 0, dofs: DofSet::TRANSLATIONS.with(flexmb_fem::Dof::Rx).with(flexmb_fem::Dof::Ry) });
    let mut b = ModelBuilder::new("flexible pendulum").gravity(Vec3::new(0.0, -9.81, 0.0));
    let mode_set = set.unwrap_or("1N");
    let settings_fe = ReductionSettings { mode_set: mode_set.parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let reduced = reduce(&fe, "beam", &settings_fe).unwrap();
    let mut modal = modal_body(&reduced.body, &ModalDamping::Ratios(vec![0.01])).unwrap();
    if set.is_none() {
        // No modes: the same FE mass, rigid.
        modal = flexmb_files::flexible_body::modal_body(&{
            let mut body = reduced.body.clone();
            body.modes.clear();
            body.shapes.clear();
            body.modal_stiffness = nalgebra::DMatrix::zeros(0, 0);
            body.modal_mass = nalgebra::DMatrix::zeros(0, 0);
            let inv = &mut body.invariants;
            inv.c2 = nalgebra::DMatrix::zeros(3, 0);
            inv.c4.clear();
            inv.c5.clear();
            inv.c6 = nalgebra::DMatrix::zeros(3, 0);
            inv.c7.clear();
            inv.c8 = nalgebra::DVector::zeros(0);
            inv.c9 = nalgebra::DMatrix::zeros(0, 0);
            inv.rotary_coupling = nalgebra::DMatrix::zeros(3, 0);
            inv.rotary_modal_mass = nalgebra::DMatrix::zeros(0, 0);
            body.geometric_stiffness = None;
            body
        }, &ModalDamping::None)
        .unwrap();
    }
    let beam_id = b.add_flexible_body("beam", InitialState::default(), modal).unwrap();
    let hinge = b.add_node_marker("hinge", beam_id, 0, Mat3::identity()).unwrap();
    let tip_marker = b.add_node_marker("tip", beam_id, tip, Mat3::identity()).unwrap();
    let ground = b.add_marker(Marker { name: "pivot".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap();
    b.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: ground, marker_j: hinge }).unwrap();
    b.add_output("tip", OutputKind::MarkerPosition(tip_marker)).unwrap();
    let model = b.build().unwrap();
    let mut tip_xy = Vec::new();
    simulate(&model, &settings(1.0, 0.01, 1e-8), &mut |f| tip_xy.push([f.values[0], f.values[1]])).unwrap();
    tip_xy
}

fn largest_difference(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    a.iter().zip(b).map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()).fold(0.0, f64::max)
}

#[test]
fn a_flexible_pendulum_converges_as_modes_are_added() {
    let reference = pendulum(Some("10N"));
    let rigid = largest_difference(&pendulum(None), &reference);
    let mut errors = Vec::new();
    for set in ["1N", "2N", "4N", "6N"] {
        errors.push(largest_difference(&pendulum(Some(set)), &reference));
    }
    println!("flexible pendulum, largest tip distance from 10N over 1 s: rigid {rigid:.2e} m; 1N, 2N, 4N, 6N: {errors:?}");
    // The flexibility matters: the rigid beam is far from the flexible reference.
    assert!(rigid > 1e-4, "rigid differs by {rigid}");
    // Adding modes approaches the reference; every flexible set is closer than the rigid beam.
    assert!(errors[0] < rigid);
    assert!(errors[2] < errors[0] && errors[3] < errors[1], "{errors:?}");
    assert!(errors[3] < 0.05 * rigid, "6N within 5 % of the rigid–flexible difference: {errors:?}");
}

/// A flexible body with the consistent mass in a mechanism: the invariants integrate the beam's field
/// exactly (its inertia about the hinge is m L² / 3, where the lumped nodes give
/// m L² (1/3 + 1/(6 n²))), so a coarse consistent mesh is much closer to a fine one than the same
/// coarse mesh lumped, and both converge to the same swing.
#[test]
fn a_flexible_pendulum_with_the_consistent_mass_converges_faster() {
    let reference = pendulum_with(40, MassModel::Consistent, Some("4N"));
    let lumped_fine = largest_difference(&pendulum_with(40, MassModel::Lumped, Some("4N")), &reference);
    let consistent = largest_difference(&pendulum_with(10, MassModel::Consistent, Some("4N")), &reference);
    let lumped = largest_difference(&pendulum_with(10, MassModel::Lumped, Some("4N")), &reference);
    println!(
        "flexible pendulum 4N, largest tip distance over 1 s from 40 consistent elements: 10 consistent {consistent:.2e} m, 10 lumped {lumped:.2e} m, 40 lumped {lumped_fine:.2e} m"
    );
    assert!(consistent < 1e-2 * lumped, "consistent {consistent:.2e} m, lumped {lumped:.2e} m");
    assert!(lumped_fine < 0.1 * lumped, "the lumped mesh converges to the same swing: {lumped_fine:.2e} m");
}

/// The assembly holds the modal coordinates unless asked otherwise: a clamped arm whose tip is pinned
/// to a ground point 1 mm off its undeformed position cannot be assembled rigidly, and assembles by
/// bending when the modal coordinates may move (the tip then sits on the point).
#[test]
fn assembly_moves_modal_coordinates_only_when_asked() {
    use flexmb::analysis::{assemble, AssemblySettings, ModalAssembly, State};
    let mut fe = beam(1.0, 12, 0.03, 0.01);
    let tip = fe.mesh.nodes.len() - 1;
    fe.supports.push(Support { node: 0, dofs: DofSet::ALL });
    fe.static_loads.push(StaticLoad { name: "tip_fz".into(), node: tip, kind: StaticLoadKind::Force(Vec3::z()) });
    let settings = ReductionSettings { mode_set: "2N1S".parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let reduced = reduce(&fe, "arm", &settings).unwrap();
    let modal = modal_body(&reduced.body, &ModalDamping::None).unwrap();
    let mut b = ModelBuilder::new("pinned arm");
    let arm = b.add_flexible_body("arm", InitialState::default(), modal).unwrap();
    let root = b.add_node_marker("root", arm, 0, Mat3::identity()).unwrap();
    let tip_marker = b.add_node_marker("tip", arm, tip, Mat3::identity()).unwrap();
    let wall = b.add_marker(Marker { name: "wall".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap();
    let target = Vec3::new(1.0, 0.0, 1e-3);
    let pin = b.add_marker(Marker { name: "pin".into(), body: BodyRef::Ground, origin: target, axes: Mat3::identity() }).unwrap();
    b.add_joint(Joint { name: "clamp".into(), kind: JointKind::Fixed, marker_i: wall, marker_j: root }).unwrap();
    b.add_joint(Joint { name: "tip_pin".into(), kind: JointKind::Spherical, marker_i: pin, marker_j: tip_marker }).unwrap();
    let model = b.build().unwrap();
    let mut data = flexmb::Data::new(&model);
    let mut held = State::initial(&model);
    assert!(assemble(&model, &mut data, &mut held, AssemblySettings::default()).is_err(), "rigid frames alone cannot reach the pin");
    let mut free = State::initial(&model);
    let report = assemble(&model, &mut data, &mut free, AssemblySettings { modal: ModalAssembly::Free, ..Default::default() }).unwrap();
    assert!(report.residual < 1e-10);
    let a = &free.q[7..10];
    assert!(a.iter().any(|x| x.abs() > 0.0), "the arm bent: a = {a:?}");
    let initial = State::initial(&model);
    for k in 0..7 {
        assert!((free.q[k] - initial.q[k]).abs() < 1e-9, "the clamped frame stayed: q[{k}] = {}", free.q[k]);
    }
}

/// The static assembly holds the frames and bends the body with the least strain energy that closes
/// the joints, which is the static deflection under the joints' loads. A clamped arm whose tip is
/// pinned 1 mm above its undeformed position takes, in the span of 2N1S (which holds the exact FE
/// response to a tip force), exactly the tip-force deflection: strain energy `δ² / (2c)` with `c` the
/// FE tip compliance, and at mid-span the FE static shape scaled to the tip deflection.
#[test]
fn static_assembly_gives_the_static_deflection_that_fits_the_joints() {
    use flexmb::analysis::{assemble, AssemblySettings, ModalAssembly, State};
    let mut fe = beam(1.0, 12, 0.03, 0.01);
    let tip = fe.mesh.nodes.len() - 1;
    let mid = tip / 2;
    fe.supports.push(Support { node: 0, dofs: DofSet::ALL });
    fe.static_loads.push(StaticLoad { name: "tip_fz".into(), node: tip, kind: StaticLoadKind::Force(Vec3::z()) });
    let raw = ReductionSettings { mode_set: "1S".parse().unwrap(), basis: Basis::Raw, eigen: Default::default() };
    let unit_load = reduce(&fe, "arm", &raw).unwrap().body;
    let compliance = unit_load.shapes[0].translation[tip][2];
    let settings = ReductionSettings { mode_set: "2N1S".parse().unwrap(), basis: Basis::Orthonormal, eigen: Default::default() };
    let reduced = reduce(&fe, "arm", &settings).unwrap();
    let modal = modal_body(&reduced.body, &ModalDamping::None).unwrap();
    let stiffness = modal.stiffness.clone();
    let psi_mid = modal.nodes[mid].psi.clone();
    let mut b = ModelBuilder::new("pinned arm");
    let arm = b.add_flexible_body("arm", InitialState::default(), modal).unwrap();
    let root = b.add_node_marker("root", arm, 0, Mat3::identity()).unwrap();
    let tip_marker = b.add_node_marker("tip", arm, tip, Mat3::identity()).unwrap();
    let wall = b.add_marker(Marker { name: "wall".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap();
    let deflection = 1e-3;
    let pin = b.add_marker(Marker {
        name: "pin".into(),
        body: BodyRef::Ground,
        origin: Vec3::new(1.0, 0.0, deflection),
        axes: Mat3::identity(),
    }).unwrap();
    b.add_joint(Joint { name: "clamp".into(), kind: JointKind::Fixed, marker_i: wall, marker_j: root }).unwrap();
    b.add_joint(Joint { name: "tip_pin".into(), kind: JointKind::Spherical, marker_i: pin, marker_j: tip_marker }).unwrap();
    let model = b.build().unwrap();
    let mut data = flexmb::Data::new(&model);
    let mut state = State::initial(&model);
    let report = assemble(&model, &mut data, &mut state, AssemblySettings { modal: ModalAssembly::Static, ..Default::default() }).unwrap();
    assert!(report.residual < 1e-10, "{}", report.residual);
    let initial = State::initial(&model);
    for k in 0..7 {
        assert_eq!(state.q[k], initial.q[k], "the frame is held: q[{k}]");
    }
    let a = nalgebra::DVector::from_column_slice(&state.q[7..10]);
    let strain = 0.5 * a.dot(&(&stiffness * &a));
    // The pin also holds the tip's small axial shortening; it is of second order (1e-6 relative).
    let expected = deflection * deflection / (2.0 * compliance);
    assert!((strain / expected - 1.0).abs() < 1e-5, "strain energy {strain:e} J, static {expected:e} J");
    let mid_z = (&psi_mid * &a)[2];
    let expected_mid = deflection / compliance * unit_load.shapes[0].translation[mid][2];
    assert!((mid_z / expected_mid - 1.0).abs() < 1e-5, "mid-span deflection {mid_z:e} m, static {expected_mid:e} m");
}

/// The stiffness signature on a flexible model: the shipped flexible pendulum with ten vibration modes
/// (up to 1.6 kHz, 2 % damped) for 1 s, with the default error per unit step over the run. Adams' step
/// is held by the highest mode's stability, not by the tolerance: its steps hardly change when the
/// tolerance is tightened a hundredfold (measured 3,393 steps at 1e-2, 3,583 at 1e-4, a root-mean-square
/// step of 3.1e-4 s at both), while the BDF and the generalized-α method, whose steps follow the accuracy
/// asked, step over the high modes at a loose tolerance (809 and 319 steps at 1e-2) and agree with Adams
/// on the swing (tip within 1.8e-3 m). At tight tolerances the accuracy asked holds every method's steps
/// (at 1e-6: BDF 5,787, Adams 4,715, generalized-α 30,111), so the signature is shown at a loose one.
#[test]
fn on_a_stiff_flexible_model_adams_needs_many_more_steps() {
    use flexmb::integrate::{AdamsConfig, Method};
    let model = flexmb_cli::bench::pendulums::flexible_pendulum(Some("10N")).unwrap();
    let tip = |frames: &[Vec<f64>]| frames.iter().map(|f| [f[0], f[1]]).collect::<Vec<_>>();
    let run = |method: Method, tolerance: f64| {
        let s = SimulationSettings { method, ..settings(1.0, 0.005, tolerance) };
        let mut frames = Vec::new();
        let report = simulate(&model, &s, &mut |f| frames.push(f.values.to_vec())).unwrap();
        (report.stats.steps, tip(&frames))
    };
    let methods = [Method::Bdf(BdfConfig::for_model(&model)), Method::Adams(AdamsConfig::default()), Method::generalized_alpha(0.9)];
    let results: Vec<_> = methods.into_iter().map(|method| run(method, 1e-2)).collect();
    let steps: Vec<usize> = results.iter().map(|r| r.0).collect();
    let (adams_tight, _) = run(Method::Adams(AdamsConfig::default()), 1e-4);
    let spread = largest_difference(&results[1].1, &results[0].1).max(largest_difference(&results[2].1, &results[0].1));
    println!("flexible pendulum 10N, 1 s at 1e-2: steps bdf, adams, gen-alpha {steps:?}, Adams at 1e-4 {adams_tight}; tip positions within {spread:.1e} m");
    assert!((adams_tight as f64) < 1.25 * steps[1] as f64, "Adams' steps follow the tolerance: {} at 1e-2, {adams_tight} at 1e-4", steps[1]);
    assert!(steps[1] > 2 * steps[0] && steps[1] > 2 * steps[2], "{steps:?}");
    assert!(spread < 5e-3, "the methods disagree by {spread} m");
}
