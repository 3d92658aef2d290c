//! Eigen-analysis of constrained mechanisms in independent coordinates against closed forms: a
//! pendulum, a double pendulum, a sleeping top (precession and nutation), a tilting rotor's forward and
//! backward whirl, a clamped flexible body; and the identities: a symmetric reduced mass matrix (and
//! stiffness at a conservative equilibrium), and the state matrix against finite differences of the
//! forward dynamics.

mod support;

use std::f64::consts::TAU;
use std::sync::Arc;

use faer::Mat;
use flexmb::analysis::{
    displaced_positions, eigen_analysis, linearize, operating_point, reduce_to_independent, state_matrix, AccelerationSolver,
    EigenAnalysis, OperatingPointChoice, ReducedLinearization, Whirl,
};
use flexmb::force::{ForceElement, ForceKind};
use flexmb::function::TimeFunction;
use flexmb::joint::JointKind;
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyRef, Model, ModelBuilder};
use support::*;

/// The linearization at the initial state in independent coordinates, and its modes.
fn analyse(model: &Model) -> (ReducedLinearization, EigenAnalysis) {
    let model = Arc::new(model.clone());
    let mut point = operating_point(&model, OperatingPointChoice::Initial, &settings(1.0, 0.1, 1e-8)).unwrap();
    let lin = linearize(&model, &mut point.data, &point.state, &point.accelerations).unwrap();
    let reduced = reduce_to_independent(&model, &mut point.data, &point.state, &point.accelerations, &lin);
    let modes = eigen_analysis(&model, &point.state, &reduced).unwrap();
    (reduced, modes)
}

fn asymmetry(m: &Mat<f64>) -> f64 {
    let n = m.nrows();
    let big = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| m[(i, j)].abs()).fold(0.0, f64::max);
    (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| (m[(i, j)] - m[(j, i)]).abs()).fold(0.0, f64::max) / big
}

fn oscillating(modes: &EigenAnalysis) -> Vec<f64> {
    modes.modes.iter().filter(|m| !m.rigid_body).map(|m| m.frequency).collect()
}

/// A pendulum hanging at rest: one mode at `√(m g L / (I + m L²))`, undamped, no whirl.
#[test]
fn a_hanging_pendulum_swings_at_the_closed_form_frequency() {
    let (l, m, ic, g) = (0.8, 1.5, 0.02, 9.81);
    let model = pendulum(l, m, ic, 0.0, g).build().unwrap();
    let (reduced, modes) = analyse(&model);
    assert_eq!(reduced.degrees_of_freedom(), 1);
    assert_eq!(reduced.independent.names, vec!["bob.theta.z".to_string()]);
    let exact = (m * g * l / (ic + m * l * l)).sqrt() / TAU;
    let found = oscillating(&modes);
    let error = (found[0] - exact).abs() / exact;
    eprintln!("pendulum: {:.12} Hz against {exact:.12} Hz, relative error {error:.1e}", found[0]);
    assert!(found.len() == 1 && error < 1e-9, "{found:?} against {exact}");
    assert!(modes.modes[0].damping_ratio.abs() < 1e-9 && modes.modes[0].whirl == Whirl::None);
}

