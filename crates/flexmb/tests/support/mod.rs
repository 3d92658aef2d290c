//! Helpers shared by the physics tests: rigid bodies with offset centres of mass and full inertia
//! tensors, markers with a chosen z axis, and a simulation run collected into named columns.
#![allow(dead_code)]

use flexmb::analysis::{output_columns, simulate, SimulationError, SimulationReport, SimulationSettings};
use flexmb::body::{InitialState, LumpedNode, Marker, ModalBody, ModalDamping, RigidBody};
use flexmb::integrate::Tolerances;
use flexmb::force::{ForceElement, ForceKind};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{EulerParameters, Mat3, Vec3};
use flexmb::model::{BodyId, BodyRef, JointId, MarkerId, Model, ModelBuilder};

/// A rigid body with its frame at `position`, turned by `orientation`; `velocity`/`omega` (global) given
/// when `Some`.
#[allow(clippy::too_many_arguments)]
pub fn rigid(
    name: &str,
    mass: f64,
    center_of_mass: Vec3,
    inertia: Mat3,
    position: Vec3,
    orientation: EulerParameters,
    velocity: Option<Vec3>,
    omega: Option<Vec3>,
) -> RigidBody {
    RigidBody {
        name: name.into(),
        mass,
        center_of_mass,
        inertia,
        initial: InitialState { position, orientation, velocity, angular_velocity: omega },
    }
}

/// A marker with the given axes (columns x, y, z in the body frame).
pub fn marker_with_axes(b: &mut ModelBuilder, name: &str, body: BodyRef, origin: Vec3, axes: Mat3) -> MarkerId {
    b.add_marker(Marker { name: name.into(), body, origin, axes }).unwrap()
}

/// A marker with its axes parallel to the body frame.
pub fn marker(b: &mut ModelBuilder, name: &str, body: BodyRef, origin: Vec3) -> MarkerId {
    marker_with_axes(b, name, body, origin, Mat3::identity())
}

/// A proper frame whose z axis is along `z` (x chosen perpendicular to it).
pub fn frame_with_z(z: Vec3) -> Mat3 {
    let z = z.normalize();
    let helper = if z.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
    let x = (helper - z * z.dot(&helper)).normalize();
    let y = z.cross(&x);
    Mat3::from_columns(&[x, y, z])
}

pub fn joint(b: &mut ModelBuilder, name: &str, kind: JointKind, i: MarkerId, j: MarkerId) -> JointId {
    b.add_joint(Joint { name: name.into(), kind, marker_i: i, marker_j: j }).unwrap()
}

/// Settings with `rtol = atol = tol`.
pub fn settings(t_end: f64, output_step: f64, tol: f64) -> SimulationSettings {
    SimulationSettings {
        t_end,
        output_step,
        tolerances: Tolerances::new(tol, tol),
        ..Default::default()
    }
}

/// The frames of one simulation, by column name.
pub struct Run {
    pub t: Vec<f64>,
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
    pub report: SimulationReport,
}

impl Run {
    /// The time series of column `name` (panics with the list of columns if there is none).
    pub fn col(&self, name: &str) -> Vec<f64> {
        let k = self
            .columns
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no column '{name}'; columns are {:?}", self.columns));
        self.rows.iter().map(|r| r[k]).collect()
    }

    /// The three columns `name.x`, `name.y`, `name.z` as vectors.
    pub fn vec3(&self, name: &str) -> Vec<Vec3> {
        let (x, y, z) =
            (self.col(&format!("{name}.x")), self.col(&format!("{name}.y")), self.col(&format!("{name}.z")));
        (0..x.len()).map(|k| Vec3::new(x[k], y[k], z[k])).collect()
    }
}

/// Runs a simulation and collects every output frame (of the last run, where global error control ran it
/// again); the error keeps the frames received before it.
#[allow(clippy::result_large_err)]
pub fn try_run(model: &Model, settings: &SimulationSettings) -> Result<Run, (SimulationError, Run)> {
    let columns: Vec<String> = output_columns(model).into_iter().map(|c| c.name).collect();
    let mut t = Vec::new();
    let mut rows = Vec::new();
    let result = simulate(model, settings, &mut |f| {
        // Global error control runs again from t = 0: the last run's frames are the results.
        if f.t == 0.0 {
            t.clear();
            rows.clear();
        }
        t.push(f.t);
        rows.push(f.values.to_vec());
    });
    match result {
        Ok(report) => Ok(Run { t, columns, rows, report }),
        Err(e) => {
            let report = (*e.report).clone();
            Err((e, Run { t, columns, rows, report }))
        }
    }
}

