//! Random mechanisms that are valid by construction: rigid bodies (and now and then the shipped
//! flexible strip) joined to ground and to each other by joints of every type whose markers agree at
//! the initial position, loops closed by further joints, drivers, springs, dampers, forces and
//! torques reading measures, gravity and outputs of every kind. They exercise the assembly, the
//! redundancy check, the velocity analysis and a short simulation, not only the parser.

use std::fmt::Write;

use nalgebra::{Quaternion, Rotation3, UnitQuaternion, Vector3};

use super::rng::Rng;

/// A body's pose at the start, global.
#[derive(Clone)]
struct Body {
    name: String,
    origin: Vector3<f64>,
    rotation: Rotation3<f64>,
    /// The node positions (body frame) of a flexible body, by label from 1.
    nodes: Option<Vec<Vector3<f64>>>,
}

/// The shipped strip the flexible bodies are reduced from: 21 nodes along body x over 1 m.
const FLEXIBLE_FE_MODEL: &str = "fe/pendulum_beam.toml";

/// A joint made: its name and type.
struct JointMade {
    name: String,
    kind: &'static str,
}

#[derive(Default)]
struct Mechanism {
    text: String,
    bodies: Vec<Body>,
    markers: Vec<(String, usize)>,
    joints: Vec<JointMade>,
    measures: Vec<String>,
    flexible: Option<(String, usize)>,
}

const JOINT_TYPES: &[&str] = &[
    "spherical", "revolute", "universal", "cylindrical", "translational", "fixed", "planar", "distance", "dot-1",
    "dot-2", "point-on-line", "point-in-plane",
];

/// A number as TOML reads it back exactly.
pub fn num(x: f64) -> String {
    format!("{x:?}")
}

pub fn vector(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z))
}

fn random_vector(rng: &mut Rng, scale: f64) -> Vector3<f64> {
    Vector3::new(rng.range(-scale, scale), rng.range(-scale, scale), rng.range(-scale, scale))
}

/// A rotation: uniformly random, or one of the axis-aligned quarter turns that real mechanisms use.
fn random_rotation(rng: &mut Rng) -> Rotation3<f64> {
    if rng.chance(0.4) {
        let axis = *rng.pick(&[Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()]);
        return Rotation3::from_axis_angle(&axis, std::f64::consts::FRAC_PI_2 * rng.below(4) as f64);
    }
    let q = Quaternion::new(rng.normal(), rng.normal(), rng.normal(), rng.normal());
    UnitQuaternion::from_quaternion(q).to_rotation_matrix()
}

/// An orientation in one of the model file's forms (`marker` adds `z_axis`/`x_axis`); empty for the
/// identity now and then.
fn orientation(rng: &mut Rng, r: &Rotation3<f64>, marker: bool) -> String {
    if r.angle() == 0.0 && rng.chance(0.5) {
        return String::new();
    }
    let q = UnitQuaternion::from_rotation_matrix(r);
    let (axis, angle) = q.axis_angle().map_or((Vector3::z(), 0.0), |(a, t)| (a.into_inner(), t));
    let m = r.matrix();
    match rng.below(if marker { 6 } else { 4 }) {
        0 => format!("orientation = {{ axis = {}, angle = {} }}\n", vector(&axis), num(angle)),
        1 => format!("orientation = {{ axis = {}, angle_deg = {} }}\n", vector(&(axis * 2.5)), num(angle.to_degrees())),
        2 => {
            let rows: Vec<String> =
                (0..3).map(|i| format!("[{}, {}, {}]", num(m[(i, 0)]), num(m[(i, 1)]), num(m[(i, 2)]))).collect();
            format!("orientation = {{ matrix = [{}] }}\n", rows.join(", "))
        }
        3 => format!("orientation = {{ euler_parameters = [{}, {}, {}, {}] }}\n", num(q.w), num(q.i), num(q.j), num(q.k)),
        _ => format!(
            "z_axis = {}\nx_axis = {}\n",
            vector(&(m.column(2).into_owned() * 3.0)),
            vector(&m.column(0).into_owned())
        ),
    }
}

