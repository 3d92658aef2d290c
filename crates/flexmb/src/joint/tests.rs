//! Identity tests of the primitive constraint equations (formulation.md §6, §9): at random states of two
//! moving rigid bodies (and of one body against ground), with marker offsets and axes that are not
//! trivial and nonzero velocities,
//!
//! - (a) the rows of `B = Φ_q T` (the marker Jacobians applied to the equation coefficients) equal central
//!   differences of `Φ` under virtual displacements `δR` and body-frame rotations `A ← A exp(δπ̄~)`;
//! - (b) `Φ̇ = B v + Φ_t` equals the time derivative of `Φ` along the motion `Ṙ = V`, `Ȧ = A ω̄~`;
//! - (c) `Φ̈ = B v̇ + accel_bias` (so `γ = −accel_bias`) equals the derivative of `Φ̇` along a motion with
//!   accelerations `v̇`;
//! - (d) `Φ_t = ∂Φ/∂t` for the equations with a time law;
//!
//! and every named joint has its documented number of equations, all of which vanish when the two markers
//! are placed as the joint allows.

use crate::body::{InitialState, Marker, RigidBody};
use crate::data::Data;
use crate::function::TimeFunction;
use crate::joint::{Axis, EquationTerms, Joint, JointKind};
use crate::math::{EulerParameters, Mat3, Vec3, Vec4};
use crate::model::{BodyRef, MarkerId, Model, ModelBuilder};
use crate::stage::{constraint_equations, jacobian_entries, kinematics, update_angle_references};
use crate::test_support::{quat_mul, turn_body_frame, Lcg};

fn rot(axis: Vec3, angle: f64) -> Mat3 {
    EulerParameters::from_axis_angle(&axis, angle).unwrap().rotation_matrix()
}

fn rigid_body(name: &str, pose: (Vec3, EulerParameters)) -> RigidBody {
    RigidBody {
        name: name.into(),
        mass: 1.0,
        center_of_mass: Vec3::zeros(),
        inertia: Mat3::identity(),
        initial: InitialState { position: pose.0, orientation: pose.1, velocity: None, angular_velocity: None },
    }
}

fn add_marker(b: &mut ModelBuilder, name: &str, body: BodyRef, origin: Vec3, axes: Mat3) -> MarkerId {
    b.add_marker(Marker { name: name.into(), body, origin, axes }).unwrap()
}

const DISTANCE_LAW: &str = "0.8 + 0.3*sin(1.7*t)";
const ANGLE_LAW: &str = "0.5*sin(2*t) + 0.3*t + 0.1*t^2";
const DISPLACEMENT_LAW: &str = "0.2 + 0.1*cos(3*t) - 0.05*t^2";

/// Every primitive equation, as the one-equation joint kinds plus a spherical joint for `Point(k)`.
fn primitive_kinds() -> Vec<JointKind> {
    use Axis::*;
    let mut kinds = vec![JointKind::Spherical];
    for a in [X, Y, Z] {
        for b in [X, Y, Z] {
            kinds.push(JointKind::Dot1 { axis_i: a, axis_j: b });
        }
    }
    for a in [X, Y, Z] {
        kinds.push(JointKind::Dot2 { axis_i: a });
    }
    kinds.push(JointKind::Distance { length: TimeFunction::parse(DISTANCE_LAW).unwrap() });
    kinds.push(JointKind::AngleDriver { function: TimeFunction::parse(ANGLE_LAW).unwrap() });
    kinds.push(JointKind::DisplacementDriver { function: TimeFunction::parse(DISPLACEMENT_LAW).unwrap() });
    kinds
}

/// Two bodies with a marker each (random offset and axes) and a ground marker; every primitive between
/// body–body, ground–body and body–ground.
fn primitives_model(rng: &mut Lcg) -> Model {
    let mut b = ModelBuilder::new("primitives");
    let b1 = b.add_body(rigid_body("b1", (Vec3::zeros(), EulerParameters::identity()))).unwrap();
    let b2 = b.add_body(rigid_body("b2", (Vec3::zeros(), EulerParameters::identity()))).unwrap();
    let m1 = add_marker(&mut b, "m1", BodyRef::Body(b1), rng.vec3(0.6), rng.rotation().rotation_matrix());
    let m2 = add_marker(&mut b, "m2", BodyRef::Body(b2), rng.vec3(0.6), rng.rotation().rotation_matrix());
    let g = add_marker(&mut b, "g", BodyRef::Ground, rng.vec3(1.0), rng.rotation().rotation_matrix());
    let mut n = 0;
    for (i, j) in [(m1, m2), (g, m2), (m1, g)] {
        for kind in primitive_kinds() {
            b.add_joint(Joint { name: format!("j{n}"), kind, marker_i: i, marker_j: j }).unwrap();
            n += 1;
        }
    }
    b.build().unwrap()
}

