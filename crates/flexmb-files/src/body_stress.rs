//! The stresses of flexible bodies in a run: for each body whose `[[flexible_body]]` table asks for
//! them (`stresses = true`), `σ = Σⱼ aⱼ σⱼ` at its stress points from the modal stresses of its
//! flexible-body file, turned to global axes (`A σ Aᵀ`), and at each node the point of largest von
//! Mises stress (a shell's top or bottom surface, a beam section's most stressed fibre). The
//! [`StressMonitor`] follows them at every output time and keeps each body's hot spot: the largest
//! von Mises stress, the node and place where and the time when it occurred. Nothing is allocated
//! per output time.

use std::ops::Range;
use std::sync::Arc;

use flexmb::analysis::OutputFrame;
use flexmb::math::{rotation_matrix, Mat3, Vec4};
use flexmb::model::BodyId;
use flexmb::Model;
use flexmb_fem::element::StressPlace;
use flexmb_fem::reduction::{von_mises, ModalStresses};
use serde_json::{json, Value};

use crate::model_file::{FlexibleBodyInfo, LoadedModel};

/// One flexible body's stress at the last state evaluated.
pub(crate) struct BodyStress {
    /// The body in the model.
    pub body: BodyId,
    /// The body's name.
    pub name: String,
    stresses: Arc<ModalStresses>,
    /// The stress points of each node (the points are in node order).
    node_points: Vec<Range<usize>>,
    /// σ at each stress point, body axes.
    point_stress: Vec<[f64; 6]>,
    /// At each node, σ (global axes) at its point of largest von Mises stress; zero at a node
    /// without stress points.
    pub node_stress: Vec<[f64; 6]>,
    /// At each node, the largest von Mises stress of its points.
    pub node_von_mises: Vec<f64>,
    /// At each node, the point of largest von Mises stress (`None` without stress points).
    node_place: Vec<Option<StressPlace>>,
}

impl BodyStress {
    /// The stress of the body of `info`, if its table asked for stresses.
    pub(crate) fn new(info: &FlexibleBodyInfo) -> Option<Self> {
        let stresses = Arc::clone(info.stresses.as_ref()?);
        let mut node_points = vec![0..0; info.nodes];
        let mut start = 0;
        while start < stresses.nodes.len() {
            let node = stresses.nodes[start];
            let end = start + stresses.nodes[start..].iter().take_while(|&&k| k == node).count();
            node_points[node] = start..end;
            start = end;
        }
        Some(Self {
            body: info.body,
            name: info.name.clone(),
            point_stress: vec![[0.0; 6]; stresses.len()],
            node_stress: vec![[0.0; 6]; info.nodes],
            node_von_mises: vec![0.0; info.nodes],
            node_place: vec![None; info.nodes],
            node_points,
            stresses,
        })
    }

    /// Evaluates the stress at the state `q`.
    pub(crate) fn evaluate(&mut self, model: &Model, q: &[f64]) {
        let range = model.layout().q_range(self.body).expect("a body of the loaded model");
        let qb = &q[range];
        let rotation = rotation_matrix(&Vec4::from_column_slice(&qb[3..7]));
        self.stresses.superpose(&qb[7..], &mut self.point_stress);
        for (node, points) in self.node_points.iter().enumerate() {
            let (mut best, mut place, mut value) = (None, None, 0.0);
            for p in points.clone() {
                let v = von_mises(&self.point_stress[p]);
                if best.is_none() || v > value {
                    (best, place, value) = (Some(p), Some(self.stresses.places[p]), v);
                }
            }
            self.node_von_mises[node] = value;
            self.node_place[node] = place;
            self.node_stress[node] = best.map_or([0.0; 6], |p| rotated(&rotation, &self.point_stress[p]));
        }
    }

    /// The node of largest von Mises stress: its index, the stress and the place there.
    fn maximum(&self) -> Option<(usize, f64, StressPlace)> {
        let (node, value) = self.node_von_mises.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
        Some((node, *value, self.node_place[node]?))
    }
}

