//! The linear state-space model of a mechanism at an operating point (Adams' STATEMAT):
//!
//! ```text
//! ẋ = A x + B u,   y = C x + D u,    x = [δz; δż]
//! ```
//!
//! in the independent coordinates of [`reduce_to_independent`](super::reduce_to_independent). The
//! inputs `u` are loads added by force elements, and drivers' offsets, named as in the model:
//!
//! - `NAME.x`, `NAME.y`, `NAME.z` for an applied force or torque `NAME`: a force (N) or torque (N m)
//!   along that global axis at the element's marker;
//! - `NAME` for a spring-damper: an actuator force (N, pushing the markers apart) or torque (N m, about
//!   the joint's `z_i`, on the body of marker `j`), added to the element's;
//! - `NAME`, `NAME.rate`, `NAME.acceleration` for an angle or displacement driver `NAME`: an offset `u`
//!   added to its prescribed angle (rad) or displacement (m), its rate `u̇` and its acceleration `ü`,
//!   three inputs a user sets consistently (a base excitation `u(t)` enters through all three;
//!   [`driver_inputs`](super::driver_inputs) has the equations);
//! - the name of a parameter of a model built in code ([`ModelBuilder::add_parameter`](crate::ModelBuilder::add_parameter)).
//!
//! The outputs `y` are measures. `A` is [`state_matrix`](super::state_matrix);
//! `B = [0; M_z⁻¹ Nᵀ Q_u]` with `Q_u` the generalized force of a unit input (by virtual power, from the
//! markers' velocities; for a parameter `−∂g/∂u`, the dynamic residual's change with accelerations and
//! multipliers held, by central differences); for a driver `B = [0; −M_z⁻¹ K_zu]`, `[0; −M_z⁻¹ C_zu]`
//! and `[0; −M_z⁻¹ M_zu]` for its offset, rate and acceleration;
//! `C` by central differences of the measures along `δx = N δz`, `δv = N δż + (Ṅ + W N) δz`; `D` by
//! central differences of the measures in the inputs (zero unless a measure reads a parameter, or the
//! part of the mechanism a driver moves: along `δx = P u`, `δv = P u̇ + (Ṗ + W P) u`; the measures read
//! positions and velocities, so a driver's acceleration has no `D`).

use faer::linalg::solvers::Solve;
use faer::Mat;

use super::{driver_inputs, linearize_at, state_matrix, Accelerations, DriverInputs, ReducedLinearization, State};
use crate::data::Data;
use crate::model::Model;
use crate::stage::{equations_of_motion, measures, retract, run_kinematic_stages};

/// `A, B, C, D` with the names of the states, inputs and outputs.
#[derive(Clone, Debug)]
pub struct StateSpace {
    /// `2n × 2n`.
    pub a: Mat<f64>,
    /// `2n × inputs`.
    pub b: Mat<f64>,
    /// `outputs × 2n`.
    pub c: Mat<f64>,
    /// `outputs × inputs`.
    pub d: Mat<f64>,
    /// The states: the independent coordinates, then their rates (`<name>.rate`).
    pub states: Vec<String>,
    /// The inputs (loads, drivers' offsets and their rates and accelerations, parameters).
    pub inputs: Vec<String>,
    /// The outputs (measures).
    pub outputs: Vec<String>,
}

/// The relative step of the central differences.
const STEP: f64 = 1e-6;