/// A random state `(q, v)` of all bodies of `model`: positions ~1 m, speeds ~1 m/s, rates ~2 rad/s.
fn random_state(model: &Model, rng: &mut Lcg) -> (Vec<f64>, Vec<f64>) {
    let l = model.layout();
    let mut q = vec![0.0; l.nq];
    let mut v = vec![0.0; l.nv];
    for b in 0..l.n_bodies() {
        let (qr, vr) = (l.q_span(b), l.v_span(b));
        q[qr.start..qr.start + 3].copy_from_slice(rng.vec3(1.0).as_slice());
        q[qr.start + 3..qr.end].copy_from_slice(rng.rotation().0.as_slice());
        v[vr.start..vr.start + 3].copy_from_slice(rng.vec3(1.0).as_slice());
        v[vr.start + 3..vr.end].copy_from_slice(rng.vec3(2.0).as_slice());
    }
    (q, v)
}

/// All equation terms at `(t, q, v)` (angle references left as they are in `data`).
fn terms_at(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64]) -> Vec<EquationTerms> {
    kinematics(model, data, q, v);
    constraint_equations(model, data, t);
    data.equations.clone()
}

/// `Φ̇ = B v + Φ_t` of every row at `(t, q, v)` from `EquationTerms::rate`.
fn rates_at(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
    let terms = terms_at(model, data, t, q, v);
    (0..model.layout.nc)
        .map(|row| {
            let joint = &model.joints[model.layout.equations[row].0 .0];
            terms[row].rate(&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0])
        })
        .collect()
}

/// Dense `B` (rows: constraint rows, columns: velocity coordinates) at `(t, q)`.
fn dense_b(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64]) -> Vec<Vec<f64>> {
    terms_at(model, data, t, q, v);
    let mut b = vec![vec![0.0; model.layout.nv]; model.layout.nc];
    jacobian_entries(model, data, |r, c, x| b[r][c] += x);
    b
}

/// Positions after the virtual displacement `ε e_k` of velocity coordinate `k` of body `b`: `δR` for
/// `k < 3`, a body-frame rotation `δπ̄` for `k ≥ 3`.
fn displaced(model: &Model, q: &[f64], b: usize, k: usize, eps: f64) -> Vec<f64> {
    let mut out = q.to_vec();
    let o = model.layout.q_offset[b];
    if k < 3 {
        out[o + k] += eps;
    } else {
        let p = Vec4::from_column_slice(&q[o + 3..o + 7]);
        let p_new = turn_body_frame(&p, &Vec3::ith(k - 3, eps));
        out[o + 3..o + 7].copy_from_slice(p_new.as_slice());
    }
    out
}

/// The state at time `t0 + s` along `R(s) = R + s V + ½ s² V̇`, `ω̄(s) = ω̄ + s ω̄̇`, `A(s) = A exp((s ω̄ + ½ s² ω̄̇)~)`,
/// exact to `O(s³)` in `q` and `O(s²)` in `v`.
fn along_motion(model: &Model, q: &[f64], v: &[f64], vdot: &[f64], s: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut q1, mut v1) = (q.to_vec(), v.to_vec());
    for b in 0..model.layout.n_bodies() {
        let (qo, vo) = (model.layout.q_offset[b], model.layout.v_offset[b]);
        for k in 0..3 {
            q1[qo + k] += s * v[vo + k] + 0.5 * s * s * vdot[vo + k];
        }
        let w = Vec3::from_column_slice(&v[vo + 3..vo + 6]);
        let wd = Vec3::from_column_slice(&vdot[vo + 3..vo + 6]);
        let p = Vec4::from_column_slice(&q[qo + 3..qo + 7]);
        q1[qo + 3..qo + 7].copy_from_slice(turn_body_frame(&p, &(s * w + 0.5 * s * s * wd)).as_slice());
        for k in 0..6 {
            v1[vo + k] += s * vdot[vo + k];
        }
    }
    (q1, v1)
}

