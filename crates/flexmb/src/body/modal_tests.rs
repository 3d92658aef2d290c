//! Identity tests of flexible bodies (formulation.md §9) on random lumped-mass bodies, checked against
//! node-by-node kinematics computed here:
//!
//! - the mass matrix from the invariants equals `Σ mᵢ Jᵢᵀ Jᵢ` (plus the nodes' rotary inertia);
//! - `M v̇ + h(q, v)` equals `Tᵀ (d/dt ∂L/∂q̇ − ∂L/∂q)` of `L = ½ Σ mᵢ |Ṙᵢ|² + ½ Σ Ωᵢᵀ Jᵢ Ωᵢ`, by
//!   finite differences;
//! - joint equations at nodes: `B` against finite differences of `Φ`, `Φ̇ = B v + Φ_t`, and
//!   `Φ̈ = B v̇ + bias`;
//! - a flexible body without modes moves exactly as the rigid body of the same mass properties;
//! - a free, undamped flexible body keeps linear and angular momentum and total energy;
//! - geometric stiffening adds `Σ f_k G_k a` and its exact acceleration columns.

use nalgebra::{DMatrix, DVector, Matrix3xX};

use crate::analysis::{simulate, SimulationSettings};
use crate::body::{InitialState, LumpedNode, Marker, ModalBody, ModalInvariants, ModalNode, RigidBody};
use crate::data::Data;
use crate::integrate::Tolerances;
use crate::joint::{Joint, JointKind};
use crate::math::euler_parameters::{g_matrix, rotation_matrix};
use crate::math::{skew, EulerParameters, Mat3, Vec3, Vec4};
use crate::model::{BodyId, BodyRef, Model, ModelBuilder, OutputKind};
use crate::stage::{body_mass_entries, constraint_equations, inertia_forces, jacobian_entries, kinematics};
use crate::test_support::Lcg;

fn random_nodes(rng: &mut Lcg, n: usize, m: usize, rotary: bool) -> Vec<LumpedNode> {
    (0..n)
        .map(|_| {
            let r = rng.vec3(0.3);
            let rotary = if rotary { Mat3::from_diagonal(&Vec3::new(1.0, 2.0, 1.5)) * 1e-3 + r * r.transpose() * 1e-3 } else { Mat3::zeros() };
            LumpedNode {
                position: rng.vec3(0.5),
                mass: rng.range(0.1, 1.0),
                rotary_inertia: rotary,
                psi: Matrix3xX::from_fn(m, |_, _| rng.range(-0.3, 0.3)),
                theta: Matrix3xX::from_fn(m, |_, _| rng.range(-0.5, 0.5)),
            }
        })
        .collect()
}

fn modal_body(nodes: &[LumpedNode], m: usize, rng: &mut Lcg) -> ModalBody {
    let r = DMatrix::from_fn(m, m, |_, _| rng.range(-1.0, 1.0));
    let stiffness = &r * r.transpose() * 50.0 + DMatrix::identity(m, m) * 200.0;
    ModalBody::from_lumped_nodes(nodes, stiffness).unwrap()
}

/// One free flexible body (no joints, no gravity).
fn free_body_model(nodes: &[LumpedNode], m: usize, rng: &mut Lcg) -> Model {
    let mut b = ModelBuilder::new("free flexible body");
    let body = modal_body(nodes, m, rng);
    b.add_flexible_body("flex", InitialState::default(), body).unwrap();
    b.build().unwrap()
}

/// A random state of body 0: `q`, `v`, and `v̇`.
fn random_state(model: &Model, rng: &mut Lcg) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let l = &model.layout;
    let mut q = vec![0.0; l.nq];
    let v: Vec<f64> = (0..l.nv).map(|_| rng.range(-1.0, 1.0)).collect();
    let vdot: Vec<f64> = (0..l.nv).map(|_| rng.range(-1.0, 1.0)).collect();
    for b in 0..model.bodies.len() {
        let qo = l.q_offset[b];
        q[qo..qo + 3].copy_from_slice(rng.vec3(1.0).as_slice());
        q[qo + 3..qo + 7].copy_from_slice(rng.rotation().0.as_slice());
        for k in 0..l.modes[b] {
            q[qo + 7 + k] = rng.range(-0.2, 0.2);
        }
    }
    (q, v, vdot)
}