/// `A σ Aᵀ` of `[σxx, σyy, σzz, σxy, σyz, σzx]`.
fn rotated(a: &Mat3, s: &[f64; 6]) -> [f64; 6] {
    let sigma = Mat3::new(s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2]);
    let g = a * sigma * a.transpose();
    [g[(0, 0)], g[(1, 1)], g[(2, 2)], g[(0, 1)], g[(1, 2)], g[(2, 0)]]
}

/// A body's largest von Mises stress over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct HotSpot {
    /// The body's name.
    pub body: String,
    /// The largest von Mises stress (Pa).
    pub von_mises: f64,
    /// The FE label of the node where it occurred.
    pub node: u64,
    /// Where at the node: a solid, a shell's top or bottom surface, a beam section's fibre.
    pub place: StressPlace,
    /// When it occurred (s).
    pub t: f64,
    /// The stress there and then, `[σxx, σyy, σzz, σxy, σyz, σzx]` in global axes (Pa).
    pub stress: [f64; 6],
}

impl HotSpot {
    /// The hot spot as the JSON summary holds it.
    pub fn to_json(&self) -> Value {
        json!({
            "body": self.body,
            "von_mises": self.von_mises,
            "node": self.node,
            "place": self.place.to_string(),
            "t": self.t,
            "stress": self.stress,
        })
    }
}

/// Follows the stresses of a run's flexible bodies at every output time and keeps each one's hot spot.
pub struct StressMonitor {
    bodies: Vec<BodyStress>,
    labels: Vec<Vec<u64>>,
    /// Each body's largest von Mises stress so far.
    largest: Vec<Option<Largest>>,
}

/// The largest von Mises stress so far: the value, node index, place, time and stress.
type Largest = (f64, usize, StressPlace, f64, [f64; 6]);

impl StressMonitor {
    /// The monitor of the bodies of `loaded` whose tables ask for stresses (none: it does nothing).
    pub fn new(loaded: &LoadedModel) -> Self {
        let bodies: Vec<BodyStress> = loaded.flexible_bodies.iter().filter_map(BodyStress::new).collect();
        let labels = bodies
            .iter()
            .map(|b| loaded.model.modal_body(b.body).map_or_else(Vec::new, |m| m.nodes.iter().map(|n| n.label).collect()))
            .collect();
        let largest = vec![None; bodies.len()];
        Self { bodies, labels, largest }
    }

    /// Whether no body's stresses are followed.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Evaluates the stresses at `frame` and updates the hot spots.
    pub fn observe(&mut self, model: &Model, frame: &OutputFrame) {
        for (body, largest) in self.bodies.iter_mut().zip(&mut self.largest) {
            body.evaluate(model, frame.q);
            let Some((node, value, place)) = body.maximum() else { continue };
            if largest.is_none_or(|(v, ..)| value > v) {
                *largest = Some((value, node, place, frame.t, body.node_stress[node]));
            }
        }
    }

    /// Each followed body's hot spot (bodies that saw no output time have none).
    pub fn hot_spots(&self) -> Vec<HotSpot> {
        let spots = self.bodies.iter().zip(&self.labels).zip(&self.largest);
        spots
            .filter_map(|((body, labels), largest)| {
                let (von_mises, node, place, t, stress) = (*largest)?;
                Some(HotSpot { body: body.name.clone(), von_mises, node: labels[node], place, t, stress })
            })
            .collect()
    }
}

/// One line per hot spot, for a run's report.
pub fn hot_spot_text(hot_spots: &[HotSpot]) -> String {
    hot_spots
        .iter()
        .map(|h| {
            format!(
                "stress hot spot of {}: von Mises {:.4e} Pa at node {} ({}) at t = {} s\n",
                h.body, h.von_mises, h.node, h.place, h.t
            )
        })
        .collect()
}