/// `|a − b| ≤ tol · max(1, |a|)`, with a message naming the row and the quantity.
fn check_close(model: &Model, what: &str, row: usize, analytic: f64, numeric: f64, tol: f64) -> f64 {
    let err = (analytic - numeric).abs() / analytic.abs().max(1.0);
    assert!(
        err <= tol,
        "{what} of {}: analytic {analytic:.12e}, finite difference {numeric:.12e}, relative error {err:.2e} > {tol:.0e}",
        model.describe_constraint_row(row)
    );
    err
}

/// The four identities (a)–(d) at several random states.
#[test]
fn primitive_equations_jacobian_rate_and_acceleration_bias_match_finite_differences() {
    let mut rng = Lcg(0x5eed_f1e7_0000_0001);
    let (mut worst_a, mut worst_b, mut worst_c, mut worst_d) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    for trial in 0..6 {
        let model = primitives_model(&mut rng);
        let mut data = Data::new(&model);
        let (q, v) = random_state(&model, &mut rng);
        let vdot: Vec<f64> = (0..model.layout.nv).map(|_| rng.range(-3.0, 3.0)).collect();
        let t = rng.range(0.0, 2.0);
        let nc = model.layout.nc;
        // Angle references at the current angles, so that no finite difference crosses a branch cut.
        kinematics(&model, &mut data, &q, &v);
        update_angle_references(&model, &mut data);
        let base = terms_at(&model, &mut data, t, &q, &v);
        let b = dense_b(&model, &mut data, t, &q, &v);
        assert!(base.iter().all(|e| e.phi.is_finite() && e.accel_bias.is_finite()), "finite Φ and γ at the base state");

        // (a) B = ∂Φ/∂(R, π̄), central differences with ε = 1e-6 (truncation ~ε², round-off ~1e-16/ε).
        let eps = 1e-6;
        for body in 0..model.layout.n_bodies() {
            for k in 0..6 {
                let plus = terms_at(&model, &mut data, t, &displaced(&model, &q, body, k, eps), &v);
                let minus = terms_at(&model, &mut data, t, &displaced(&model, &q, body, k, -eps), &v);
                for row in 0..nc {
                    let fd = (plus[row].phi - minus[row].phi) / (2.0 * eps);
                    let col = model.layout.v_offset[body] + k;
                    let what = format!("trial {trial}: ∂Φ/∂v[{col}] (body {body}, coordinate {k})");
                    worst_a = worst_a.max(check_close(&model, &what, row, b[row][col], fd, 1e-7));
                }
            }
        }

        // (b) Φ̇ along the motion with constant V, ω̄ (and t advancing), ε = 1e-6.
        let zero = vec![0.0; model.layout.nv];
        let rate = rates_at(&model, &mut data, t, &q, &v);
        let (qp, _) = along_motion(&model, &q, &v, &zero, eps);
        let (qm, _) = along_motion(&model, &q, &v, &zero, -eps);
        let plus = terms_at(&model, &mut data, t + eps, &qp, &v);
        let minus = terms_at(&model, &mut data, t - eps, &qm, &v);
        for row in 0..nc {
            let fd = (plus[row].phi - minus[row].phi) / (2.0 * eps);
            worst_b = worst_b.max(check_close(&model, &format!("trial {trial}: Φ̇"), row, rate[row], fd, 1e-7));
        }

        // (c) Φ̈ = B v̇ + accel_bias against the derivative of Φ̇ along a motion with accelerations v̇,
        // ε = 1e-5 (truncation ~ε² |Φ⁗|, round-off ~1e-16 |Φ̇|/ε).
        let eps2 = 1e-5;
        let (qp, vp) = along_motion(&model, &q, &v, &vdot, eps2);
        let (qm, vm) = along_motion(&model, &q, &v, &vdot, -eps2);
        let rp = rates_at(&model, &mut data, t + eps2, &qp, &vp);
        let rm = rates_at(&model, &mut data, t - eps2, &qm, &vm);
        for row in 0..nc {
            let fd = (rp[row] - rm[row]) / (2.0 * eps2);
            let analytic: f64 = b[row].iter().zip(&vdot).map(|(x, y)| x * y).sum::<f64>() + base[row].accel_bias;
            worst_c = worst_c.max(check_close(&model, &format!("trial {trial}: Φ̈"), row, analytic, fd, 1e-6));
        }

        // (d) Φ_t = ∂Φ/∂t at fixed q.
        let plus = terms_at(&model, &mut data, t + eps, &q, &v);
        let minus = terms_at(&model, &mut data, t - eps, &q, &v);
        for row in 0..nc {
            let fd = (plus[row].phi - minus[row].phi) / (2.0 * eps);
            worst_d = worst_d.max(check_close(&model, &format!("trial {trial}: Φ_t"), row, base[row].phi_t, fd, 1e-7));
        }
    }
    eprintln!("largest relative errors: B {worst_a:.2e}, Φ̇ {worst_b:.2e}, Φ̈ {worst_c:.2e}, Φ_t {worst_d:.2e}");
}