/// The state-space model of `reduced` (linearized at `state` with `acc`) for the parameters `inputs`
/// and the measures `outputs`. A name that is not a parameter, or not a measure, of `model` is an error
/// that lists the names there are. `data`'s parameter values are those of the operating point; it is
/// left evaluated at some nearby state.
pub fn state_space(
    model: &Model,
    data: &mut Data,
    state: &State,
    acc: &Accelerations,
    reduced: &ReducedLinearization,
    inputs: &[String],
    outputs: &[String],
) -> Result<StateSpace, String> {
    let sources = inputs.iter().map(|name| input_source(model, name)).collect::<Result<Vec<_>, _>>()?;
    let drivers = driven(&sources);
    let driver_terms = if drivers.is_empty() {
        None
    } else {
        let lin = linearize_at(model, data, state, acc);
        Some(driver_inputs(model, data, state, acc, &lin, &drivers)?.1)
    };
    let measured = outputs.iter().map(|name| find(name, "measure", model.measures.iter().map(|m| m.name.as_str()))).collect::<Result<Vec<_>, _>>()?;
    let n = reduced.degrees_of_freedom();
    let a = state_matrix(reduced);
    let nt = reduced.independent.basis.transpose();
    let lu = reduced.mass.partial_piv_lu();
    let mut b = Mat::zeros(2 * n, inputs.len());
    let mut d = Mat::zeros(outputs.len(), inputs.len());
    for (col, source) in sources.iter().enumerate() {
        let generalized = match *source {
            InputSource::Load(load) => unit_load(model, data, state, load),
            InputSource::Driver(ref name, derivative) => {
                let terms = driver_terms.as_ref().expect("the driver terms of a driver input");
                let k = drivers.iter().position(|d| d == name).unwrap_or(0);
                let column = driver_column(terms, derivative, k);
                let column = lu.solve(&Mat::from_fn(n, 1, |i, _| -column[(i, 0)]));
                for i in 0..n {
                    b[(n + i, col)] = column[(i, 0)];
                }
                let y = driver_feedthrough(model, data, state, terms, derivative, k, &measured);
                for (r, x) in y.iter().enumerate() {
                    d[(r, col)] = *x;
                }
                continue;
            }
            InputSource::Parameter(p) => {
                let u0 = data.parameters[p];
                let h = STEP * u0.abs().max(1.0);
                let mut at = |u: f64| {
                    data.parameters[p] = u;
                    (residual(model, data, state, acc), measured_values(model, data, state.t, &state.q, &state.v, &measured))
                };
                let ((g_plus, y_plus), (g_minus, y_minus)) = (at(u0 + h), at(u0 - h));
                data.parameters[p] = u0;
                for (r, (yp, ym)) in y_plus.iter().zip(&y_minus).enumerate() {
                    d[(r, col)] = (yp - ym) / (2.0 * h);
                }
                g_plus.iter().zip(&g_minus).map(|(x, y)| -(x - y) / (2.0 * h)).collect()
            }
        };
        let q_u = Mat::from_fn(model.layout.nv, 1, |i, _| generalized[i]);
        let column = lu.solve(&(nt * &q_u));
        for i in 0..n {
            b[(n + i, col)] = column[(i, 0)];
        }
    }
    let mut c = Mat::zeros(outputs.len(), 2 * n);
    let (basis, rate) = (&reduced.independent.basis, &reduced.basis_rate);
    let size = (0..basis.nrows()).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| basis[(i, j)].abs()).fold(1.0, f64::max);
    let h = STEP / size;
    for col in 0..2 * n {
        let mut moved = |sign: f64| {
            let mut q = state.q.clone();
            let mut v = state.v.clone();
            if col < n {
                let dx: Vec<f64> = (0..basis.nrows()).map(|i| sign * h * basis[(i, col)]).collect();
                retract(&model.layout, &state.q, &dx, &mut q);
                v.iter_mut().enumerate().for_each(|(i, x)| *x += sign * h * rate[(i, col)]);
            } else {
                v.iter_mut().enumerate().for_each(|(i, x)| *x += sign * h * basis[(i, col - n)]);
            }
            measured_values(model, data, state.t, &q, &v, &measured)
        };
        let (plus, minus) = (moved(1.0), moved(-1.0));
        for r in 0..outputs.len() {
            c[(r, col)] = (plus[r] - minus[r]) / (2.0 * h);
        }
    }
    let names = &reduced.independent.names;
    let states = names.iter().cloned().chain(names.iter().map(|s| format!("{s}.rate"))).collect();
    Ok(StateSpace { a, b, c, d, states, inputs: inputs.to_vec(), outputs: outputs.to_vec() })
}