/// Kinetic energy `½ Σ mᵢ |Ṙᵢ|² + ½ Σ Ωᵢᵀ Jᵢ Ωᵢ` of body 0 at `q`, `q̇` (any `p`; `ω̄ = 2 G(p) ṗ`).
fn kinetic_energy(nodes: &[LumpedNode], m: usize, q: &[f64], qd: &[f64]) -> f64 {
    let p = Vec4::from_column_slice(&q[3..7]);
    let a_mat = rotation_matrix(&p);
    let w = 2.0 * g_matrix(&p) * Vec4::from_column_slice(&qd[3..7]);
    let r_dot = Vec3::from_column_slice(&qd[0..3]);
    let a = DVector::from_column_slice(&q[7..7 + m]);
    let ad = DVector::from_column_slice(&qd[7..7 + m]);
    nodes
        .iter()
        .map(|n| {
            let r_bar: Vec3 = n.position + &n.psi * &a;
            let u_dot: Vec3 = &n.psi * &ad;
            let vel = r_dot + a_mat * (w.cross(&r_bar) + u_dot);
            let omega: Vec3 = w + &n.theta * &ad;
            0.5 * n.mass * vel.norm_squared() + 0.5 * omega.dot(&(n.rotary_inertia * omega))
        })
        .sum()
}

#[test]
fn mass_matrix_from_invariants_equals_the_node_sum() {
    let mut rng = Lcg(0xf1e5_0001);
    for rotary in [false, true] {
        let m = 3;
        let nodes = random_nodes(&mut rng, 7, m, rotary);
        let model = free_body_model(&nodes, m, &mut rng);
        let mut data = Data::new(&model);
        let (q, v, _) = random_state(&model, &mut rng);
        kinematics(&model, &mut data, &q, &v);
        let n = 6 + m;
        let mut mass = DMatrix::<f64>::zeros(n, n);
        body_mass_entries(&model, &data, 0, |r, c, x| mass[(r, c)] += x);
        let a_mat = data.bodies[0].rotation;
        let a = DVector::from_column_slice(&q[7..7 + m]);
        let mut reference = DMatrix::zeros(n, n);
        for node in &nodes {
            let r_bar: Vec3 = node.position + &node.psi * &a;
            let mut j = DMatrix::zeros(3, n);
            j.view_mut((0, 0), (3, 3)).copy_from(&Mat3::identity());
            j.view_mut((0, 3), (3, 3)).copy_from(&(-a_mat * skew(&r_bar)));
            j.view_mut((0, 6), (3, m)).copy_from(&(a_mat * &node.psi));
            reference += node.mass * j.transpose() * &j;
            let mut jr = DMatrix::zeros(3, n);
            jr.view_mut((0, 3), (3, 3)).copy_from(&Mat3::identity());
            jr.view_mut((0, 6), (3, m)).copy_from(&node.theta);
            let rot = DMatrix::from_fn(3, 3, |r, c| node.rotary_inertia[(r, c)]);
            reference += jr.transpose() * rot * &jr;
        }
        let error = (&mass - &reference).amax() / reference.amax();
        assert!(error < 1e-13, "rotary {rotary}: relative error {error:.2e}");
    }
}

#[test]
fn inertia_forces_equal_lagranges_equations_of_the_node_kinetic_energy() {
    let mut rng = Lcg(0xf1e5_0002);
    for rotary in [false, true] {
        let m = 3;
        let nodes = random_nodes(&mut rng, 6, m, rotary);
        let model = free_body_model(&nodes, m, &mut rng);
        let mut data = Data::new(&model);
        let (q, v, vdot) = random_state(&model, &mut rng);
        kinematics(&model, &mut data, &q, &v);
        inertia_forces(&model, &mut data, &vdot);
        let ours = data.inertia.clone();

        // q̇ = T v, q̈ = T v̇ + Ṫ v.
        let p = Vec4::from_column_slice(&q[3..7]);
        let w = Vec3::from_column_slice(&v[3..6]);
        let wd = Vec3::from_column_slice(&vdot[3..6]);
        let p_dot = 0.5 * g_matrix(&p).transpose() * w;
        let p_ddot = 0.5 * g_matrix(&p_dot).transpose() * w + 0.5 * g_matrix(&p).transpose() * wd;
        let nq = 7 + m;
        let mut qd = vec![0.0; nq];
        let mut qdd = vec![0.0; nq];
        qd[0..3].copy_from_slice(&v[0..3]);
        qdd[0..3].copy_from_slice(&vdot[0..3]);
        qd[3..7].copy_from_slice(p_dot.as_slice());
        qdd[3..7].copy_from_slice(p_ddot.as_slice());
        qd[7..].copy_from_slice(&v[6..]);
        qdd[7..].copy_from_slice(&vdot[6..]);

        let t = |q: &[f64], qd: &[f64]| kinetic_energy(&nodes, m, q, qd);
        let eta = 1e-5;
        let partial = |q: &[f64], qd: &[f64], k: usize, wrt_rate: bool| {
            let (mut a, mut b) = (q.to_vec(), qd.to_vec());
            let (mut c, mut d) = (q.to_vec(), qd.to_vec());
            if wrt_rate {
                b[k] += eta;
                d[k] -= eta;
            } else {
                a[k] += eta;
                c[k] -= eta;
            }
            (t(&a, &b) - t(&c, &d)) / (2.0 * eta)
        };
        let shifted = |s: f64| -> (Vec<f64>, Vec<f64>) {
            let qs: Vec<f64> = (0..nq).map(|k| q[k] + s * qd[k] + 0.5 * s * s * qdd[k]).collect();
            let qds: Vec<f64> = (0..nq).map(|k| qd[k] + s * qdd[k]).collect();
            (qs, qds)
        };
        // d/dt ∂L/∂q̇ by central differences along the motion, Richardson-extrapolated in the step.
        let time_derivative = |k: usize, eps: f64| {
            let (qp, qdp) = shifted(eps);
            let (qm, qdm) = shifted(-eps);
            (partial(&qp, &qdp, k, true) - partial(&qm, &qdm, k, true)) / (2.0 * eps)
        };
        let f_q: Vec<f64> = (0..nq)
            .map(|k| (4.0 * time_derivative(k, 5e-4) - time_derivative(k, 1e-3)) / 3.0 - partial(&q, &qd, k, false))
            .collect();
        // Tᵀ F_q: translation as is, rotation ½ G F_p, modes as is.
        let g = g_matrix(&p);
        let f_p = Vec4::from_column_slice(&f_q[3..7]);
        let f_rot = 0.5 * g * f_p;
        let mut reference = vec![0.0; 6 + m];
        reference[0..3].copy_from_slice(&f_q[0..3]);
        reference[3..6].copy_from_slice(f_rot.as_slice());
        reference[6..].copy_from_slice(&f_q[7..]);
        let scale = reference.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        let mut worst = 0.0_f64;
        for k in 0..6 + m {
            let error = (ours[k] - reference[k]).abs() / scale;
            worst = worst.max(error);
            assert!(error < 1e-7, "rotary {rotary}, row {k}: ours {}, Lagrange {}", ours[k], reference[k]);
        }
        println!("rotary inertia {rotary}: largest difference from Lagrange's equations {worst:.1e} (relative)");
    }
}