/// The time-law equations really depend on time: a check that (d) above is not vacuous.
#[test]
fn time_law_equations_have_nonzero_partial_time_derivative() {
    let mut rng = Lcg(0x0dd_ba11);
    let model = primitives_model(&mut rng);
    let mut data = Data::new(&model);
    let (q, v) = random_state(&model, &mut rng);
    let terms = terms_at(&model, &mut data, 0.7, &q, &v);
    for (row, (_, eq)) in model.layout.equations.iter().enumerate() {
        let timed = matches!(eq, super::Equation::Distance | super::Equation::Angle | super::Equation::Displacement);
        assert_eq!(
            terms[row].phi_t != 0.0,
            timed,
            "Φ_t = {} of {}: nonzero exactly for the equations with a time law",
            terms[row].phi_t,
            model.describe_constraint_row(row)
        );
    }
}

#[test]
fn hamilton_product_composes_rotation_matrices() {
    let mut rng = Lcg(42);
    for _ in 0..10 {
        let (p, r) = (rng.rotation().0, rng.rotation().0);
        let lhs = EulerParameters(quat_mul(&p, &r)).rotation_matrix();
        let rhs = EulerParameters(p).rotation_matrix() * EulerParameters(r).rotation_matrix();
        assert!((lhs - rhs).abs().max() < 1e-14, "A(p ⊗ r) − A(p) A(r) = {:e}", (lhs - rhs).abs().max());
    }
}

// ---------------------------------------------------------------------------------------------------------
// Named joints: equation counts and consistency.

/// Every named joint kind with the number of equations it must have.
fn named_kinds() -> Vec<(JointKind, usize)> {
    vec![
        (JointKind::Spherical, 3),
        (JointKind::Revolute, 5),
        (JointKind::Universal, 4),
        (JointKind::Cylindrical, 4),
        (JointKind::Translational, 5),
        (JointKind::Fixed, 6),
        (JointKind::Planar, 3),
        (JointKind::Distance { length: TimeFunction::parse(DISTANCE_LAW).unwrap() }, 1),
        (JointKind::PointOnLine, 2),
        (JointKind::PointInPlane, 1),
        (JointKind::Dot1 { axis_i: Axis::X, axis_j: Axis::Y }, 1),
        (JointKind::Dot1 { axis_i: Axis::Z, axis_j: Axis::Z }, 1),
        (JointKind::Dot2 { axis_i: Axis::Y }, 1),
        (JointKind::AngleDriver { function: TimeFunction::parse(ANGLE_LAW).unwrap() }, 1),
        (JointKind::DisplacementDriver { function: TimeFunction::parse(DISPLACEMENT_LAW).unwrap() }, 1),
    ]
}

#[test]
fn every_named_joint_has_its_number_of_equations() {
    let mut b = ModelBuilder::new("counts");
    let body = b.add_body(rigid_body("b", (Vec3::zeros(), EulerParameters::identity()))).unwrap();
    let g = add_marker(&mut b, "g", BodyRef::Ground, Vec3::zeros(), Mat3::identity());
    let m = add_marker(&mut b, "m", BodyRef::Body(body), Vec3::zeros(), Mat3::identity());
    let kinds = named_kinds();
    for (n, (kind, _)) in kinds.iter().enumerate() {
        b.add_joint(Joint { name: format!("j{n}"), kind: kind.clone(), marker_i: g, marker_j: m }).unwrap();
    }
    let model = b.build().unwrap();
    let mut total = 0;
    for (n, (kind, expected)) in kinds.iter().enumerate() {
        let rows = model.layout().joint_rows(crate::model::JointId(n)).expect("a joint of the model");
        assert_eq!(rows.len(), *expected, "{} joint: number of constraint rows", kind.keyword());
        assert_eq!(kind.equations().len(), *expected, "{} joint: number of primitive equations", kind.keyword());
        total += expected;
    }
    assert_eq!(model.layout().nc, total, "constraint rows of the model = sum over its joints");
}