/// A planar double pendulum of two bodies with offset centres of mass, hanging at rest: the two roots of
/// `det(K − ω² M) = 0` with the absolute angles' `M = [I₁ + m₁c₁² + m₂L₁², m₂L₁c₂; m₂L₁c₂, I₂ + m₂c₂²]`,
/// `K = diag((m₁c₁ + m₂L₁) g, m₂c₂ g)`; the reduced `M_z` and `K_z` symmetric (a conservative
/// equilibrium).
#[test]
fn a_double_pendulum_has_the_two_closed_form_frequencies() {
    let (g, l1) = (9.81, 0.6);
    let (m1, c1, i1) = (1.2, 0.25, 0.03);
    let (m2, c2, i2) = (0.7, 0.3, 0.015);
    let model = double_pendulum(g, l1, (m1, c1, i1), (m2, c2, i2), None).build().unwrap();
    let (reduced, modes) = analyse(&model);
    let (a, b, d) = (i1 + m1 * c1 * c1 + m2 * l1 * l1, m2 * l1 * c2, i2 + m2 * c2 * c2);
    let (k1, k2) = ((m1 * c1 + m2 * l1) * g, m2 * c2 * g);
    // det([k1 − w a, −w b; −w b, k2 − w d]) = (ad − b²) w² − (k1 d + k2 a) w + k1 k2 = 0, w = ω².
    let (qa, qb, qc) = (a * d - b * b, -(k1 * d + k2 * a), k1 * k2);
    let root = (qb * qb - 4.0 * qa * qc).sqrt();
    let exact = [((-qb - root) / (2.0 * qa)).sqrt() / TAU, ((-qb + root) / (2.0 * qa)).sqrt() / TAU];
    let found = oscillating(&modes);
    assert_eq!(found.len(), 2, "{found:?}");
    let error = (0..2).map(|k| (found[k] - exact[k]).abs() / exact[k]).fold(0.0, f64::max);
    eprintln!("double pendulum: {found:?} Hz against {exact:?} Hz, largest relative error {error:.1e}");
    assert!(error < 1e-9);
    let (sm, sk) = (asymmetry(&reduced.mass), asymmetry(&reduced.stiffness));
    eprintln!("double pendulum: asymmetry of M_z {sm:.1e}, of K_z {sk:.1e}");
    assert!(sm < 1e-12 && sk < 1e-6, "{sm:.1e} {sk:.1e}");
}

/// The double pendulum with a spring–damper from the lower link to ground, at rest at its equilibrium
/// (the spring at its free length): the state matrix `A` against finite differences of the forward
/// dynamics `v̇(q, v)` moved along each independent coordinate and rate (`δz̈` read at the independent
/// coordinates, rotations in global axes).
#[test]
fn the_state_matrix_matches_finite_differences_of_the_forward_dynamics() {
    let model = double_pendulum(9.81, 0.6, (1.2, 0.25, 0.03), (0.7, 0.3, 0.015), Some((40.0, 0.8))).build().unwrap();
    let (reduced, _) = analyse(&model);
    let a = state_matrix(&reduced);
    let n = reduced.degrees_of_freedom();
    let arc = Arc::new(model.clone());
    let mut point = operating_point(&arc, OperatingPointChoice::Initial, &settings(1.0, 0.1, 1e-8)).unwrap();
    let (state, acc0) = (&point.state, &point.accelerations);
    let mut solver = AccelerationSolver::new(&model);
    let basis = &reduced.independent.basis;
    let delta = 1e-6;
    let mut worst = 0.0_f64;
    let scale = (0..2 * n).flat_map(|i| (0..2 * n).map(move |j| (i, j))).map(|(i, j)| a[(i, j)].abs()).fold(0.0, f64::max);
    for k in 0..2 * n {
        let column: Vec<f64> = (0..model.layout().nv).map(|r| basis[(r, k % n)] * delta).collect();
        let (q, v) = if k < n {
            (displaced_positions(&model, &state.q, &column).unwrap(), state.v.clone())
        } else {
            (state.q.clone(), column.clone())
        };
        let moved = solver.solve(&model, &mut point.data, state.t, &q, &v, &state.active).unwrap();
        let dvdot: Vec<f64> = moved.vdot.iter().zip(&acc0.vdot).map(|(x, y)| (x - y) / delta).collect();
        // Planar: the rotations are about z in body and global axes alike.
        for (i, &c) in reduced.independent.coordinates.iter().enumerate() {
            worst = worst.max((dvdot[c] - a[(n + i, k)]).abs() / scale);
        }
    }
    eprintln!("state matrix against finite differences: largest difference {worst:.1e} of its largest entry");
    assert!(worst < 1e-5, "{worst:.1e}");
}