/// Where an input acts.
#[derive(Clone, Debug)]
enum InputSource {
    Load(UnitLoad),
    Parameter(usize),
    /// A driver's offset (0), its rate (1) or its acceleration (2).
    Driver(String, usize),
}

/// The drivers among the inputs, each once, in order.
fn driven(sources: &[InputSource]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for source in sources {
        if let InputSource::Driver(name, _) = source {
            if !names.contains(name) {
                names.push(name.clone());
            }
        }
    }
    names
}

/// The reduced equations' term of driver `k`'s offset, rate or acceleration (`K_zu`, `C_zu`, `M_zu`).
fn driver_column(terms: &DriverInputs, derivative: usize, k: usize) -> Mat<f64> {
    let matrix = [&terms.stiffness, &terms.damping, &terms.mass][derivative];
    Mat::from_fn(matrix.nrows(), 1, |i, _| matrix[(i, k)])
}

/// `D` of driver `k`'s offset (the measures along `δx = P u`, `δv = (Ṗ + W P) u`) or rate
/// (`δv = P u̇`), by central differences; zero for its acceleration.
fn driver_feedthrough(model: &Model, data: &mut Data, state: &State, terms: &DriverInputs, derivative: usize, k: usize, measured: &[usize]) -> Vec<f64> {
    if derivative == 2 {
        return vec![0.0; measured.len()];
    }
    let (motion, rate) = (&terms.motion, &terms.motion_rate);
    let size = (0..motion.nrows()).map(|i| motion[(i, k)].abs()).fold(1.0, f64::max);
    let h = STEP / size;
    let mut moved = |sign: f64| {
        let mut q = state.q.clone();
        let mut v = state.v.clone();
        if derivative == 0 {
            let dx: Vec<f64> = (0..motion.nrows()).map(|i| sign * h * motion[(i, k)]).collect();
            retract(&model.layout, &state.q, &dx, &mut q);
            v.iter_mut().enumerate().for_each(|(i, x)| *x += sign * h * rate[(i, k)]);
        } else {
            v.iter_mut().enumerate().for_each(|(i, x)| *x += sign * h * motion[(i, k)]);
        }
        measured_values(model, data, state.t, &q, &v, measured)
    };
    let (plus, minus) = (moved(1.0), moved(-1.0));
    plus.iter().zip(&minus).map(|(p, m)| (p - m) / (2.0 * h)).collect()
}

/// A unit load: a force or torque along a global axis at a marker, or a spring-damper's actuator.
#[derive(Clone, Copy, Debug)]
enum UnitLoad {
    Force(crate::model::MarkerId, usize),
    Torque(crate::model::MarkerId, usize),
    Between(crate::model::MarkerId, crate::model::MarkerId),
    AboutJoint(crate::model::JointId),
}

