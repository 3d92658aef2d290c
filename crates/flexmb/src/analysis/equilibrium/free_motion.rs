//! A motion under an unbalanced load: the directions the constrained stiffness does not resist
//! (the null space of `Nᵀ K N`) along which the generalized force `Nᵀ f` has a component. Such a
//! mechanism has no static equilibrium (a slider on a horizontal guide pushed by a constant force, a
//! free body under gravity); the motion is named body by body, as a translation and a rotation in
//! global axes and a deformation of the modal coordinates.

use faer::Mat;

use crate::math::Vec3;
use crate::model::Model;
use crate::stage::run_kinematic_stages;
use crate::data::Data;

/// One body's share of a free motion.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodyMotion {
    /// The body's name.
    pub body: String,
    /// Direction of its translation (global, unit; zero when it does not translate).
    pub translation: [f64; 3],
    /// Axis of its rotation (global, unit; zero when it does not turn).
    pub rotation: [f64; 3],
    /// Whether its modal coordinates take part (a flexible body deforming).
    pub deforms: bool,
}

/// A motion the mechanism makes under its loads without ever coming to rest.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FreeMotion {
    /// The bodies that move, with their directions.
    pub bodies: Vec<BodyMotion>,
    /// The unbalanced generalized force along the motion (N for a translation, N m for a rotation,
    /// per unit of the motion's velocity-space direction).
    pub unbalanced_force: f64,
}

impl std::fmt::Display for FreeMotion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self.bodies.iter().map(describe).collect();
        write!(f, "{} (unbalanced generalized force {:.3e})", parts.join("; "), self.unbalanced_force)
    }
}

fn describe(m: &BodyMotion) -> String {
    let mut what = Vec::new();
    if m.translation != [0.0; 3] {
        what.push(format!("translation along {}", direction(&m.translation)));
    }
    if m.rotation != [0.0; 3] {
        what.push(format!("rotation about {}", direction(&m.rotation)));
    }
    if m.deforms {
        what.push("deformation".to_string());
    }
    format!("body '{}': {}", m.body, what.join(" and "))
}

/// `+x`, `−y`, … for a direction along a global axis, else its components.
fn direction(d: &[f64; 3]) -> String {
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        if (d[k].abs() - 1.0).abs() < 1e-6 {
            return format!("{}{axis}", if d[k] > 0.0 { "+" } else { "-" });
        }
    }
    format!("({:.3}, {:.3}, {:.3})", d[0], d[1], d[2])
}

/// The free motion in the velocity-space direction `d` (length `nv`; the load pushes along it) at
/// `q`, with the unbalanced force `unbalanced_force`. Body parts below 10⁻³ of the largest are left
/// out.
pub(super) fn free_motion(model: &Model, data: &mut Data, t: f64, q: &[f64], d: &Mat<f64>, unbalanced_force: f64) -> FreeMotion {
    let l = &model.layout;
    run_kinematic_stages(model, data, t, q, &vec![0.0; l.nv]);
    let largest = (0..l.nv).map(|k| d[(k, 0)].abs()).fold(0.0, f64::max);
    let significant = |x: f64| x.abs() > 1e-3 * largest;
    let mut bodies = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        let vo = l.v_offset[b];
        let translation = Vec3::new(d[(vo, 0)], d[(vo + 1, 0)], d[(vo + 2, 0)]);
        let rotation = data.bodies[b].rotation * Vec3::new(d[(vo + 3, 0)], d[(vo + 4, 0)], d[(vo + 5, 0)]);
        let deforms = (0..l.modes[b]).any(|k| significant(d[(vo + 6 + k, 0)]));
        let unit = |v: Vec3| if significant(v.norm()) { (v / v.norm()).into() } else { [0.0; 3] };
        let motion = BodyMotion { body: body.name.clone(), translation: unit(translation), rotation: unit(rotation), deforms };
        if motion.translation != [0.0; 3] || motion.rotation != [0.0; 3] || deforms {
            bodies.push(motion);
        }
    }
    FreeMotion { bodies, unbalanced_force }
}