/// Global frame `(origin, axes)` that marker `j` must have for the joint to hold, given marker `i`'s
/// global frame, at time `t`; free parameters of the joint's motion drawn from `rng`.
fn consistent_frame(kind: &JointKind, ri: Vec3, ai: Mat3, t: f64, rng: &mut Lcg) -> (Vec3, Mat3) {
    let (x, y, z) = (ai.column(0).into_owned(), ai.column(1).into_owned(), ai.column(2).into_owned());
    let about_z = |rng: &mut Lcg| ai * rot(Vec3::z(), rng.range(-3.0, 3.0));
    let any_axes = |rng: &mut Lcg| rng.rotation().rotation_matrix();
    match kind {
        JointKind::Spherical => (ri, any_axes(rng)),
        JointKind::Revolute => (ri, about_z(rng)),
        JointKind::Universal => {
            let a = ai * rot(Vec3::z(), rng.range(-3.0, 3.0)) * rot(Vec3::x(), std::f64::consts::FRAC_PI_2);
            (ri, a * rot(Vec3::z(), rng.range(-3.0, 3.0)))
        }
        JointKind::Cylindrical => (ri + rng.range(-1.0, 1.0) * z, about_z(rng)),
        JointKind::Translational => (ri + rng.range(-1.0, 1.0) * z, ai),
        JointKind::Fixed => (ri, ai),
        JointKind::Planar => (ri + rng.range(-1.0, 1.0) * x + rng.range(-1.0, 1.0) * y, about_z(rng)),
        JointKind::Distance { length } => (ri + length.eval(t)[0] * rng.unit(), any_axes(rng)),
        JointKind::PointOnLine => (ri + rng.range(-1.0, 1.0) * z, any_axes(rng)),
        JointKind::PointInPlane => (ri + rng.range(-1.0, 1.0) * x + rng.range(-1.0, 1.0) * y, any_axes(rng)),
        JointKind::Dot1 { axis_i, axis_j } => {
            // Axis `axis_j` of j along a random direction w ⟂ axis_i of i; the rest turned about it.
            let a = ai.column(axis_i.index()).into_owned();
            let w = a.cross(&rng.unit()).normalize();
            let e = Vec3::ith(axis_j.index(), 1.0);
            let align = rot(e.cross(&w), e.dot(&w).clamp(-1.0, 1.0).acos());
            (rng.vec3(1.0), align * rot(e, rng.range(-3.0, 3.0)))
        }
        JointKind::Dot2 { axis_i } => {
            let a = ai.column(axis_i.index()).into_owned();
            (ri + a.cross(&rng.unit()), any_axes(rng))
        }
        JointKind::AngleDriver { function } => (rng.vec3(1.0), ai * rot(Vec3::z(), function.eval(t)[0])),
        JointKind::DisplacementDriver { function } => {
            (ri + function.eval(t)[0] * z + rng.range(-1.0, 1.0) * x + rng.range(-1.0, 1.0) * y, any_axes(rng))
        }
    }
}

/// Where marker `i` and marker `j` sit in the consistency test.
#[derive(Clone, Copy, Debug)]
enum Placement {
    BodyBody,
    GroundBody,
    BodyGround,
}