/// A mechanism model file.
pub fn mechanism(rng: &mut Rng) -> String {
    let mut m = Mechanism::default();
    m.bodies.push(Body { name: "ground".into(), origin: Vector3::zeros(), rotation: Rotation3::identity(), nodes: None });
    header(rng, &mut m);
    let rigid = rng.between(1, 5);
    for k in 0..rigid {
        rigid_body(rng, &mut m, k);
    }
    if rng.chance(0.2) {
        flexible_body(rng, &mut m);
    }
    for b in 1..m.bodies.len() {
        let other = if b == 1 || rng.chance(0.35) { 0 } else { rng.below(b) };
        joint(rng, &mut m, other, b);
    }
    for _ in 0..rng.below(3) {
        let (a, b) = (rng.below(m.bodies.len()), rng.below(m.bodies.len()));
        if a != b {
            joint(rng, &mut m, a, b);
        }
    }
    for _ in 0..rng.below(4) {
        measure(rng, &mut m);
    }
    for _ in 0..rng.below(4) {
        force(rng, &mut m);
    }
    for _ in 0..rng.between(1, 5) {
        output(rng, &mut m);
    }
    m.text
}

fn header(rng: &mut Rng, m: &mut Mechanism) {
    let gravity = match rng.below(3) {
        0 => Vector3::zeros(),
        1 => Vector3::new(0.0, -9.81, 0.0),
        _ => random_vector(rng, 10.0),
    };
    let t = &mut m.text;
    let _ = writeln!(t, "# A mechanism made by the fuzz harness.\n[model]\nname = \"generated\"\ngravity = {}\n", vector(&gravity));
    let _ = writeln!(t, "[simulation]\nt_end = 0.05\noutput_step = {}", num(*rng.pick(&[0.01, 0.005, 0.025])));
    if rng.chance(0.5) {
        let _ = writeln!(t, "rtol = {}\natol = {}", num(rng.log_range(1e-8, 1e-3)), num(rng.log_range(1e-8, 1e-3)));
    }
    match rng.below(4) {
        0 => {
            let _ = writeln!(t, "integrator = \"adams\"");
        }
        1 => {
            let _ = writeln!(t, "integrator = \"gen-alpha\"\nspectral_radius = {}", num(rng.range(0.0, 1.0)));
        }
        2 => {
            let _ = writeln!(t, "integrator = \"bdf\"\nmax_order = {}", rng.between(1, 5));
        }
        _ => {}
    }
    let _ = writeln!(t, "\n[parameters]\nk0 = {}\nc0 = {}\n", num(rng.log_range(1.0, 1e4)), num(rng.range(0.0, 5.0)));
}

fn rigid_body(rng: &mut Rng, m: &mut Mechanism, k: usize) {
    let name = format!("b{k}");
    let mass = rng.log_range(0.1, 10.0);
    let (a, b, c) = (rng.log_range(0.02, 1.0), rng.log_range(0.02, 1.0), rng.log_range(0.02, 1.0));
    let principal = Vector3::new(b * b + c * c, a * a + c * c, a * a + b * b) * (mass / 12.0);
    let origin = random_vector(rng, 1.0);
    let rotation = if rng.chance(0.3) { Rotation3::identity() } else { random_rotation(rng) };
    let t = &mut m.text;
    let _ = writeln!(t, "[[body]]\nname = \"{name}\"\nmass = {}", num(mass));
    match rng.below(3) {
        0 => {
            let _ = writeln!(t, "inertia = {}", vector(&principal));
        }
        form => {
            let r = random_rotation(rng);
            let j = r.matrix() * nalgebra::Matrix3::from_diagonal(&principal) * r.matrix().transpose();
            let e = |p: usize, q: usize| num(0.5 * (j[(p, q)] + j[(q, p)]));
            if form == 1 {
                let _ = writeln!(
                    t,
                    "inertia = [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]]",
                    e(0, 0), e(0, 1), e(0, 2), e(0, 1), e(1, 1), e(1, 2), e(0, 2), e(1, 2), e(2, 2)
                );
            } else {
                let _ = writeln!(
                    t,
                    "inertia = {{ xx = {}, yy = {}, zz = {}, xy = {}, xz = {}, yz = {} }}",
                    e(0, 0), e(1, 1), e(2, 2), e(0, 1), e(0, 2), e(1, 2)
                );
            }
        }
    }
    if rng.chance(0.5) {
        let _ = writeln!(t, "center_of_mass = {}", vector(&random_vector(rng, 0.3)));
    }
    let _ = writeln!(t, "position = {}", vector(&origin));
    t.push_str(&orientation(rng, &rotation, false));
    initial_velocities(rng, t);
    if rng.chance(0.3) {
        let shape = match rng.below(4) {
            0 => format!("{{ box = [{}, {}, {}] }}", num(a), num(b), num(c)),
            1 => format!("{{ sphere = {} }}", num(a)),
            2 => format!("{{ cylinder = {{ radius = {}, length = {}, axis = \"y\" }}, origin = [0, 0.1, 0] }}", num(a), num(b)),
            _ => "{ frame = 0.1 }".to_string(),
        };
        let _ = writeln!(t, "shape = {shape}");
    }
    t.push('\n');
    m.bodies.push(Body { name, origin, rotation, nodes: None });
}