/// A sleeping top (upright, spin `Ω` about its axis, tip in a spherical joint): precession and
/// nutation `ω = (I₃Ω ± √(I₃²Ω² − 4 I₁ m g l)) / (2 I₁)`, both turning with the spin (forward), and
/// the spin itself a rigid-body mode.
#[test]
fn a_sleeping_top_precesses_and_nutates_at_the_closed_form_frequencies() {
    let (m, l, i3, a, g, spin) = (0.5, 0.1, 6.25e-4, 3.5e-4, 9.81, 200.0);
    let mut b = ModelBuilder::new("sleeping top").gravity(Vec3::new(0.0, 0.0, -g));
    let top = b
        .add_body(rigid("top", m, Vec3::new(0.0, 0.0, l), Mat3::from_diagonal(&Vec3::new(a, a, i3)), Vec3::zeros(), EulerParameters::identity(), Some(Vec3::zeros()), Some(Vec3::new(0.0, 0.0, spin))))
        .unwrap();
    let support = marker(&mut b, "support", BodyRef::Ground, Vec3::zeros());
    let tip = marker(&mut b, "tip", BodyRef::Body(top), Vec3::zeros());
    joint(&mut b, "tip", JointKind::Spherical, support, tip);
    let (_, modes) = analyse(&b.build().unwrap());
    let i1 = a + m * l * l;
    let root = (i3 * i3 * spin * spin - 4.0 * i1 * m * g * l).sqrt();
    let exact = [(i3 * spin - root) / (2.0 * i1) / TAU, (i3 * spin + root) / (2.0 * i1) / TAU];
    let found: Vec<_> = modes.modes.iter().filter(|m| !m.rigid_body).collect();
    assert_eq!(found.len(), 2);
    assert_eq!(modes.modes.iter().filter(|m| m.rigid_body).count(), 1);
    let error = (0..2).map(|k| (found[k].frequency - exact[k]).abs() / exact[k]).fold(0.0, f64::max);
    eprintln!(
        "sleeping top: {:.10} and {:.10} Hz against {:.10} and {:.10} Hz, largest relative error {error:.1e}; whirl {} {}",
        found[0].frequency, found[1].frequency, exact[0], exact[1], found[0].whirl.label(), found[1].whirl.label()
    );
    assert!(error < 1e-10);
    assert!(found.iter().all(|m| m.whirl == Whirl::Forward && m.damping_ratio.abs() < 1e-7));
}

/// A tilting rotor: a disk driven at `Ω` in a revolute on a housing that tilts on a spherical joint,
/// held by four vertical springs (tilt stiffness `k_θ = 2 k a²` about x and y) and a horizontal one
/// (torsion `k b²` about z). Forward and backward whirl `ω = (±I_pΩ + √(I_p²Ω² + 4 I_t k_θ)) / (2 I_t)`
/// (`I_t` the disk's and the housing's transverse inertia, `I_p` the disk's polar one), and the
/// housing's torsion `√(k b² / (I_zz,housing + I_p))` with no whirl.
#[test]
fn a_tilting_rotor_whirls_forward_and_backward_at_the_closed_form_frequencies() {
    let (spin, k, a, bz, ls) = (300.0, 2.0e4, 0.1, 0.15, 0.2);
    let (disk_t, disk_p, housing_t, housing_z) = (0.02, 0.035, 0.01, 0.012);
    let mut b = ModelBuilder::new("tilting rotor");
    let housing = b
        .add_body(rigid("housing", 2.0, Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(housing_t, housing_t, housing_z)), Vec3::zeros(), EulerParameters::identity(), None, None))
        .unwrap();
    let disk = b
        .add_body(rigid("disk", 5.0, Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(disk_t, disk_t, disk_p)), Vec3::zeros(), EulerParameters::identity(), None, Some(Vec3::new(0.0, 0.0, spin))))
        .unwrap();
    let origin = marker(&mut b, "origin", BodyRef::Ground, Vec3::zeros());
    let h0 = marker(&mut b, "housing_centre", BodyRef::Body(housing), Vec3::zeros());
    let d0 = marker(&mut b, "disk_centre", BodyRef::Body(disk), Vec3::zeros());
    joint(&mut b, "pivot", JointKind::Spherical, origin, h0);
    joint(&mut b, "bearing", JointKind::Revolute, h0, d0);
    let motor = JointKind::AngleDriver { function: TimeFunction::parse(&format!("{spin}*t")).unwrap() };
    joint(&mut b, "motor", motor, h0, d0);
    let spring = |b: &mut ModelBuilder, name: &str, on_housing: Vec3, on_ground: Vec3| {
        let i = marker(b, &format!("{name}_ground"), BodyRef::Ground, on_ground);
        let j = marker(b, &format!("{name}_housing"), BodyRef::Body(housing), on_housing);
        let kind = ForceKind::TranslationalSpringDamper { marker_i: i, marker_j: j, stiffness: k, damping: 0.0, free_length: ls, actuator: None };
        b.add_force(ForceElement { name: name.into(), kind }).unwrap();
    };
    for (name, x, y) in [("s1", a, 0.0), ("s2", -a, 0.0), ("s3", 0.0, a), ("s4", 0.0, -a)] {
        spring(&mut b, name, Vec3::new(x, y, 0.0), Vec3::new(x, y, -ls));
    }
    spring(&mut b, "torsion", Vec3::new(bz, 0.0, 0.0), Vec3::new(bz, -ls, 0.0));
    let (_, modes) = analyse(&b.build().unwrap());
    let (it, ip, ktheta) = (disk_t + housing_t, disk_p, 2.0 * k * a * a);
    let root = (ip * ip * spin * spin + 4.0 * it * ktheta).sqrt();
    let backward = (root - ip * spin) / (2.0 * it) / TAU;
    let forward = (root + ip * spin) / (2.0 * it) / TAU;
    let torsion = (k * bz * bz / (housing_z + disk_p)).sqrt() / TAU;
    let found: Vec<_> = modes.modes.iter().filter(|m| !m.rigid_body).collect();
    for m in &found {
        eprintln!("tilting rotor: {:.10} Hz, whirl {}, damping {:.1e}", m.frequency, m.whirl.label(), m.damping_ratio);
    }
    assert_eq!(found.len(), 3);
    let pick = |f: f64| found.iter().min_by(|x, y| (x.frequency - f).abs().total_cmp(&(y.frequency - f).abs())).unwrap();
    let (b_mode, f_mode, t_mode) = (pick(backward), pick(forward), pick(torsion));
    let error = [(b_mode.frequency, backward), (f_mode.frequency, forward), (t_mode.frequency, torsion)]
        .iter()
        .map(|(x, e)| (x - e).abs() / e)
        .fold(0.0, f64::max);
    eprintln!("tilting rotor: backward {backward:.10}, forward {forward:.10}, torsion {torsion:.10} Hz; largest relative error {error:.1e}");
    assert!(error < 1e-7);
    assert_eq!((b_mode.whirl, f_mode.whirl, t_mode.whirl), (Whirl::Backward, Whirl::Forward, Whirl::None));
}