/// Runs a simulation that must succeed.
pub fn run(model: &Model, settings: &SimulationSettings) -> Run {
    try_run(model, settings).unwrap_or_else(|(e, _)| panic!("simulation of '{}' failed: {e}", model.name()))
}

/// The assembled, velocity-analysed initial state of `model` and its accelerations: where an
/// integrator starts.
pub fn consistent_start(model: &Model) -> (flexmb::analysis::State, flexmb::analysis::Accelerations) {
    use flexmb::analysis::{assemble, velocity_analysis, AccelerationSolver, State};
    let mut data = flexmb::Data::new(model);
    let mut state = State::initial(model);
    assemble(model, &mut data, &mut state, Default::default()).unwrap();
    velocity_analysis(model, &mut data, &mut state).unwrap();
    let acc = AccelerationSolver::new(model).solve(model, &mut data, 0.0, &state.q, &state.v, &state.active).unwrap().clone();
    (state, acc)
}

/// Largest absolute value of `f(k)` over the frames.
pub fn max_over(n: usize, f: impl Fn(usize) -> f64) -> f64 {
    (0..n).map(f).fold(0.0, f64::max)
}

/// Angle unwrapped to be continuous.
pub fn unwrap_angles(a: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(a.len());
    let mut offset = 0.0;
    for k in 0..a.len() {
        if k > 0 {
            let d = a[k] - a[k - 1];
            if d > std::f64::consts::PI {
                offset -= std::f64::consts::TAU;
            } else if d < -std::f64::consts::PI {
                offset += std::f64::consts::TAU;
            }
        }
        out.push(a[k] + offset);
    }
    out
}

/// A pendulum of length `l` swinging about the global z axis through the origin, bob (mass `m`,
/// inertia `ic` about its centre) released at rest `theta0` from the hanging position; gravity −y.
pub fn pendulum(l: f64, m: f64, ic: f64, theta0: f64, g: f64) -> ModelBuilder {
    let mut b = ModelBuilder::new("pendulum").gravity(Vec3::new(0.0, -g, 0.0));
    let pose = EulerParameters::from_axis_angle(&Vec3::z(), theta0).unwrap();
    let bob = b.add_body(rigid("bob", m, Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(ic, ic, ic)), Vec3::new(l * theta0.sin(), -l * theta0.cos(), 0.0), pose, None, None)).unwrap();
    let gm = marker(&mut b, "pivot_ground", BodyRef::Ground, Vec3::zeros());
    let bm = marker(&mut b, "pivot_bob", BodyRef::Body(bob), Vec3::new(0.0, l, 0.0));
    marker(&mut b, "bob_centre", BodyRef::Body(bob), Vec3::zeros());
    joint(&mut b, "pivot", JointKind::Revolute, gm, bm);
    b
}

/// Complete elliptic integral of the first kind `K(k)` by the arithmetic–geometric mean.
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut g) = (1.0_f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        let an = 0.5 * (a + g);
        g = (a * g).sqrt();
        a = an;
    }
    std::f64::consts::PI / (2.0 * a)
}

/// The elements of a slider-crank built by [`slider_crank_linkage`].
pub struct SliderCrank {
    pub crank_joint: JointId,
    pub slide: JointId,
    pub pivot_ground: MarkerId,
    pub pivot: MarkerId,
    pub rod_slider_end: MarkerId,
    pub slider_pin: MarkerId,
}