/// A flexible body held at its nodes by a spherical joint to ground, a revolute to a rigid body, a
/// cylindrical and a universal joint to ground, a distance joint to the rigid body and an angle driver:
/// joint equations at nodes, translational and rotational (the model is over-constrained, which does
/// not matter for the identities).
fn jointed_model(rng: &mut Lcg) -> Model {
    let m = 3;
    let nodes = random_nodes(rng, 6, m, true);
    let mut b = ModelBuilder::new("jointed flexible body").gravity(Vec3::new(0.0, 0.0, -9.81));
    let flex = b.add_flexible_body("flex", InitialState::default(), modal_body(&nodes, m, rng)).unwrap();
    let rigid = b.add_body(RigidBody {
        name: "link".into(),
        mass: 1.0,
        center_of_mass: Vec3::new(0.1, 0.0, 0.0),
        inertia: Mat3::from_diagonal(&Vec3::new(0.01, 0.02, 0.02)),
        initial: InitialState::default(),
    }).unwrap();
    let axes = |rng: &mut Lcg| rng.rotation().rotation_matrix();
    let n0 = b.add_node_marker("n0", flex, 0, axes(rng)).unwrap();
    let n1 = b.add_node_marker("n1", flex, 1, axes(rng)).unwrap();
    let n2 = b.add_node_marker("n2", flex, 2, axes(rng)).unwrap();
    let n3 = b.add_node_marker("n3", flex, 3, axes(rng)).unwrap();
    let ground = b.add_marker(Marker { name: "g".into(), body: BodyRef::Ground, origin: rng.vec3(0.5), axes: axes(rng) }).unwrap();
    let ground2 = b.add_marker(Marker { name: "g2".into(), body: BodyRef::Ground, origin: rng.vec3(0.5), axes: axes(rng) }).unwrap();
    let on_link = b.add_marker(Marker { name: "l".into(), body: BodyRef::Body(rigid), origin: rng.vec3(0.2), axes: axes(rng) }).unwrap();
    b.add_joint(Joint { name: "ball".into(), kind: JointKind::Spherical, marker_i: n0, marker_j: ground }).unwrap();
    b.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: n1, marker_j: on_link }).unwrap();
    b.add_joint(Joint { name: "slide".into(), kind: JointKind::Cylindrical, marker_i: ground2, marker_j: n2 }).unwrap();
    b.add_joint(Joint { name: "cross".into(), kind: JointKind::Universal, marker_i: n3, marker_j: ground }).unwrap();
    let n4 = b.add_node_marker("n4", flex, 4, axes(rng)).unwrap();
    let n5 = b.add_node_marker("n5", flex, 5, axes(rng)).unwrap();
    let length = crate::function::TimeFunction::parse("0.7").unwrap();
    b.add_joint(Joint { name: "rod".into(), kind: JointKind::Distance { length }, marker_i: n4, marker_j: on_link }).unwrap();
    let angle = crate::function::TimeFunction::parse("0.2").unwrap();
    b.add_joint(Joint { name: "turn".into(), kind: JointKind::AngleDriver { function: angle }, marker_i: ground2, marker_j: n5 }).unwrap();
    b.add_output("tip", OutputKind::MarkerPosition(n3)).unwrap();
    b.build().unwrap()
}

