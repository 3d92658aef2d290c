//! The coupling graph of a model: which bodies' equations read which bodies' states, through joints
//! (the constraint forces `Bᵀλ` and the constraint rows of a joint read both its bodies) and force
//! elements (a force acts on the bodies of its markers and reads those and the bodies of the measures
//! its expressions use). The sparse patterns of the iteration matrices and of the linearization, and
//! the colouring of their finite-difference columns, are derived from it once per model.

use crate::force::ForceKind;
use crate::measure::MeasureKind;
use crate::model::{BodyId, JointId, MarkerId, MeasureId, Model};

/// The bodies coupled through joints and force elements, by body index (ground is no body).
#[derive(Clone, Debug)]
pub(crate) struct Coupling {
    /// The bodies each joint connects: none, one or two, in the order of its markers `i`, `j`.
    pub joint_bodies: Vec<Vec<usize>>,
    /// The joints that connect each body, in joint order.
    pub joints_of: Vec<Vec<usize>>,
    /// For each body `b`, the bodies whose dynamic equations read `b`'s state (sorted, `b` included):
    /// those sharing a joint with `b`, and those a force element acts on that reads `b`.
    pub readers: Vec<Vec<usize>>,
    /// For each body `b`, `b` and the bodies sharing a joint with it (sorted).
    pub joint_neighbours: Vec<Vec<usize>>,
}

impl Coupling {
    /// The coupling graph of `model`.
    pub fn new(model: &Model) -> Self {
        let nb = model.bodies.len();
        let joint_bodies: Vec<Vec<usize>> =
            model.joints.iter().map(|j| model.joint_bodies(j).into_iter().flatten().map(|b| b.0).collect()).collect();
        let mut joints_of: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for (k, bodies) in joint_bodies.iter().enumerate() {
            for &b in bodies {
                joints_of[b].push(k);
            }
        }
        joints_of.iter_mut().for_each(|j| j.dedup());
        let mut joint_neighbours: Vec<Vec<usize>> = (0..nb).map(|b| vec![b]).collect();
        for bodies in &joint_bodies {
            for &a in bodies {
                joint_neighbours[a].extend(bodies.iter().copied());
            }
        }
        let mut readers = joint_neighbours.clone();
        for (acted, read) in force_couplings(model) {
            for &r in &read {
                readers[r].extend(acted.iter().copied());
            }
        }
        for list in readers.iter_mut().chain(joint_neighbours.iter_mut()) {
            list.sort_unstable();
            list.dedup();
        }
        Self { joint_bodies, joints_of, readers, joint_neighbours }
    }
}

/// For each body, whether a force element acts on it or reads its state.
pub(crate) fn bodies_under_force_elements(model: &Model) -> Vec<bool> {
    let mut under = vec![false; model.bodies.len()];
    for (acted, read) in force_couplings(model) {
        for b in acted.into_iter().chain(read) {
            under[b] = true;
        }
    }
    under
}

/// For each force element: the bodies it acts on and the bodies whose state it reads (through its
/// markers and the measures its expressions use).
fn force_couplings(model: &Model) -> Vec<(Vec<usize>, Vec<usize>)> {
    let marker_body = |m: MarkerId| model.markers[m.0].body.body().map(|b: BodyId| b.0);
    let joint_bodies = |j: JointId| {
        let jt = &model.joints[j.0];
        [marker_body(jt.marker_i), marker_body(jt.marker_j)]
    };
    let measure_bodies = |m: MeasureId| -> Vec<Option<usize>> {
        match model.measures[m.0].kind {
            MeasureKind::JointAngle(j)
            | MeasureKind::JointRate(j)
            | MeasureKind::JointDisplacement(j)
            | MeasureKind::JointVelocity(j) => joint_bodies(j).to_vec(),
            MeasureKind::Distance(a, b) | MeasureKind::DistanceRate(a, b) => vec![marker_body(a), marker_body(b)],
            MeasureKind::Position(a, _) | MeasureKind::Velocity(a, _) | MeasureKind::Speed(a) => vec![marker_body(a)],
            MeasureKind::Parameter(_) => Vec::new(),
        }
    };
    model
        .forces
        .iter()
        .map(|f| {
            let acted: Vec<Option<usize>> = match &f.kind {
                ForceKind::TranslationalSpringDamper { marker_i, marker_j, .. } => {
                    vec![marker_body(*marker_i), marker_body(*marker_j)]
                }
                ForceKind::RotationalSpringDamper { joint, .. } => joint_bodies(*joint).to_vec(),
                ForceKind::AppliedForce { marker, .. } | ForceKind::AppliedTorque { marker, .. } => {
                    vec![marker_body(*marker)]
                }
            };
            let mut read = acted.clone();
            for e in f.kind.expressions() {
                for m in e.measures() {
                    read.extend(measure_bodies(m));
                }
            }
            (acted.into_iter().flatten().collect(), read.into_iter().flatten().collect())
        })
        .collect()
}