/// A slider-crank in the x-y plane: crank of radius `r` on a revolute to ground about global z, rod of
/// length `l`, slider on a translational joint along global x; crank along +x at the start. Joints as in
/// `models/slider_crank.toml` (revolute, spherical, universal, translational), so the loop has no
/// redundant equations: one degree of freedom, zero with a driver on `crank_joint`'s markers.
pub fn slider_crank_linkage(b: &mut ModelBuilder, r: f64, l: f64, crank_omega: Option<Vec3>) -> SliderCrank {
    let id = EulerParameters::identity();
    let crank = b.add_body(rigid(
        "crank",
        0.5,
        Vec3::new(r / 2.0, 0.0, 0.0),
        Mat3::from_diagonal(&Vec3::new(4.17e-5, 6.04e-4, 6.38e-4)),
        Vec3::zeros(),
        id,
        None,
        crank_omega,
    )).unwrap();
    let rod = b.add_body(rigid(
        "rod",
        0.8,
        Vec3::new(l / 2.0, 0.0, 0.0),
        Mat3::from_diagonal(&Vec3::new(4.83e-5, 6.01e-3, 6.04e-3)),
        Vec3::new(r, 0.0, 0.0),
        id,
        None,
        None,
    )).unwrap();
    let slider = b.add_body(rigid(
        "slider",
        1.0,
        Vec3::zeros(),
        Mat3::from_diagonal(&Vec3::new(4.17e-4, 4.17e-4, 4.17e-4)),
        Vec3::new(r + l, 0.0, 0.0),
        id,
        None,
        None,
    )).unwrap();
    let pivot_ground = marker(b, "crank_pivot_ground", BodyRef::Ground, Vec3::zeros());
    let pivot = marker(b, "crank_pivot", BodyRef::Body(crank), Vec3::zeros());
    let pin = marker(b, "crank_pin", BodyRef::Body(crank), Vec3::new(r, 0.0, 0.0));
    let rod_a = marker(b, "rod_crank_end", BodyRef::Body(rod), Vec3::zeros());
    let rod_slider_end =
        marker_with_axes(b, "rod_slider_end", BodyRef::Body(rod), Vec3::new(l, 0.0, 0.0), frame_with_z(Vec3::y()));
    let slider_pin = marker(b, "slider_pin", BodyRef::Body(slider), Vec3::zeros());
    let guide = marker_with_axes(b, "guide", BodyRef::Ground, Vec3::zeros(), frame_with_z(Vec3::x()));
    let slider_guide = marker_with_axes(b, "slider_guide", BodyRef::Body(slider), Vec3::zeros(), frame_with_z(Vec3::x()));
    let crank_joint = joint(b, "crank_pivot", JointKind::Revolute, pivot_ground, pivot);
    joint(b, "crank_rod", JointKind::Spherical, pin, rod_a);
    joint(b, "rod_slider", JointKind::Universal, rod_slider_end, slider_pin);
    let slide = joint(b, "slide", JointKind::Translational, guide, slider_guide);
    SliderCrank { crank_joint, slide, pivot_ground, pivot, rod_slider_end, slider_pin }
}

/// A flexible beam-like body: 8 lumped nodes 0.1 m apart along x, 3 modes of modal stiffness
/// `stiffness` (shapes not from an FE model, but smooth and with rotary inertia), 2 % modal damping,
/// initial modal rates `rates`, hanging from ground by a revolute at its first node, gravity −y.
/// Returns the builder, the body and a marker at its last node.
pub fn lumped_flexible_pendulum(stiffness: [f64; 3], rates: [f64; 3]) -> (ModelBuilder, BodyId, MarkerId) {
    use nalgebra::{DMatrix, DVector, Matrix3xX};
    let m = 3;
    let nodes: Vec<LumpedNode> = (0..8)
        .map(|i| {
            let x = 0.1 * i as f64;
            let shape = |k: usize| (x * (k + 1) as f64 * 1.7).sin() * x;
            let component = |r: usize, k: usize, weights: [f64; 3]| weights[r] * shape(k);
            LumpedNode {
                position: Vec3::new(x, 0.0, 0.0),
                mass: 0.2,
                rotary_inertia: Mat3::from_diagonal(&Vec3::new(1e-4, 2e-4, 2e-4)),
                psi: Matrix3xX::from_fn(m, |r, k| component(r, k, [0.0, 1.0, 0.3])),
                theta: Matrix3xX::from_fn(m, |r, k| component(r, k, [0.0, 0.0, 0.5])),
            }
        })
        .collect();
    let mut modal = ModalBody::from_lumped_nodes(&nodes, DMatrix::from_diagonal(&DVector::from_vec(stiffness.to_vec()))).unwrap();
    modal.initial_rates = DVector::from_vec(rates.to_vec());
    modal.damping = modal.damping_matrix(&ModalDamping::Ratios(vec![0.02])).unwrap();
    let mut b = ModelBuilder::new("flexible pendulum").gravity(Vec3::new(0.0, -9.81, 0.0));
    let beam = b.add_flexible_body("beam", Default::default(), modal).unwrap();
    let hinge = b.add_node_marker("hinge", beam, 0, Mat3::identity()).unwrap();
    let tip = b.add_node_marker("tip", beam, 7, Mat3::identity()).unwrap();
    let pivot = marker(&mut b, "pivot", BodyRef::Ground, Vec3::zeros());
    joint(&mut b, "hinge", JointKind::Revolute, pivot, hinge);
    (b, beam, tip)
}

