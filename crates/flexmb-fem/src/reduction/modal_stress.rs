//! Modal stresses: each mode's stress at the body's stress points (a solid's nodes, a shell's top
//! and bottom surfaces at its nodes, a beam section's extreme fibres at its nodes), recovered element
//! by element from the mode shape and averaged over the elements that share a point. A run then
//! has the stress of the deformed body as `σ(t) = Σⱼ aⱼ(t) σⱼ` (static correction modes included),
//! linear in the modal coordinates like the displacement `Ψ a`.

use serde::{Deserialize, Serialize};

use super::flexible_body::FlexibleBody;
use crate::element::{element_stress, StressPlace};
use crate::error::FemError;
use crate::mesh::FeModel;

/// The stresses of a body's modes at its stress points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModalStresses {
    /// The node of each stress point (index into [`FlexibleBody::nodes`]), in ascending order.
    pub nodes: Vec<usize>,
    /// Where at its node each stress point is.
    pub places: Vec<StressPlace>,
    /// For each mode (basis order), the stress at each point: `[σxx, σyy, σzz, σxy, σyz, σzx]` in
    /// body axes (Pa per unit modal coordinate).
    pub modes: Vec<Vec<[f64; 6]>>,
}

impl ModalStresses {
    /// The modal stresses of `body`, reduced from `model`: `None` if no element of the model
    /// recovers stresses.
    pub fn recover(model: &FeModel, body: &FlexibleBody) -> Result<Option<ModalStresses>, FemError> {
        let mesh = &model.mesh;
        let m = body.mode_count();
        // Sums and counts per (node, place, the element for points that are an element's alone), in
        // the order of the map: by node.
        type Key = (usize, StressPlace, Option<usize>);
        let mut sums: std::collections::BTreeMap<Key, (Vec<[f64; 6]>, usize)> = Default::default();
        for (e, element) in mesh.elements.iter().enumerate() {
            let Some(recovery) =
                element_stress(mesh, element).map_err(|source| FemError::Element { label: element.label, source })?
            else {
                continue;
            };
            let n = element.nodes.len();
            let mut u = nalgebra::DMatrix::zeros(6 * n, m);
            for (j, shape) in body.shapes.iter().enumerate() {
                for (a, &node) in element.nodes.iter().enumerate() {
                    for i in 0..3 {
                        u[(6 * a + i, j)] = shape.translation[node][i];
                        u[(6 * a + 3 + i, j)] = shape.rotation[node][i];
                    }
                }
            }
            let sigma = &recovery.matrix * u;
            for (p, &(a, place)) in recovery.points.iter().enumerate() {
                let owner = (!recovery.shared).then_some(e);
                let (sum, count) = sums.entry((element.nodes[a], place, owner)).or_insert_with(|| (vec![[0.0; 6]; m], 0));
                for (j, s) in sum.iter_mut().enumerate() {
                    for (k, value) in s.iter_mut().enumerate() {
                        *value += sigma[(6 * p + k, j)];
                    }
                }
                *count += 1;
            }
        }
        if sums.is_empty() {
            return Ok(None);
        }
        let mut stresses = ModalStresses { nodes: Vec::new(), places: Vec::new(), modes: vec![Vec::with_capacity(sums.len()); m] };
        for ((node, place, _), (sum, count)) in sums {
            stresses.nodes.push(node);
            stresses.places.push(place);
            for (j, s) in sum.into_iter().enumerate() {
                stresses.modes[j].push(s.map(|x| x / count as f64));
            }
        }
        Ok(Some(stresses))
    }

    /// Number of stress points.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether there is no stress point.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// `σ = Σⱼ aⱼ σⱼ` at every stress point, into `stress` (one entry per point).
    pub fn superpose(&self, a: &[f64], stress: &mut [[f64; 6]]) {
        stress.iter_mut().for_each(|s| *s = [0.0; 6]);
        for (aj, mode) in a.iter().zip(&self.modes) {
            for (s, sj) in stress.iter_mut().zip(mode) {
                for k in 0..6 {
                    s[k] += aj * sj[k];
                }
            }
        }
    }

    /// That the sizes agree with a body of `modes` modes and `nodes` nodes, and the values are finite.
    pub(super) fn validate(&self, modes: usize, nodes: usize) -> Result<(), String> {
        let points = self.nodes.len();
        if self.places.len() != points {
            return Err(format!("stresses: {} places for {points} stress points", self.places.len()));
        }
        if self.modes.len() != modes {
            return Err(format!("stresses: {} modes' stresses for {modes} modes", self.modes.len()));
        }
        if let Some(j) = self.modes.iter().position(|s| s.len() != points) {
            return Err(format!("stresses of mode {} do not have one entry per stress point ({points})", j + 1));
        }
        if self.nodes.iter().any(|&k| k >= nodes) {
            return Err(format!("stresses: a stress point refers to a node index beyond the {nodes} nodes"));
        }
        if self.nodes.windows(2).any(|w| w[0] > w[1]) {
            return Err("stresses: the stress points are not in ascending node order".to_string());
        }
        if self.modes.iter().flatten().flatten().any(|x| !x.is_finite()) {
            return Err("stresses: a value is not a finite number".to_string());
        }
        Ok(())
    }
}

/// Recovers the modal stresses of `body`, reduced from `model`, into `body.stresses`; a warning when
/// no element of the model recovers stresses (then `body.stresses` stays `None`).
pub fn add_modal_stresses(model: &FeModel, body: &mut FlexibleBody) -> Result<Option<String>, FemError> {
    body.stresses = ModalStresses::recover(model, body)?;
    Ok(body.stresses.is_none().then(|| "stresses were asked for, but no element of the model recovers them (solids, beams and shells do)".to_string()))
}

/// The von Mises equivalent stress of `[σxx, σyy, σzz, σxy, σyz, σzx]`:
/// `√(½((σxx − σyy)² + (σyy − σzz)² + (σzz − σxx)²) + 3 (σxy² + σyz² + σzx²))`.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let normal = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    (0.5 * normal + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
}