/// `q` advanced by the velocity-space step `s·δv` (body-frame rotation `A ← A exp(s δω̄~)`) plus
/// `½ s² δv̇` on the translations and modes, and `exp(s δω̄ + ½ s² δω̇)` on the rotation.
fn advance(model: &Model, q: &[f64], dv: &[f64], dvdot: &[f64], s: f64) -> Vec<f64> {
    let l = &model.layout;
    let mut out = q.to_vec();
    for b in 0..model.bodies.len() {
        let (qo, vo) = (l.q_offset[b], l.v_offset[b]);
        for k in 0..3 {
            out[qo + k] = q[qo + k] + s * dv[vo + k] + 0.5 * s * s * dvdot[vo + k];
        }
        let w = Vec3::from_column_slice(&dv[vo + 3..vo + 6]);
        let wd = Vec3::from_column_slice(&dvdot[vo + 3..vo + 6]);
        let p = Vec4::from_column_slice(&q[qo + 3..qo + 7]);
        out[qo + 3..qo + 7].copy_from_slice(crate::test_support::turn_body_frame(&p, &(s * w + 0.5 * s * s * wd)).as_slice());
        for k in 0..l.modes[b] {
            out[qo + 7 + k] = q[qo + 7 + k] + s * dv[vo + 6 + k] + 0.5 * s * s * dvdot[vo + 6 + k];
        }
    }
    out
}

fn phi(model: &Model, data: &mut Data, q: &[f64], v: &[f64]) -> Vec<f64> {
    kinematics(model, data, q, v);
    constraint_equations(model, data, 0.0);
    data.equations.iter().map(|e| e.phi).collect()
}

#[test]
fn joint_jacobians_at_nodes_match_finite_differences() {
    let mut rng = Lcg(0xf1e5_0003);
    let model = jointed_model(&mut rng);
    let mut data = Data::new(&model);
    let (q, v, vdot) = random_state(&model, &mut rng);
    let (nv, nc) = (model.layout.nv, model.layout.nc);
    kinematics(&model, &mut data, &q, &v);
    constraint_equations(&model, &mut data, 0.0);
    let mut b = DMatrix::<f64>::zeros(nc, nv);
    jacobian_entries(&model, &data, |r, c, x| b[(r, c)] += x);
    let rates: Vec<f64> = (0..nc)
        .map(|r| {
            let (j, _) = model.layout.equations[r];
            let joint = &model.joints[j.0];
            data.equations[r].rate(&data.markers[joint.marker_i.0], &data.markers[joint.marker_j.0])
        })
        .collect();
    let bias: Vec<f64> = data.equations.iter().map(|e| e.accel_bias).collect();
    let zero = vec![0.0; nv];
    // (a) columns of B: central differences of Φ along each velocity direction.
    let h = 1e-6;
    for c in 0..nv {
        let mut dv = vec![0.0; nv];
        dv[c] = 1.0;
        let plus = phi(&model, &mut data, &advance(&model, &q, &dv, &zero, h), &v);
        let minus = phi(&model, &mut data, &advance(&model, &q, &dv, &zero, -h), &v);
        for r in 0..nc {
            let fd = (plus[r] - minus[r]) / (2.0 * h);
            assert!((fd - b[(r, c)]).abs() < 1e-7 * (1.0 + fd.abs()), "{}: column {c}: B {} vs FD {fd}", model.describe_constraint_row(r), b[(r, c)]);
        }
    }
    // (b) Φ̇ = B v along the motion, (c) Φ̈ = B v̇ + bias.
    let s = 1e-4;
    let p1 = phi(&model, &mut data, &advance(&model, &q, &v, &vdot, s), &v);
    let p0 = phi(&model, &mut data, &q, &v);
    let m1 = phi(&model, &mut data, &advance(&model, &q, &v, &vdot, -s), &v);
    for r in 0..nc {
        let first = (p1[r] - m1[r]) / (2.0 * s);
        let second = (p1[r] - 2.0 * p0[r] + m1[r]) / (s * s);
        let bv: f64 = (0..nv).map(|c| b[(r, c)] * v[c]).sum();
        let bvdot: f64 = (0..nv).map(|c| b[(r, c)] * vdot[c]).sum();
        assert!((first - rates[r]).abs() < 1e-6 * (1.0 + first.abs()), "{}: rate {} vs FD {first}", model.describe_constraint_row(r), rates[r]);
        assert!((bv - rates[r]).abs() < 1e-12 * (1.0 + bv.abs()), "rate equals B v");
        assert!(
            (second - (bvdot + bias[r])).abs() < 1e-4 * (1.0 + second.abs()),
            "{}: B v̇ + bias {} vs FD {second}",
            model.describe_constraint_row(r),
            bvdot + bias[r]
        );
    }
}