fn initial_velocities(rng: &mut Rng, t: &mut String) {
    for key in ["velocity", "angular_velocity"] {
        if rng.chance(0.4) {
            let v = if rng.chance(0.5) { Vector3::zeros() } else { random_vector(rng, 1.0) };
            let _ = writeln!(t, "{key} = {}", vector(&v));
        }
    }
}

fn flexible_body(rng: &mut Rng, m: &mut Mechanism) {
    let name = "strip".to_string();
    let origin = random_vector(rng, 1.0);
    let rotation = random_rotation(rng);
    let modes = rng.between(1, 4);
    let t = &mut m.text;
    let _ = writeln!(t, "[[flexible_body]]\nname = \"{name}\"\nfe_model = \"{FLEXIBLE_FE_MODEL}\"\nmodes = \"{modes}N\"");
    if rng.chance(0.3) {
        let _ = writeln!(t, "basis = \"{}\"", rng.pick(&["raw", "orthonormal"]));
    }
    if rng.chance(0.5) {
        let _ = writeln!(t, "damping = {{ ratio = {} }}", num(rng.range(0.0, 0.1)));
    }
    let _ = writeln!(t, "position = {}", vector(&origin));
    t.push_str(&orientation(rng, &rotation, false));
    initial_velocities(rng, t);
    if rng.chance(0.3) {
        let a: Vec<String> = (0..modes).map(|_| num(rng.range(-1e-3, 1e-3))).collect();
        let _ = writeln!(t, "modal_coordinates = [{}]", a.join(", "));
    }
    t.push('\n');
    let nodes = (0..21).map(|k| Vector3::new(k as f64 / 20.0, 0.0, 0.0)).collect();
    m.flexible = Some((name.clone(), modes));
    m.bodies.push(Body { name, origin, rotation, nodes: Some(nodes) });
}

/// A marker on `body` at the global point `at` with global axes `axes`; on a flexible body, at the
/// node `node` (whose global point `at` must be).
fn marker(rng: &mut Rng, m: &mut Mechanism, body: usize, at: &Vector3<f64>, axes: &Rotation3<f64>, node: Option<usize>) -> String {
    let name = format!("k{}", m.markers.len());
    let b = m.bodies[body].clone();
    let local_axes = b.rotation.inverse() * axes;
    let local_origin = b.rotation.inverse() * (at - b.origin);
    let t = &mut m.text;
    let _ = writeln!(t, "[[marker]]\nname = \"{name}\"\nbody = \"{}\"", b.name);
    match node {
        Some(n) => {
            // The strip's node sets are named after its beam line, `arm`.
            let reference = match (n, rng.below(3)) {
                (0, 0) => "\"arm.start\"".to_string(),
                (20, 0) => "\"arm.end\"".to_string(),
                (_, 1) => vector(&b.nodes.as_ref().unwrap()[n]),
                _ => (n + 1).to_string(),
            };
            let _ = writeln!(t, "node = {reference}");
        }
        None => {
            if local_origin.norm() > 0.0 || rng.chance(0.5) {
                let _ = writeln!(t, "origin = {}", vector(&local_origin));
            }
        }
    }
    t.push_str(&orientation(rng, &local_axes, true));
    t.push('\n');
    m.markers.push((name.clone(), body));
    name
}

/// A point on body `b` for a joint or force: a node of a flexible body, else a point near the body.
fn point_on(rng: &mut Rng, m: &Mechanism, b: usize) -> (Vector3<f64>, Option<usize>) {
    let body = &m.bodies[b];
    match &body.nodes {
        Some(nodes) => {
            let n = if rng.chance(0.5) { *rng.pick(&[0, 20]) } else { rng.below(nodes.len()) };
            (body.origin + body.rotation * nodes[n], Some(n))
        }
        None => (body.origin + random_vector(rng, 0.5), None),
    }
}