/// A model with one joint of `kind` whose markers satisfy it, built from random poses and marker frames.
fn consistent_model(kind: &JointKind, placement: Placement, t: f64, rng: &mut Lcg) -> Model {
    let mut b = ModelBuilder::new("consistent");
    let (si, ai_local) = (rng.vec3(0.6), rng.rotation().rotation_matrix());
    let (sj, aj_local) = (rng.vec3(0.6), rng.rotation().rotation_matrix());
    let (r1, p1) = (rng.vec3(1.0), rng.rotation());
    let (ri, ai) = match placement {
        Placement::GroundBody => (rng.vec3(1.0), rng.rotation().rotation_matrix()),
        _ => (r1 + p1.rotation_matrix() * si, p1.rotation_matrix() * ai_local),
    };
    let (rj, aj) = consistent_frame(kind, ri, ai, t, rng);
    let (mi, mj) = match placement {
        Placement::GroundBody => {
            let mi = add_marker(&mut b, "i", BodyRef::Ground, ri, ai);
            // Body 2 posed so that its marker (sj, aj_local) lands on (rj, aj).
            let a2 = aj * aj_local.transpose();
            let p2 = EulerParameters::from_rotation_matrix(&a2).unwrap();
            let b2 = b.add_body(rigid_body("b2", (rj - a2 * sj, p2))).unwrap();
            (mi, add_marker(&mut b, "j", BodyRef::Body(b2), sj, aj_local))
        }
        Placement::BodyBody => {
            let b1 = b.add_body(rigid_body("b1", (r1, p1))).unwrap();
            let mi = add_marker(&mut b, "i", BodyRef::Body(b1), si, ai_local);
            let a2 = aj * aj_local.transpose();
            let p2 = EulerParameters::from_rotation_matrix(&a2).unwrap();
            let b2 = b.add_body(rigid_body("b2", (rj - a2 * sj, p2))).unwrap();
            (mi, add_marker(&mut b, "j", BodyRef::Body(b2), sj, aj_local))
        }
        Placement::BodyGround => {
            let b1 = b.add_body(rigid_body("b1", (r1, p1))).unwrap();
            let mi = add_marker(&mut b, "i", BodyRef::Body(b1), si, ai_local);
            (mi, add_marker(&mut b, "j", BodyRef::Ground, rj, aj))
        }
    };
    b.add_joint(Joint { name: "joint".into(), kind: kind.clone(), marker_i: mi, marker_j: mj }).unwrap();
    b.build().unwrap()
}

#[test]
fn joint_equations_vanish_when_markers_are_placed_as_the_joint_allows() {
    let mut rng = Lcg(0xc0ffee);
    let mut worst = 0.0_f64;
    for trial in 0..5 {
        for placement in [Placement::BodyBody, Placement::GroundBody, Placement::BodyGround] {
            for (kind, _) in named_kinds() {
                let t = rng.range(0.0, 1.5);
                let model = consistent_model(&kind, placement, t, &mut rng);
                let state = crate::analysis::State::initial(&model);
                let mut data = Data::new(&model);
                let terms = terms_at(&model, &mut data, t, &state.q, &state.v);
                for (row, terms) in terms.iter().enumerate() {
                    worst = worst.max(terms.phi.abs());
                    assert!(
                        terms.phi.abs() < 1e-12,
                        "trial {trial}, {placement:?}: Φ = {:e} (tolerance 1e-12, round-off of unit-size geometry) in {}",
                        terms.phi,
                        model.describe_constraint_row(row)
                    );
                }
            }
        }
    }
    eprintln!("largest |Φ| of consistently placed joints: {worst:.2e}");
}

/// The consistency test is not vacuous: the same joints with marker `j` displaced or turned a little do not hold.
#[test]
fn joint_equations_detect_a_misplaced_marker() {
    let mut rng = Lcg(0xbad_cafe);
    for (kind, _) in named_kinds() {
        let model = consistent_model(&kind, Placement::BodyBody, 0.4, &mut rng);
        let mut state = crate::analysis::State::initial(&model);
        let q = &mut state.q;
        // Body 2: shift and turn its frame.
        let o = model.layout.q_offset[1];
        for k in 0..3 {
            q[o + k] += 1e-3 * (k as f64 + 1.0);
        }
        let p = Vec4::from_column_slice(&q[o + 3..o + 7]);
        q[o + 3..o + 7].copy_from_slice(turn_body_frame(&p, &Vec3::new(2e-3, -3e-3, 1e-3)).as_slice());
        let mut data = Data::new(&model);
        let terms = terms_at(&model, &mut data, 0.4, &state.q, &state.v);
        let largest = terms.iter().map(|t| t.phi.abs()).fold(0.0, f64::max);
        assert!(largest > 1e-5, "{} joint: |Φ| = {largest:e} after a 1e-3 misplacement", kind.keyword());
    }
}