/// A pendulum on a spherical joint, once rigid and once as a flexible body with no modes and the same
/// mass properties (one node at the hinge): the same motion to round-off (the BDF's floor under a step's
/// share made of its measured noise, `integrate/noise_floor.rs`, is rounding and differs between the two;
/// where it was measured from the first steps on, their steps parted, 2.8e-10 at 1 s).
#[test]
fn a_flexible_body_without_modes_moves_like_the_rigid_body() {
    let mass = 2.0;
    let com = Vec3::new(0.3, 0.05, -0.1);
    let inertia_com = Mat3::new(0.02, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.025);
    let initial = InitialState {
        position: Vec3::zeros(),
        orientation: EulerParameters::from_axis_angle(&Vec3::new(0.2, 1.0, 0.1), 0.4).unwrap(),
        velocity: None,
        angular_velocity: Some(Vec3::new(0.5, -1.0, 2.0)),
    };
    let run = |flexible: bool| -> Vec<f64> {
        let mut b = ModelBuilder::new("pendulum").gravity(Vec3::new(0.0, 0.0, -9.81));
        let body = if flexible {
            let j_origin = inertia_com - mass * skew(&com) * skew(&com);
            let modal = ModalBody {
                invariants: ModalInvariants {
                    mass,
                    c1: mass * com,
                    c2: Matrix3xX::zeros(0),
                    c3: -j_origin,
                    c4: vec![],
                    c5: vec![],
                    c6: Matrix3xX::zeros(0),
                    c7: vec![],
                    c9: DMatrix::zeros(0, 0),
                    rotary_inertia: Mat3::zeros(),
                    rotary_coupling: Matrix3xX::zeros(0),
                    rotary_modal_mass: DMatrix::zeros(0, 0),
                },
                stiffness: DMatrix::zeros(0, 0),
                damping: DMatrix::zeros(0, 0),
                nodes: vec![ModalNode { label: 1, position: Vec3::zeros(), psi: Matrix3xX::zeros(0), theta: Matrix3xX::zeros(0) }],
                mode_labels: vec![],
                initial_coordinates: DVector::zeros(0),
                initial_rates: DVector::zeros(0),
                geometric_stiffness: None,
            };
            b.add_flexible_body("link", initial.clone(), modal).unwrap()
        } else {
            b.add_body(RigidBody { name: "link".into(), mass, center_of_mass: com, inertia: inertia_com, initial: initial.clone() }).unwrap()
        };
        let hinge = if flexible {
            b.add_node_marker("hinge", body, 0, Mat3::identity()).unwrap()
        } else {
            b.add_marker(Marker { name: "hinge".into(), body: BodyRef::Body(body), origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap()
        };
        let ground = b.add_marker(Marker { name: "g".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap();
        b.add_joint(Joint { name: "ball".into(), kind: JointKind::Spherical, marker_i: ground, marker_j: hinge }).unwrap();
        let tip = if flexible {
            b.add_node_marker("tip", body, 0, Mat3::identity()).unwrap()
        } else {
            b.add_marker(Marker { name: "tip".into(), body: BodyRef::Body(body), origin: Vec3::zeros(), axes: Mat3::identity() }).unwrap()
        };
        b.add_output("w", OutputKind::MarkerAngularVelocity(tip)).unwrap();
        b.add_output("e", OutputKind::Energy).unwrap();
        let model = b.build().unwrap();
        let settings = settings(1.0, 0.05, 1e-8);
        let mut values = Vec::new();
        simulate(&model, &settings, &mut |f| values.extend_from_slice(f.values)).unwrap();
        values
    };
    let (rigid, flexible) = (run(false), run(true));
    assert_eq!(rigid.len(), flexible.len());
    for (a, b) in rigid.iter().zip(&flexible) {
        assert!((a - b).abs() < 1e-10 * (1.0 + a.abs()), "rigid {a} vs flexible {b}");
    }
}

fn settings(t_end: f64, output_step: f64, tolerance: f64) -> SimulationSettings {
    SimulationSettings {
        t_end,
        output_step,
        tolerances: Tolerances::new(tolerance, tolerance),
        ..Default::default()
    }
}

/// Node-by-node linear and angular momentum (about the global origin) of body 0.
fn momentum(nodes: &[LumpedNode], m: usize, q: &[f64], v: &[f64]) -> (Vec3, Vec3) {
    let p = Vec4::from_column_slice(&q[3..7]);
    let a_mat = rotation_matrix(&p);
    let r0 = Vec3::from_column_slice(&q[0..3]);
    let w = Vec3::from_column_slice(&v[3..6]);
    let a = DVector::from_column_slice(&q[7..7 + m]);
    let ad = DVector::from_column_slice(&v[6..6 + m]);
    let (mut lin, mut ang) = (Vec3::zeros(), Vec3::zeros());
    for n in nodes {
        let r_bar: Vec3 = n.position + &n.psi * &a;
        let u_dot: Vec3 = &n.psi * &ad;
        let vel = Vec3::from_column_slice(&v[0..3]) + a_mat * (w.cross(&r_bar) + u_dot);
        let pos = r0 + a_mat * r_bar;
        let omega: Vec3 = w + &n.theta * &ad;
        lin += n.mass * vel;
        ang += n.mass * pos.cross(&vel) + a_mat * (n.rotary_inertia * omega);
    }
    (lin, ang)
}

#[test]
fn a_free_undamped_flexible_body_keeps_momentum_and_energy() {
    let mut rng = Lcg(0xf1e5_0004);
    let m = 3;
    let nodes = random_nodes(&mut rng, 8, m, true);
    let mut modal = modal_body(&nodes, m, &mut rng);
    modal.initial_rates = DVector::from_vec(vec![0.3, -0.2, 0.4]);
    modal.initial_coordinates = DVector::from_vec(vec![0.02, 0.01, -0.015]);
    let mut b = ModelBuilder::new("free flexible body");
    let initial = InitialState {
        position: Vec3::new(0.1, 0.2, 0.3),
        orientation: EulerParameters::from_axis_angle(&Vec3::new(1.0, 2.0, 0.5), 0.7).unwrap(),
        velocity: Some(Vec3::new(0.3, -0.1, 0.2)),
        angular_velocity: Some(Vec3::new(1.0, 2.0, -1.5)),
    };
    let body = b.add_flexible_body("flex", initial, modal).unwrap();
    b.add_output("e", OutputKind::Energy).unwrap();
    let model = b.build().unwrap();
    let _ = body;
    let mut states: Vec<(Vec<f64>, Vec<f64>, f64)> = Vec::new();
    let report = simulate(&model, &settings(2.0, 0.1, 1e-9), &mut |f| states.push((f.q.to_vec(), f.v.to_vec(), f.values[3]))).unwrap();
    assert!(report.t_reached >= 2.0 - 1e-12);
    let (l0, h0) = momentum(&nodes, m, &states[0].0, &states[0].1);
    let e0 = states[0].2;
    let (mut dl, mut dh, mut de) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (q, v, e) in &states {
        let (l, h) = momentum(&nodes, m, q, v);
        dl = dl.max((l - l0).norm() / l0.norm());
        dh = dh.max((h - h0).norm() / h0.norm());
        de = de.max((e - e0).abs() / e0.abs());
    }
    println!("free flexible body over 2 s: relative drift of linear momentum {dl:.1e}, angular momentum {dh:.1e}, energy {de:.1e}");
    assert!(dl < 1e-6 && dh < 1e-6 && de < 1e-6, "drifts {dl:.1e} {dh:.1e} {de:.1e}");
    let _ = BodyId(0);
}

#[test]
fn damping_ratios_go_to_the_modes_in_order_of_frequency() {
    let mut rng = Lcg(0xf1e5_0005);
    let m = 3;
    let nodes = random_nodes(&mut rng, 6, m, false);
    let body = modal_body(&nodes, m, &mut rng);
    let ratios = [0.01, 0.05, 0.2];
    let damping = body.damping_matrix(&crate::body::ModalDamping::Ratios(ratios.to_vec())).unwrap();
    // The natural modes of (K, M), ascending: Xᵀ M X = I, Xᵀ K X = diag(ω²), and Xᵀ D X = diag(2 ζ ω).
    let mass = body.invariants.modal_mass();
    let chol = nalgebra::Cholesky::new(mass).unwrap();
    let l_inv = chol.l().try_inverse().unwrap();
    let eigen = nalgebra::SymmetricEigen::new(&l_inv * &body.stiffness * l_inv.transpose());
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let x = l_inv.transpose() * &eigen.eigenvectors;
    let modal_damping = x.transpose() * &damping * &x;
    for (rank, &k) in order.iter().enumerate() {
        let omega = eigen.eigenvalues[k].sqrt();
        assert!((modal_damping[(k, k)] - 2.0 * ratios[rank] * omega).abs() < 1e-9 * omega, "mode {rank}");
    }
}

/// A flexible body on a revolute joint at a node, with a rotational spring on that joint and a
/// translational spring from another node to ground, under gravity, undamped: total energy (kinetic,
/// gravity, springs, strain) is conserved, so the spring forces at nodes do the work their potentials
/// say.
#[test]
fn springs_at_nodes_conserve_energy() {
    use crate::force::{ForceElement, ForceKind};
    let mut rng = Lcg(0xf1e5_0006);
    let m = 3;
    let nodes = random_nodes(&mut rng, 6, m, true);
    let mut modal = modal_body(&nodes, m, &mut rng);
    modal.initial_rates = DVector::from_vec(vec![0.2, -0.1, 0.3]);
    let mut b = ModelBuilder::new("sprung flexible body").gravity(Vec3::new(0.0, -9.81, 0.0));
    let flex = b.add_flexible_body("flex", InitialState { angular_velocity: Some(Vec3::new(0.0, 0.0, 1.5)), ..Default::default() }, modal).unwrap();
    let hinge = b.add_node_marker("hinge", flex, 0, Mat3::identity()).unwrap();
    let far = b.add_node_marker("far", flex, 3, Mat3::identity()).unwrap();
    let ground = b.add_marker(Marker { name: "g".into(), body: BodyRef::Ground, origin: nodes[0].position, axes: Mat3::identity() }).unwrap();
    let anchor = b.add_marker(Marker { name: "anchor".into(), body: BodyRef::Ground, origin: Vec3::new(0.8, 0.5, 0.2), axes: Mat3::identity() }).unwrap();
    let joint = b.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: ground, marker_j: hinge }).unwrap();
    b.add_force(ForceElement {
        name: "torsion".into(),
        kind: ForceKind::RotationalSpringDamper { joint, stiffness: 5.0, damping: 0.0, free_angle: 0.3, actuator: None },
    }).unwrap();
    b.add_force(ForceElement {
        name: "spring".into(),
        kind: ForceKind::TranslationalSpringDamper { marker_i: anchor, marker_j: far, stiffness: 40.0, damping: 0.0, free_length: 0.4, actuator: None },
    }).unwrap();
    b.add_output("e", OutputKind::Energy).unwrap();
    let model = b.build().unwrap();
    let mut energy = Vec::new();
    simulate(&model, &settings(1.0, 0.01, 1e-9), &mut |f| energy.push((f.values[0], f.values[3]))).unwrap();
    let e0 = energy[0].1;
    let kinetic_range = energy.iter().map(|e| e.0).fold(0.0_f64, f64::max) - energy.iter().map(|e| e.0).fold(f64::INFINITY, f64::min);
    let drift = energy.iter().map(|e| (e.1 - e0).abs()).fold(0.0_f64, f64::max);
    println!("sprung flexible body: kinetic energy range {kinetic_range:.3} J, largest total-energy drift {drift:.1e} J");
    assert!(kinetic_range > 0.1, "it moves: {kinetic_range}");
    assert!(drift < 1e-6 * kinetic_range.max(1.0), "energy drift {drift:.2e}");
}

/// High-mode damping damps the natural modes above its cutoff with its ratio and leaves those below
/// undamped: `Xᵀ D X = diag(0, …, 2 ζ ωⱼ, …)`, and `D x = 0` for a mode `x` below the cutoff, so
/// `(−ω² M + i ω D + K) x = 0` still holds at that mode's undamped frequency (its frequency is unchanged).
#[test]
fn high_mode_damping_damps_only_the_modes_above_its_cutoff() {
    use crate::body::HighModeDamping;
    let mut rng = Lcg(0xf1e5_0007);
    let m = 4;
    let nodes = random_nodes(&mut rng, 7, m, true);
    let body = modal_body(&nodes, m, &mut rng);
    let (omega_squared, x) = body.natural_modes().unwrap();
    let omega: Vec<f64> = omega_squared.iter().map(|w2| w2.sqrt()).collect();
    assert!(omega.windows(2).all(|w| w[1] > 1.01 * w[0]), "distinct frequencies {omega:?}");
    // The cutoff between the second and the third mode.
    let above_hz = 0.5 * (omega[1] + omega[2]) / (2.0 * std::f64::consts::PI);
    let damping = HighModeDamping { above_hz, ratio: 0.3 };
    assert_eq!(body.modes_above_cutoff(&damping), 2);
    let d = body.high_mode_damping_matrix(&damping).unwrap();
    let modal = x.transpose() * &d * &x;
    let scale = omega[m - 1];
    for j in 0..m {
        for k in 0..m {
            let expected = if j == k && j >= 2 { 2.0 * 0.3 * omega[j] } else { 0.0 };
            assert!((modal[(j, k)] - expected).abs() < 1e-9 * scale, "({j}, {k}): {} against {expected}", modal[(j, k)]);
        }
    }
    let mass = body.invariants.modal_mass();
    for j in 0..2 {
        let xj = x.column(j);
        assert!((&d * xj).norm() < 1e-9 * scale * (&mass * xj).norm(), "mode {j} is damped");
        let undamped = (&body.stiffness - omega_squared[j] * &mass) * xj;
        assert!(undamped.norm() < 1e-9 * omega_squared[j] * (&mass * xj).norm(), "mode {j}: {}", undamped.norm());
    }
    // No mode above the cutoff: no damping; a bad cutoff or ratio is refused.
    let none = HighModeDamping::above(2.0 * omega[m - 1] / (2.0 * std::f64::consts::PI));
    assert_eq!(body.high_mode_damping_matrix(&none).unwrap(), nalgebra::DMatrix::zeros(m, m));
    assert!(HighModeDamping { above_hz: 0.0, ratio: 0.5 }.validate().unwrap_err().contains("positive"));
    assert!(HighModeDamping { above_hz: 100.0, ratio: -0.1 }.validate().unwrap_err().contains("negative"));
    assert!(HighModeDamping { above_hz: f64::NAN, ratio: 0.5 }.validate().is_err());
    assert!(HighModeDamping::above(100.0).validate().is_ok());
    let negative = HighModeDamping { above_hz: 100.0, ratio: -0.5 };
    assert!(matches!(body.high_mode_damping_matrix(&negative), Err(crate::body::ModalError::HighModeDamping(m)) if m.contains("negative")));
}

/// Geometric stiffening (formulation.md §11) on a random body with random symmetric `G_k`, in
/// gravity: the inertia forces gain exactly `Σ f_k G_k a` with the factors computed here from
/// `ā = Aᵀ(R̈ − g)`, `ω̄̇`, `ω̄`, and `inertia_jacobian_entries` is their derivative in `v̇` (central
/// differences; the forces are linear in `v̇`).
#[test]
fn geometric_stiffening_adds_its_term_and_its_acceleration_columns() {
    use crate::body::ModalGeometricStiffness;
    use crate::stage::inertia_jacobian_entries;
    let mut rng = Lcg(0xf1e5_0020);
    let m = 3;
    let nodes = random_nodes(&mut rng, 6, m, true);
    let plain = modal_body(&nodes, m, &mut rng);
    let cases: Vec<DMatrix<f64>> = (0..12)
        .map(|_| {
            let r = DMatrix::from_fn(m, m, |_, _| rng.range(-1.0, 1.0));
            &r + r.transpose()
        })
        .collect();
    let gravity = Vec3::new(0.3, -9.81, 1.2);
    let build = |body: ModalBody| {
        let mut b = ModelBuilder::new("stiffened").gravity(gravity);
        b.add_flexible_body("flex", InitialState::default(), body).unwrap();
        b.build().unwrap()
    };
    let stiffened = build(ModalBody { geometric_stiffness: Some(ModalGeometricStiffness::of_inertia_cases(cases.clone())), ..plain.clone() });
    let unstiffened = build(plain);
    let (q, v, vdot) = random_state(&stiffened, &mut rng);
    let forces = |model: &Model, vdot: &[f64]| {
        let mut data = Data::new(model);
        kinematics(model, &mut data, &q, &v);
        inertia_forces(model, &mut data, vdot);
        data.inertia.clone()
    };
    let (with, without) = (forces(&stiffened, &vdot), forces(&unstiffened, &vdot));
    let rotation = rotation_matrix(&Vec4::from_column_slice(&q[3..7]));
    let a_bar = rotation.transpose() * (Vec3::from_column_slice(&vdot[0..3]) - gravity);
    let (wd, w) = (Vec3::from_column_slice(&vdot[3..6]), Vec3::from_column_slice(&v[3..6]));
    let factors = [a_bar.x, a_bar.y, a_bar.z, wd.x, wd.y, wd.z, w.x * w.x, w.y * w.y, w.z * w.z, w.x * w.y, w.y * w.z, w.z * w.x];
    let a = DVector::from_column_slice(&q[7..7 + m]);
    let expected = cases.iter().zip(factors).fold(DVector::zeros(m), |sum, (g, f)| sum + g * &a * f);
    for k in 0..6 + m {
        let added = with[k] - without[k];
        let reference = if k < 6 { 0.0 } else { expected[k - 6] };
        assert!((added - reference).abs() < 1e-12 * (1.0 + reference.abs()), "row {k}: {added} against {reference}");
    }
    let n = 6 + m;
    let mut jacobian = DMatrix::<f64>::zeros(n, n);
    let mut data = Data::new(&stiffened);
    kinematics(&stiffened, &mut data, &q, &v);
    inertia_jacobian_entries(&stiffened, &data, 0, |r, c, x| jacobian[(r, c)] += x);
    let h = 1e-4;
    let mut worst = 0.0_f64;
    for c in 0..n {
        let (mut plus, mut minus) = (vdot.clone(), vdot.clone());
        plus[c] += h;
        minus[c] -= h;
        let (fp, fm) = (forces(&stiffened, &plus), forces(&stiffened, &minus));
        for r in 0..n {
            worst = worst.max(((fp[r] - fm[r]) / (2.0 * h) - jacobian[(r, c)]).abs());
        }
    }
    assert!(worst < 1e-9 * jacobian.amax(), "∂(inertia forces)/∂v̇ against central differences: {worst:.2e}");
    assert!((0..m).any(|j| jacobian[(6 + j, 0)] != jacobian[(0, 6 + j)]), "the stiffening columns make it non-symmetric");
}