/// A joint of a random type between bodies `a` and `b`, its markers agreeing at the start, sometimes
/// with a driver.
fn joint(rng: &mut Rng, m: &mut Mechanism, a: usize, b: usize) {
    let kind = *rng.pick(JOINT_TYPES);
    let (pa, na) = point_on(rng, m, a);
    let (pb, nb) = point_on(rng, m, b);
    let g = random_rotation(rng);
    let (x, y, z) = (g * Vector3::x(), g * Vector3::y(), g * Vector3::z());
    let offset = match kind {
        "distance" => random_vector(rng, 0.5),
        "cylindrical" | "translational" | "point-on-line" => z * rng.range(-0.2, 0.2),
        "planar" | "dot-2" | "point-in-plane" => x * rng.range(-0.2, 0.2) + y * rng.range(-0.2, 0.2),
        _ => Vector3::zeros(),
    };
    let h = match kind {
        "spherical" | "distance" => random_rotation(rng),
        "universal" => g * Rotation3::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
        _ => g,
    };
    // A flexible body's marker must sit at its node: the offset goes to the other marker.
    let (pi, pj) = match (na, nb) {
        (Some(_), _) => (pa, pa + offset),
        (None, Some(_)) => (pb - offset, pb),
        (None, None) => (pb, pb + offset),
    };
    let i = marker(rng, m, a, &pi, &g, na);
    let j = marker(rng, m, b, &pj, &h, nb);
    let name = format!("j{}", m.joints.len());
    let t = &mut m.text;
    let _ = writeln!(t, "[[joint]]\nname = \"{name}\"\ntype = \"{kind}\"\ni = \"{i}\"\nj = \"{j}\"");
    match kind {
        "distance" if rng.chance(0.3) => {
            let _ = writeln!(t, "length = \"{} + 0.01*sin(3*t)\"", num(offset.norm()));
        }
        "dot-1" => {
            let (ai, aj) = *rng.pick(&[("x", "y"), ("y", "z"), ("z", "x"), ("x", "z")]);
            let _ = writeln!(t, "axis_i = \"{ai}\"\naxis_j = \"{aj}\"");
        }
        "dot-2" => {
            let _ = writeln!(t, "axis_i = \"z\"");
        }
        _ => {}
    }
    t.push('\n');
    if matches!(kind, "revolute" | "translational" | "cylindrical") && rng.chance(0.3) {
        driver(rng, m, &name, kind);
    }
    m.joints.push(JointMade { name, kind });
}

fn driver(rng: &mut Rng, m: &mut Mechanism, joint: &str, kind: &str) {
    let t = &mut m.text;
    let _ = writeln!(t, "[[driver]]\nname = \"drive_{joint}\"\njoint = \"{joint}\"");
    if kind == "cylindrical" || rng.chance(0.3) {
        let driven = if kind == "revolute" || (kind == "cylindrical" && rng.chance(0.5)) { "angle" } else { "displacement" };
        let _ = writeln!(t, "type = \"{driven}\"");
    }
    let (a, w) = (rng.range(0.01, 0.5), rng.range(0.5, 20.0));
    let function = match rng.below(4) {
        0 => format!("{a}*sin({w}*t)"),
        1 => format!("{w}*t"),
        2 => format!("{a}*(1 - cos({w}*t))"),
        _ => format!("{a} + {w}*t"),
    };
    let _ = writeln!(t, "function = \"{function}\"\n");
}

fn measure(rng: &mut Rng, m: &mut Mechanism) {
    let name = format!("m{}", m.measures.len());
    let rotary: Vec<&JointMade> = m.joints.iter().filter(|j| matches!(j.kind, "revolute" | "cylindrical")).collect();
    let sliding: Vec<&JointMade> = m.joints.iter().filter(|j| matches!(j.kind, "translational" | "cylindrical")).collect();
    let marker_a = rng.pick(&m.markers).0.clone();
    let marker_b = rng.pick(&m.markers).0.clone();
    let component = rng.pick(&["x", "y", "z"]);
    let body = match rng.below(5) {
        0 if !rotary.is_empty() => format!("type = \"{}\"\njoint = \"{}\"", rng.pick(&["joint_angle", "joint_rate"]), rng.pick(&rotary).name),
        1 if !sliding.is_empty() => {
            format!("type = \"{}\"\njoint = \"{}\"", rng.pick(&["joint_displacement", "joint_velocity"]), rng.pick(&sliding).name)
        }
        2 if marker_a != marker_b => format!("type = \"{}\"\ni = \"{marker_a}\"\nj = \"{marker_b}\"", rng.pick(&["distance", "distance_rate"])),
        3 => format!("type = \"speed\"\nmarker = \"{marker_a}\""),
        _ => format!("type = \"{}\"\nmarker = \"{marker_a}\"\ncomponent = \"{component}\"", rng.pick(&["position", "velocity"])),
    };
    let _ = writeln!(m.text, "[[measure]]\nname = \"{name}\"\n{body}\n");
    m.measures.push(name);
}