/// A planar double pendulum (revolutes about global z through the origin and the end of the first
/// link, gravity −y), at rest hanging; link `(mass, centre of mass from its pivot, inertia about the
/// centre)`; optionally a spring–damper `(k, c)` from the second link's centre to a ground point below
/// it, at its free length.
fn double_pendulum(g: f64, l1: f64, (m1, c1, i1): (f64, f64, f64), (m2, c2, i2): (f64, f64, f64), spring: Option<(f64, f64)>) -> ModelBuilder {
    let mut b = ModelBuilder::new("double pendulum").gravity(Vec3::new(0.0, -g, 0.0));
    let inertia = |i: f64| Mat3::from_diagonal(&Vec3::new(i, i, i));
    let p = EulerParameters::identity();
    let link1 = b.add_body(rigid("link1", m1, Vec3::zeros(), inertia(i1), Vec3::new(0.0, -c1, 0.0), p, None, None)).unwrap();
    let link2 = b.add_body(rigid("link2", m2, Vec3::zeros(), inertia(i2), Vec3::new(0.0, -l1 - c2, 0.0), p, None, None)).unwrap();
    let o = marker(&mut b, "o", BodyRef::Ground, Vec3::zeros());
    let top1 = marker(&mut b, "top1", BodyRef::Body(link1), Vec3::new(0.0, c1, 0.0));
    let end1 = marker(&mut b, "end1", BodyRef::Body(link1), Vec3::new(0.0, c1 - l1, 0.0));
    let top2 = marker(&mut b, "top2", BodyRef::Body(link2), Vec3::new(0.0, c2, 0.0));
    joint(&mut b, "shoulder", JointKind::Revolute, o, top1);
    joint(&mut b, "elbow", JointKind::Revolute, end1, top2);
    if let Some((k, c)) = spring {
        let anchor = marker(&mut b, "anchor", BodyRef::Ground, Vec3::new(0.3, -l1 - c2, 0.0));
        let centre = marker(&mut b, "centre2", BodyRef::Body(link2), Vec3::zeros());
        let kind = ForceKind::TranslationalSpringDamper { marker_i: anchor, marker_j: centre, stiffness: k, damping: c, free_length: 0.3, actuator: None };
        b.add_force(ForceElement { name: "spring".into(), kind }).unwrap();
    }
    b
}