fn input_source(model: &Model, name: &str) -> Result<InputSource, String> {
    use crate::force::ForceKind;
    let (element, axis) = match name.rsplit_once('.') {
        Some((e, a)) if ["x", "y", "z"].contains(&a) => (e, Some(["x", "y", "z"].iter().position(|c| *c == a).unwrap_or(0))),
        _ => (name, None),
    };
    if let Some(force) = model.forces.iter().find(|f| f.name == element) {
        let load = match (&force.kind, axis) {
            (ForceKind::AppliedForce { marker, .. }, Some(k)) => UnitLoad::Force(*marker, k),
            (ForceKind::AppliedTorque { marker, .. }, Some(k)) => UnitLoad::Torque(*marker, k),
            (ForceKind::TranslationalSpringDamper { marker_i, marker_j, .. }, None) => UnitLoad::Between(*marker_i, *marker_j),
            (ForceKind::RotationalSpringDamper { joint, .. }, None) => UnitLoad::AboutJoint(*joint),
            (kind, _) => {
                let form = if matches!(kind, ForceKind::AppliedForce { .. } | ForceKind::AppliedTorque { .. }) { "NAME.x, NAME.y or NAME.z" } else { "NAME" };
                return Err(format!("input '{name}': the {} '{element}' is an input as {form}", kind.keyword()));
            }
        };
        return Ok(InputSource::Load(load));
    }
    if let Some(p) = model.parameters.iter().position(|p| p.name == name) {
        return Ok(InputSource::Parameter(p));
    }
    let (driver, derivative) = match name.rsplit_once('.') {
        Some((d, "rate")) => (d, 1),
        Some((d, "acceleration")) => (d, 2),
        _ => (name, 0),
    };
    if model.joints.iter().any(|j| j.name == driver && j.kind.is_driver()) {
        return Ok(InputSource::Driver(driver.to_string(), derivative));
    }
    let known: Vec<String> = model
        .forces
        .iter()
        .map(|f| match f.kind {
            ForceKind::AppliedForce { .. } | ForceKind::AppliedTorque { .. } => format!("{}.x", f.name),
            _ => f.name.clone(),
        })
        .chain(model.parameters.iter().map(|p| p.name.clone()))
        .chain(model.joints.iter().filter(|j| j.kind.is_driver()).map(|j| format!("{0} ({0}.rate, {0}.acceleration)", j.name)))
        .collect();
    let list = if known.is_empty() { "it has no force elements or drivers".to_string() } else { format!("inputs are {}", known.join(", ")) };
    Err(format!("input '{name}' is not a force element or driver of the model: {list}"))
}

/// The generalized force `Q_u` of a unit load, by virtual power: `Q_u[k]` is the load's power when the
/// velocities are the unit vector `e_k`.
fn unit_load(model: &Model, data: &mut Data, state: &State, load: UnitLoad) -> Vec<f64> {
    let nv = model.layout.nv;
    let mut v = vec![0.0; nv];
    let mut q_u = vec![0.0; nv];
    for k in 0..nv {
        v[k] = 1.0;
        run_kinematic_stages(model, data, state.t, &state.q, &v);
        let m = &data.markers;
        q_u[k] = match load {
            UnitLoad::Force(marker, axis) => m[marker.0].velocity[axis],
            UnitLoad::Torque(marker, axis) => m[marker.0].angular_velocity[axis],
            UnitLoad::Between(i, j) => {
                let d = m[j.0].position - m[i.0].position;
                let norm = d.norm();
                if norm > 0.0 { d.dot(&(m[j.0].velocity - m[i.0].velocity)) / norm } else { 0.0 }
            }
            UnitLoad::AboutJoint(joint) => {
                let jt = &model.joints[joint.0];
                let (mi, mj) = (&m[jt.marker_i.0], &m[jt.marker_j.0]);
                mi.axes.column(2).dot(&(mj.angular_velocity - mi.angular_velocity))
            }
        };
        v[k] = 0.0;
    }
    q_u
}

fn find<'a>(name: &str, what: &str, mut names: impl Iterator<Item = &'a str> + Clone) -> Result<usize, String> {
    names.clone().position(|n| n == name).ok_or_else(|| {
        let known: Vec<&str> = names.by_ref().collect();
        let list = if known.is_empty() { "it has none".to_string() } else { format!("it has {}", known.join(", ")) };
        format!("the model has no {what} '{name}': {list}")
    })
}

/// `g = M v̇ + h − Q + Bᵀλ` at the state with the accelerations and multipliers held.
fn residual(model: &Model, data: &mut Data, state: &State, acc: &Accelerations) -> Vec<f64> {
    let l = &model.layout;
    let mut g = vec![0.0; l.nv + l.nc];
    equations_of_motion(model, data, &state.active, state.t, &state.q, &state.v, &acc.vdot, &acc.lambda, &mut g);
    g.truncate(l.nv);
    g
}

fn measured_values(model: &Model, data: &mut Data, t: f64, q: &[f64], v: &[f64], which: &[usize]) -> Vec<f64> {
    run_kinematic_stages(model, data, t, q, v);
    measures(model, data);
    which.iter().map(|&k| data.measures[k]).collect()
}