/// A small function of time and of the measures, for actuators and force components; bounded by
/// `scale`, so that no load grows with the motion it drives (a torque proportional to a speed it
/// raised spun a body up exponentially: a diverging model, not a valid one).
fn load_function(rng: &mut Rng, m: &Mechanism, scale: f64) -> String {
    let s = num(scale * rng.range(-1.0, 1.0));
    match (rng.below(4), m.measures.is_empty()) {
        (0, false) => format!("-{}*tanh({})", num(scale), rng.pick(&m.measures)),
        (1, false) => format!("{s}*sin({})", rng.pick(&m.measures)),
        (2, _) => format!("{s}*sin({}*t)", num(rng.range(1.0, 30.0))),
        _ => s,
    }
}

fn force(rng: &mut Rng, m: &mut Mechanism) {
    let name = format!("f{}", m.text.matches("[[force]]").count());
    let rotary: Vec<String> = m.joints.iter().filter(|j| matches!(j.kind, "revolute" | "cylindrical")).map(|j| j.name.clone()).collect();
    let kind = rng.below(4);
    let mut t = format!("[[force]]\nname = \"{name}\"\n");
    match kind {
        0 if !rotary.is_empty() => {
            let _ = writeln!(t, "type = \"rotational_spring_damper\"\njoint = \"{}\"", rng.pick(&rotary));
            spring_damper(rng, m, &mut t, "free_angle");
        }
        0 | 1 => {
            let (a, b) = (1 + rng.below(m.bodies.len() - 1), rng.below(m.bodies.len()));
            if a == b {
                return;
            }
            let (pa, na) = point_on(rng, m, a);
            let (pb, nb) = point_on(rng, m, b);
            let i = marker(rng, m, a, &pa, &Rotation3::identity(), na);
            let j = marker(rng, m, b, &pb, &Rotation3::identity(), nb);
            let _ = writeln!(t, "type = \"translational_spring_damper\"\ni = \"{i}\"\nj = \"{j}\"");
            spring_damper(rng, m, &mut t, "free_length");
        }
        _ => {
            let on = rng.pick(&m.markers).0.clone();
            let c: Vec<String> = (0..3).map(|_| format!("\"{}\"", load_function(rng, m, 5.0))).collect();
            let _ = writeln!(
                t,
                "type = \"{}\"\nmarker = \"{on}\"\nframe = \"{}\"\ncomponents = [{}]",
                rng.pick(&["force", "torque"]),
                rng.pick(&["global", "body", "marker"]),
                c.join(", ")
            );
        }
    }
    m.text.push_str(&t);
    m.text.push('\n');
}

fn spring_damper(rng: &mut Rng, m: &Mechanism, t: &mut String, free: &str) {
    if rng.chance(0.7) {
        let _ = writeln!(t, "stiffness = {}", if rng.chance(0.3) { "\"k0\"".to_string() } else { num(rng.log_range(1.0, 1e4)) });
    }
    if rng.chance(0.5) {
        let _ = writeln!(t, "damping = {}", if rng.chance(0.3) { "\"c0\"".to_string() } else { num(rng.range(0.0, 10.0)) });
    }
    if rng.chance(0.4) {
        let _ = writeln!(t, "{free} = {}", num(rng.range(0.0, 0.5)));
    }
    if rng.chance(0.4) {
        let _ = writeln!(t, "actuator = \"{}\"", load_function(rng, m, 2.0));
    }
}

fn output(rng: &mut Rng, m: &mut Mechanism) {
    let marker = rng.pick(&m.markers).0.clone();
    let mut kinds = vec!["marker_position", "marker_velocity", "marker_acceleration", "marker_angular_velocity", "energy", "constraint_residual"];
    if !m.joints.is_empty() {
        kinds.push("joint_reaction");
    }
    if !m.measures.is_empty() {
        kinds.push("measure");
    }
    if m.flexible.is_some() {
        kinds.extend(["modal_coordinates", "node_position", "node_velocity", "node_acceleration", "node_deformation", "strain_energy"]);
    }
    let kind = *rng.pick(&kinds);
    let key = match kind {
        "energy" | "constraint_residual" => String::new(),
        "joint_reaction" => format!("joint = \"{}\"\n", rng.pick(&m.joints).name),
        "measure" => format!("measure = \"{}\"\n", rng.pick(&m.measures)),
        "modal_coordinates" | "strain_energy" => format!("body = \"{}\"\n", m.flexible.as_ref().unwrap().0),
        k if k.starts_with("node_") => format!("body = \"{}\"\nnode = {}\n", m.flexible.as_ref().unwrap().0, rng.between(1, 21)),
        _ => format!("marker = \"{marker}\"\n"),
    };
    let n = m.text.matches("[[output]]").count();
    let _ = writeln!(m.text, "[[output]]\nname = \"out{n}\"\ntype = \"{kind}\"\n{key}");
}