/// A pendulum (bob 1 kg, 1 m, swinging in the x–y plane) carrying a small slider (10 g) on a
/// translational joint along the hinge axis z, held by a stiff spring (1e4 N/m: 1000 rad/s); the slider
/// starts `x0` from the spring's rest length. Gravity and the swing act across the slider's axis, so the
/// spring's rest position is exact at every instant and its energy is that of the fast oscillation alone.
pub fn pendulum_with_stiff_slider(x0: f64) -> Model {
    pendulum_with_slider(x0, 1e4).build().unwrap()
}

/// [`pendulum_with_stiff_slider`] with a spring of `stiffness` (N/m; the slider's 10 g vibrates at
/// `√(stiffness / 0.01)` rad/s), before it is built: the slider's markers are `rail` (on the bob) and
/// `runner` (on the slider), both at the origins of their bodies, the slider's global z its own
/// coordinate, `−(0.1 + x0 cos ωt)`.
pub fn pendulum_with_slider(x0: f64, stiffness: f64) -> ModelBuilder {
    let (l, theta0, s0) = (1.0, 1.0_f64, 0.1);
    let mut b = pendulum(l, 1.0, 1e-3, theta0, 9.81);
    let bob = flexmb::model::BodyId(0);
    let pose = flexmb::math::EulerParameters::from_axis_angle(&Vec3::z(), theta0).unwrap();
    let bob_position = Vec3::new(l * theta0.sin(), -l * theta0.cos(), 0.0);
    let slider = b.add_body(rigid(
        "slider",
        0.01,
        Vec3::zeros(),
        Mat3::from_diagonal(&Vec3::new(1e-6, 1e-6, 1e-6)),
        bob_position - Vec3::new(0.0, 0.0, s0 + x0),
        pose,
        None,
        None,
    )).unwrap();
    let rail = marker(&mut b, "rail", BodyRef::Body(bob), Vec3::zeros());
    let runner = marker(&mut b, "runner", BodyRef::Body(slider), Vec3::zeros());
    joint(&mut b, "slide", JointKind::Translational, rail, runner);
    b.add_force(ForceElement {
        name: "spring".into(),
        kind: ForceKind::TranslationalSpringDamper {
            marker_i: rail,
            marker_j: runner,
            stiffness,
            damping: 0.0,
            free_length: s0,
            actuator: None,
        },
    }).unwrap();
    b
}

/// The peer's chain: `n` rods of 1 kg and 0.5 m on spherical joints, straight along x at rest, falling.
pub fn peer_chain(n: usize) -> Model {
    let l = 0.5;
    let mut b = ModelBuilder::new("chain").gravity(Vec3::new(0.0, 0.0, -9.81));
    let mut previous = marker(&mut b, "anchor", BodyRef::Ground, Vec3::zeros());
    for i in 0..n {
        let inertia = Mat3::from_diagonal(&Vec3::new(1e-4, l * l / 12.0, l * l / 12.0));
        let position = Vec3::new((i as f64 + 0.5) * l, 0.0, 0.0);
        let rod = b
            .add_body(rigid(&format!("rod{i}"), 1.0, Vec3::zeros(), inertia, position, EulerParameters::identity(), None, None))
            .unwrap();
        let start = marker(&mut b, &format!("rod{i}_start"), BodyRef::Body(rod), Vec3::new(-0.5 * l, 0.0, 0.0));
        joint(&mut b, &format!("s{i}"), JointKind::Spherical, previous, start);
        previous = marker(&mut b, &format!("rod{i}_end"), BodyRef::Body(rod), Vec3::new(0.5 * l, 0.0, 0.0));
    }
    b.build().unwrap()
}
